#include "rans_coder.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace foldcast::codec {
namespace {
constexpr int kCodeBits = 6;
constexpr std::uint32_t kLow = std::uint32_t(1) << 16;

// Code c: 1..7 are the values themselves; from 8 on, a leading-two-bits float
// (4..7) << e, e >= 1, decoded to the middle of its interval.
constexpr std::uint32_t code_value(int c) {
    if (c < 8) return static_cast<std::uint32_t>(c);
    const int e = 1 + (c - 8) / 4;
    const std::uint32_t m = 4u + static_cast<std::uint32_t>((c - 8) % 4);
    return (m << e) + (std::uint32_t(1) << (e - 1));
}
constexpr auto kCodeValues = [] {
    std::array<std::uint32_t, std::size_t(1) << kCodeBits> values{};
    for (std::size_t c = 0; c < values.size(); ++c) values[c] = code_value(static_cast<int>(c));
    return values;
}();

std::uint8_t value_code(std::uint32_t v) {
    if (v < 8) return static_cast<std::uint8_t>(v);
    const int e = std::bit_width(v) - 3;
    return static_cast<std::uint8_t>(8 + (e - 1) * 4 + static_cast<int>((v >> e) - 4));
}

void finish_table(SymbolTable& t) {
    std::uint32_t start = 0;
    for (std::size_t s = 0; s < t.freq.size(); ++s) {
        t.start[s] = static_cast<std::uint16_t>(start);
        start += t.freq[s];
    }
}
}  // namespace

QuantisedTable quantise_table(const SymbolCounts& counts) {
    std::uint64_t total = 0;
    for (std::uint64_t c : counts) total += c;
    QuantisedTable q;
    if (total == 0) return q;
    for (std::size_t s = 0; s < counts.size(); ++s) {
        if (counts[s] == 0) continue;
        const std::uint64_t scaled = (counts[s] * kRansTotal + total / 2) / total;
        q.code[s] = value_code(static_cast<std::uint32_t>(std::clamp<std::uint64_t>(scaled, 1, kRansTotal)));
    }
    return q;
}

void write_table(BitWriter& out, const QuantisedTable& table) {
    for (std::uint8_t c : table.code) {
        out.put(c != 0, 1);
        if (c != 0) out.put(c, kCodeBits);
    }
}

QuantisedTable read_table(BitReader& in) {
    // An absent symbol is a single zero bit, so a run of them is skipped at once by counting
    // leading zeros; each present symbol is then a one and its 6-bit code (0 reads as 1).
    // The reader and codes are locals while reading, so the byte stores cannot alias the
    // reader's state.
    BitReader bits = in;
    QuantisedTable q;
    for (std::size_t s = 0; s < kRansAlphabet;) {
        const auto absent =
            std::min<std::size_t>(static_cast<std::size_t>(std::countl_zero(bits.peek(32))), kRansAlphabet - s);
        bits.skip(static_cast<int>(absent));
        s += absent;
        if (s == kRansAlphabet || absent == 32) continue;  // done, or 32 absent and more to look at
        const std::uint32_t code = bits.get(1 + kCodeBits) & ((1u << kCodeBits) - 1);
        q.code[s++] = static_cast<std::uint8_t>(std::max<std::uint32_t>(1, code));
    }
    in = bits;
    return q;
}

SymbolTable uniform_table() {
    SymbolTable t;
    t.freq.fill(static_cast<std::uint16_t>(kRansTotal / kRansAlphabet));
    finish_table(t);
    return t;
}

SymbolTable make_table(const QuantisedTable& table) {
    // Code values are below 2^17: their sum, and each times kRansTotal, fit 32 bits.
    std::array<std::uint8_t, kRansAlphabet> present;  // the present symbols, ascending
    std::size_t count = 0;
    std::uint32_t total = 0;
    for (std::size_t s = 0; s < kRansAlphabet; ++s) {
        present[count] = static_cast<std::uint8_t>(s);
        count += table.code[s] != 0;
        total += kCodeValues[table.code[s]];
    }
    if (total == 0) return uniform_table();
    SymbolTable t;
    std::int64_t left = kRansTotal;
    std::size_t big = present[0];  // the first most frequent symbol
    for (std::size_t i = 0; i < count; ++i) {
        const std::size_t s = present[i];
        t.freq[s] =
            static_cast<std::uint16_t>(std::max<std::uint32_t>(1, kCodeValues[table.code[s]] * kRansTotal / total));
        left -= t.freq[s];
        if (t.freq[s] > t.freq[big]) big = s;
    }
    // Rounding leaves a remainder of either sign: the most frequent symbol absorbs it, where
    // it costs least.  While the sum is too large some frequency exceeds 1 (64 ones sum to
    // less than kRansTotal), so every round makes progress.
    while (left != 0) {
        const std::int64_t change = left > 0 ? left : std::max<std::int64_t>(left, 1 - std::int64_t(t.freq[big]));
        t.freq[big] = static_cast<std::uint16_t>(std::int64_t(t.freq[big]) + change);
        left -= change;
        if (left != 0) big = static_cast<std::size_t>(std::max_element(t.freq.begin(), t.freq.end()) - t.freq.begin());
    }
    finish_table(t);
    return t;
}

void fill_decode_table(const SymbolTable& table, DecodeTable& out) {
    for (std::size_t s = 0; s < kRansAlphabet; ++s)
        out.freq_start[s] = table.freq[s] | std::uint32_t(table.start[s]) << 16;
    // Each present symbol's slots in whole 16-byte blocks: a block running past them is
    // overwritten by the next symbol's (ranges ascend with the symbol), the last one's by
    // nothing.  Most symbols need one block, written without a loop.
    for (std::size_t s = 0; s < kRansAlphabet; ++s) {
        const std::uint32_t start = table.start[s], end = start + table.freq[s];
        if (start == end) continue;
        std::uint8_t block[16];
        std::memset(block, static_cast<int>(s), sizeof block);
        std::memcpy(out.symbol.data() + start, block, sizeof block);
        for (std::uint32_t k = start + 16; k < end; k += 16) std::memcpy(out.symbol.data() + k, block, sizeof block);
    }
}

double coded_bits(const SymbolCounts& counts, const SymbolTable& table) {
    double bits = 0.0;
    for (std::size_t s = 0; s < counts.size(); ++s) {
        if (counts[s] == 0) continue;
        if (table.freq[s] == 0) return -1.0;
        bits += double(counts[s]) * (kRansProbabilityBits - std::log2(double(table.freq[s])));
    }
    return bits;
}

std::string RansEncoder::finish() {
    std::array<std::uint32_t, kRansLanes> x;
    x.fill(kLow);
    std::vector<std::uint16_t> words;  // in emission order: the reverse of reading order
    words.reserve(symbols_.size() / 2 + 2 * kRansLanes);
    for (std::size_t i = symbols_.size(); i-- > 0;) {
        const Coded& c = symbols_[i];
        std::uint32_t& s = x[c.lane];
        // Keep the state in [kLow, 2^32) after coding: emit 16 bits first if it would overflow.
        const std::uint64_t limit =
            std::uint64_t((kLow >> kRansProbabilityBits) << 16) * c.freq;  // 2^32 for freq = kRansTotal
        if (s >= limit) {
            words.push_back(static_cast<std::uint16_t>(s & 0xffffu));
            s >>= 16;
        }
        s = ((s / c.freq) << kRansProbabilityBits) + (s % c.freq) + c.start;
    }
    for (int lane = kRansLanes - 1; lane >= 0; --lane) {
        words.push_back(static_cast<std::uint16_t>(x[static_cast<std::size_t>(lane)] >> 16));
        words.push_back(static_cast<std::uint16_t>(x[static_cast<std::size_t>(lane)] & 0xffffu));
    }
    std::string out(2 * words.size(), '\0');
    for (std::size_t i = 0; i < words.size(); ++i) {
        const std::uint16_t w = words[words.size() - 1 - i];
        out[2 * i] = static_cast<char>(w & 0xffu);
        out[2 * i + 1] = static_cast<char>(w >> 8);
    }
    symbols_.clear();
    return out;
}

RansDecoder::RansDecoder(std::string_view bytes, std::size_t words_between_checks, std::vector<std::uint8_t>& storage) {
    storage.assign(bytes.begin(), bytes.end());
    storage.resize(bytes.size() + 2 * (words_between_checks + 2 * kRansLanes), 0);
    pos_ = storage.data();
    end_ = storage.data() + bytes.size();
    for (auto& x : state) {
        x = std::uint32_t(pos_[0]) | std::uint32_t(pos_[1]) << 8 | std::uint32_t(pos_[2]) << 16 |
            std::uint32_t(pos_[3]) << 24;
        pos_ += 4;
    }
}

}  // namespace foldcast::codec
