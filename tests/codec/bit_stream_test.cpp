// Bit packing (codec/src/bit_stream.hpp): what BitWriter writes, BitReader and the padded
// reader of raw fields read back, from any bit position; reading past the end is noticed
// and never leaves the buffer.
#include <gtest/gtest.h>

#include <random>

#include "bit_stream.hpp"

namespace foldcast::codec {
namespace {

TEST(BitStream, PaddedReaderReadsWhatWasWrittenFromAnyPosition) {
    std::mt19937 rng(5);
    std::vector<std::pair<std::uint32_t, int>> fields;
    BitWriter w;
    for (int i = 0; i < 5000; ++i) {
        const int count = 1 + static_cast<int>(rng() % 32);
        const std::uint32_t value =
            count == 32 ? static_cast<std::uint32_t>(rng()) : static_cast<std::uint32_t>(rng()) & ((1u << count) - 1u);
        fields.push_back({value, count});
        w.put(value, count);
    }
    const std::string bytes = w.finish();
    // A plain reader consumes a prefix; the padded one continues where it stopped.
    for (std::size_t split : {std::size_t(0), std::size_t(1), std::size_t(777), fields.size()}) {
        BitReader plain(bytes);
        for (std::size_t i = 0; i < split; ++i) ASSERT_EQ(plain.get(fields[i].second), fields[i].first);
        std::vector<std::uint8_t> storage;
        PaddedBitReader padded(plain.bytes(), plain.bit_position(), storage);
        for (std::size_t i = split; i < fields.size(); ++i)
            ASSERT_EQ(padded.get(fields[i].second), fields[i].first) << "field " << i;
        EXPECT_FALSE(padded.overrun());
    }
}

TEST(BitStream, PeekingPastTheEndIsNoOverrunButConsumingIs) {
    BitReader r(std::string_view("\xa5", 1));
    EXPECT_EQ(r.peek(12), 0xa50u);
    EXPECT_FALSE(r.overrun());
    r.skip(8);
    EXPECT_FALSE(r.overrun());
    EXPECT_EQ(r.bit_position(), 8u);
    EXPECT_EQ(r.peek(7), 0u);
    EXPECT_FALSE(r.overrun());
    EXPECT_EQ(r.get(1), 0u);
    EXPECT_TRUE(r.overrun());
}

TEST(BitStream, PaddedReaderPastTheEndGivesZerosAndSaysSo) {
    const std::string bytes = "\xff\xff";
    std::vector<std::uint8_t> storage;
    PaddedBitReader r(bytes, 12, storage);
    EXPECT_EQ(r.get(4), 0xfu);
    EXPECT_FALSE(r.overrun());
    EXPECT_EQ(r.get(1), 0u);
    EXPECT_TRUE(r.overrun());
    for (int i = 0; i < 1000; ++i) EXPECT_EQ(r.get(32), 0u);  // far beyond: still inside the padding
}

}  // namespace
}  // namespace foldcast::codec
