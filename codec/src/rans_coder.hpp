#pragma once
// Static-model rANS (Duda's asymmetric numeral systems, range variant) over a 64-symbol
// alphabet: the entropy stage of the default profile (docs/codec.md).  Four states
// interleaved in one stream of 16-bit words, so four independent decodes overlap in the
// pipeline; a decode is two table loads, a multiply and an add.  Frequencies are static per
// packet (sent, or kept from the previous packet), so decoding never adapts a model.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "bit_stream.hpp"

namespace foldcast::codec {

constexpr int kRansAlphabet = 64;
constexpr int kRansProbabilityBits = 12;
constexpr std::uint32_t kRansTotal = std::uint32_t(1) << kRansProbabilityBits;
constexpr int kRansLanes = 4;

using SymbolCounts = std::array<std::uint64_t, kRansAlphabet>;

// A distribution as the file carries it: one 6-bit code per present symbol, a frequency
// rounded to two significant bits (docs/fca-format.md); absent symbols cost one bit.
struct QuantisedTable {
    std::array<std::uint8_t, kRansAlphabet> code{};  // 0: absent
};
QuantisedTable quantise_table(const SymbolCounts& counts);
void write_table(BitWriter& out, const QuantisedTable& table);
QuantisedTable read_table(BitReader& in);
constexpr int table_bits(const QuantisedTable& table) {
    int bits = 0;
    for (std::uint8_t c : table.code) bits += c ? 7 : 1;
    return bits;
}

// Frequencies summing to kRansTotal.
struct SymbolTable {
    std::array<std::uint16_t, kRansAlphabet> freq{}, start{};
};
// Every symbol equally likely: what each context holds before its first table arrives.
SymbolTable uniform_table();
// Deterministic normalisation of the quantised frequencies (at least one present symbol).
SymbolTable make_table(const QuantisedTable& table);

// What the decoder looks up: the symbol of each slot x mod kRansTotal (a byte, so a
// context's tables stay in the first-level cache and building one writes 4 KB), then that
// symbol's frequency and start.
struct DecodeTable {
    std::array<std::uint32_t, kRansAlphabet> freq_start;  // freq | start << 16
    std::array<std::uint8_t, kRansTotal + 16> symbol;     // the last 16: room for the fill's last block
};
void fill_decode_table(const SymbolTable& table, DecodeTable& out);
// Bits to code `counts` with `table`, or a negative value if a counted symbol is absent.
double coded_bits(const SymbolCounts& counts, const SymbolTable& table);

// Collects symbols in decoding order and encodes them backwards, as rANS requires.
class RansEncoder {
public:
    void push(const SymbolTable& table, int symbol, int lane) {
        symbols_.push_back({table.start[static_cast<std::size_t>(symbol)], table.freq[static_cast<std::size_t>(symbol)],
                            static_cast<std::uint8_t>(lane)});
    }
    std::string finish();  // the four initial states, then the words the decoder reads

private:
    struct Coded {
        std::uint16_t start, freq;
        std::uint8_t lane;
    };
    std::vector<Coded> symbols_;
};

// Decodes from a copy of the stream padded with zero words, so no single read needs a
// bounds check: whoever decodes must call overrun() at least every `words_between_checks`
// symbols (each reads at most one word), and a stream that ran into the padding was
// truncated or corrupt.  The copy lives in `storage`, which a decoder of many packets reuses.
class RansDecoder {
public:
    RansDecoder(std::string_view bytes, std::size_t words_between_checks, std::vector<std::uint8_t>& storage);
    bool overrun() const { return pos_ > end_; }
    std::array<std::uint32_t, kRansLanes> state{};

    int decode(const DecodeTable& table, std::uint32_t& x) { return decode(table, x, pos_); }

    // The same on a caller's copy of the read position: hot loops keep it in a register
    // (their byte stores could otherwise alias it), then hand it back with set_position.
    // Renormalisation `branch_free` (in arithmetic, so the compiler cannot make a branch of
    // it: whether a word is needed is as unpredictable as the symbol) costs no misprediction
    // but lengthens each state's dependency chain; `branch` leaves the chain short while
    // predicted.  Long runs of symbols are bound by throughput and want the first, short
    // ones (the states restart at every small frame) by latency and want the second.
    enum class Renormalise { branch_free, branch };
    template <Renormalise R = Renormalise::branch_free>
    static int decode(const DecodeTable& table, std::uint32_t& x, const std::uint8_t*& pos) {
        const std::uint32_t slot = x & (kRansTotal - 1), symbol = table.symbol[slot], e = table.freq_start[symbol];
        x = (e & 0xffffu) * (x >> kRansProbabilityBits) + slot - (e >> 16);
        if constexpr (R == Renormalise::branch_free) {
            const std::uint32_t word = std::uint32_t(pos[0]) | (std::uint32_t(pos[1]) << 8);
            const std::uint32_t need = x < kLow;
            x = (x << (16 * need)) | (word & (0u - need));
            pos += 2 * need;
        } else if (x < kLow) {
            x = (x << 16) | std::uint32_t(pos[0]) | (std::uint32_t(pos[1]) << 8);
            pos += 2;
        }
        return static_cast<int>(symbol);
    }
    const std::uint8_t* position() const { return pos_; }
    void set_position(const std::uint8_t* pos) { pos_ = pos; }

private:
    static constexpr std::uint32_t kLow = std::uint32_t(1) << 16;
    const std::uint8_t* pos_;
    const std::uint8_t* end_;
};

}  // namespace foldcast::codec
