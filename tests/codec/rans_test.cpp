// The default profile's entropy stage (codec/src/rans_coder.*, bit_stream.hpp): tables
// normalise exactly, symbols round-trip through four interleaved states, the coded size
// follows the model, and a cut stream is caught by the padding check.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bit_stream.hpp"
#include "rans_coder.hpp"

namespace foldcast::codec {
namespace {

SymbolCounts skewed_counts(std::mt19937& rng, int present) {
    SymbolCounts counts{};
    std::uniform_int_distribution<int> symbol(0, kRansAlphabet - 1);
    for (int i = 0; i < present; ++i)
        counts[static_cast<std::size_t>(symbol(rng))] += 1 + (rng() % 5000) * (rng() % 50);
    return counts;
}

std::vector<int> draw(std::mt19937& rng, const SymbolCounts& counts, std::size_t n) {
    std::vector<double> weights(counts.begin(), counts.end());
    std::discrete_distribution<int> pick(weights.begin(), weights.end());
    std::vector<int> out(n);
    for (auto& s : out) s = pick(rng);
    return out;
}

TEST(Rans, TablesSumToTheTotalAndKeepEveryPresentSymbol) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 200; ++trial) {
        const SymbolCounts counts = skewed_counts(rng, 1 + trial % kRansAlphabet);
        const SymbolTable t = make_table(quantise_table(counts));
        DecodeTable d;
        fill_decode_table(t, d);
        std::uint32_t sum = 0;
        for (std::size_t s = 0; s < counts.size(); ++s) {
            EXPECT_EQ(counts[s] > 0, t.freq[s] > 0) << "symbol " << s;
            sum += t.freq[s];
        }
        ASSERT_EQ(sum, kRansTotal);
        for (std::uint32_t slot = 0; slot < kRansTotal; ++slot) {  // every slot names the symbol whose range holds it
            const std::uint32_t s = d.symbol[slot];
            ASSERT_LT(s, std::uint32_t(kRansAlphabet));
            ASSERT_GE(slot, t.start[s]);
            ASSERT_LT(slot, t.start[s] + t.freq[s]);
        }
        for (std::size_t s = 0; s < counts.size(); ++s)
            ASSERT_EQ(d.freq_start[s], t.freq[s] | std::uint32_t(t.start[s]) << 16);
    }
}

TEST(Rans, TablesSurviveTheirBitPacking) {
    std::mt19937 rng(11);
    BitWriter w;
    std::vector<QuantisedTable> tables;
    for (int i = 0; i < 20; ++i) {
        tables.push_back(quantise_table(skewed_counts(rng, 1 + 3 * i)));
        write_table(w, tables.back());
    }
    const std::string bytes = w.finish();
    BitReader r(bytes);
    for (const auto& t : tables) EXPECT_EQ(read_table(r).code, t.code);
    EXPECT_FALSE(r.overrun());
    r.get(16);
    EXPECT_TRUE(r.overrun());
}

TEST(Rans, TableEndingAtTheLastBitReadsWithoutOverrun) {
    // Absent symbols last: their one-bit flags end the bytes exactly (8 of 64 present, each
    // 7 bits, and 56 flags: 112 bits), though reading looks seven bits ahead.
    QuantisedTable table;
    for (std::size_t s = 0; s < 8; ++s) table.code[s] = static_cast<std::uint8_t>(7 * s + 1);
    BitWriter w;
    write_table(w, table);
    const std::string bytes = w.finish();
    ASSERT_EQ(bytes.size(), 14u);
    BitReader r(bytes);
    EXPECT_EQ(read_table(r).code, table.code);
    EXPECT_FALSE(r.overrun());
    EXPECT_EQ(r.bit_position(), 112u);
}

TEST(Rans, InterleavedStatesRoundTripAndCostWhatTheModelSays) {
    std::mt19937 rng(3);
    // Several tables used in turn, one with a single symbol (frequency = the whole total).
    std::vector<SymbolCounts> counts = {skewed_counts(rng, 40), skewed_counts(rng, 3), SymbolCounts{}};
    counts[2][17] = 1;
    std::vector<SymbolTable> tables;
    for (const auto& c : counts) tables.push_back(make_table(quantise_table(c)));
    std::vector<DecodeTable> decode_tables(tables.size());
    for (std::size_t k = 0; k < tables.size(); ++k) fill_decode_table(tables[k], decode_tables[k]);
    constexpr std::size_t n = 100003;
    std::vector<std::vector<int>> streams;
    for (const auto& c : counts) streams.push_back(draw(rng, c, n));
    RansEncoder enc;
    double model_bits = 0.0;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t k = 0; k < tables.size(); ++k) {
            const int s = streams[k][i];
            enc.push(tables[k], s, static_cast<int>((3 * i + k) % kRansLanes));
            model_bits += kRansProbabilityBits - std::log2(double(tables[k].freq[static_cast<std::size_t>(s)]));
        }
    const std::string bytes = enc.finish();
    EXPECT_LT(8.0 * double(bytes.size()), model_bits + 200.0);  // within the four states' flush
    std::vector<std::uint8_t> storage;
    RansDecoder dec(bytes, 3 * n, storage);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t k = 0; k < tables.size(); ++k)
            ASSERT_EQ(dec.decode(decode_tables[k], dec.state[(3 * i + k) % kRansLanes]), streams[k][i]) << i;
    EXPECT_FALSE(dec.overrun());

    // Both renormalisations read the same words: the same symbols, states and position.
    std::vector<std::uint8_t> storage_a, storage_b;
    RansDecoder free_of_branches(bytes, 3 * n, storage_a), branching(bytes, 3 * n, storage_b);
    const std::uint8_t *p = free_of_branches.position(), *q = branching.position();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t k = 0; k < tables.size(); ++k) {
            const std::size_t lane = (3 * i + k) % kRansLanes;
            const int a = RansDecoder::decode<RansDecoder::Renormalise::branch_free>(decode_tables[k],
                                                                                     free_of_branches.state[lane], p);
            const int b =
                RansDecoder::decode<RansDecoder::Renormalise::branch>(decode_tables[k], branching.state[lane], q);
            ASSERT_EQ(a, streams[k][i]) << i;
            ASSERT_EQ(b, streams[k][i]) << i;
            ASSERT_EQ(free_of_branches.state[lane], branching.state[lane]) << i;
            ASSERT_EQ(p - storage_a.data(), q - storage_b.data()) << i;
        }
}

TEST(Rans, ACutStreamRunsIntoThePadding) {
    std::mt19937 rng(5);
    const SymbolCounts counts = skewed_counts(rng, 64);
    const SymbolTable table = make_table(quantise_table(counts));
    DecodeTable decode_table;
    fill_decode_table(table, decode_table);
    const std::vector<int> symbols = draw(rng, counts, 5000);
    RansEncoder enc;
    for (std::size_t i = 0; i < symbols.size(); ++i) enc.push(table, symbols[i], static_cast<int>(i % kRansLanes));
    const std::string bytes = enc.finish();
    std::vector<std::uint8_t> storage;
    RansDecoder dec(std::string_view(bytes).substr(0, bytes.size() / 2), symbols.size(), storage);
    for (std::size_t i = 0; i < symbols.size(); ++i) dec.decode(decode_table, dec.state[i % kRansLanes]);
    EXPECT_TRUE(dec.overrun());
}

}  // namespace
}  // namespace foldcast::codec
