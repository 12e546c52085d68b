#include <gtest/gtest.h>

#include <random>

#include "huffman.hpp"
#include "run_length_coder.hpp"

namespace foldcast::codec {
namespace {

TEST(Huffman, CanonicalCodeRoundTripsAndBeatsFixedLength) {
    std::mt19937 rng(3);
    std::geometric_distribution<int> d(0.3);
    std::vector<std::uint32_t> symbols(5000);
    std::vector<std::uint64_t> counts(64, 0);
    for (auto& s : symbols) {
        s = static_cast<std::uint32_t>(std::min(d(rng), 63));
        ++counts[s];
    }
    const HuffmanTable table = HuffmanTable::from_counts(counts);
    ByteWriter stored;
    table.write(stored);
    ByteReader in(stored.bytes(), "table");
    const HuffmanTable read = HuffmanTable::read(in, 64);
    EXPECT_EQ(read.lengths(), table.lengths());
    BitWriter bits;
    for (auto s : symbols) table.encode(bits, s);
    const std::string packed = bits.finish();
    EXPECT_LT(packed.size() * 8, symbols.size() * 6);  // fewer bits than 6-bit fixed codes
    BitReader br(packed);
    ByteReader ctx("", "test");
    for (auto s : symbols) ASSERT_EQ(read.decode(br, ctx), s);
}

TEST(Huffman, LengthLimitHolds) {
    std::vector<std::uint64_t> counts(40);
    for (std::size_t i = 0; i < counts.size(); ++i) counts[i] = std::uint64_t(1) << i;  // skewed: depth 39 unlimited
    const HuffmanTable table = HuffmanTable::from_counts(counts, 12);
    for (auto l : table.lengths()) EXPECT_LE(l, 12);
}

TEST(Huffman, OverSubscribedTableIsRejected) {
    ByteWriter w;
    w.put_varint(3);
    for (std::uint8_t s = 0; s < 3; ++s) {
        w.put_varint(s);
        w.put<std::uint8_t>(1);  // three codes of length 1: Kraft sum 1.5
    }
    ByteReader in(w.bytes(), "table");
    EXPECT_THROW(HuffmanTable::read(in, 8), InputError);
}

TEST(RunLength, RoundTripsSparseValuesWithLongZeroRuns) {
    std::vector<std::int32_t> values(2000, 0);
    values[0] = 5;
    values[17] = -1;
    values[100] = 1 << 20;
    values[101] = -(1 << 29);
    values[1500] = 3;
    std::vector<std::uint64_t> counts(kRunLengthAlphabet, 0);
    count_run_length_symbols(values, counts);
    const HuffmanTable table = HuffmanTable::from_counts(counts);
    BitWriter bits;
    encode_run_length(values, table, bits);
    const std::string packed = bits.finish();
    EXPECT_LT(packed.size(), 100u);
    std::vector<std::int32_t> back(values.size(), 7);
    BitReader br(packed);
    ByteReader ctx("", "test");
    decode_run_length(br, table, back, ctx);
    EXPECT_EQ(back, values);
}

}  // namespace
}  // namespace foldcast::codec
