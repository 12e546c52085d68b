#pragma once
// Canonical, length-limited Huffman coding: the entropy stage of the `paper` profile.
// Code lengths are built from symbol counts (a heap-built Huffman tree, counts flattened
// until no code exceeds the limit), codes are assigned canonically (by length, then
// symbol), so only the lengths travel in the file.  Reading a table checks the Kraft sum,
// so a hostile table cannot describe an over-subscribed code.
#include <cstdint>
#include <string>
#include <vector>

#include "bit_stream.hpp"
#include "byte_io.hpp"

namespace foldcast::codec {

constexpr int kMaxHuffmanLength = 24;

class HuffmanTable {
public:
    // Lengths for each symbol (0 = never used).  At least one count must be non-zero.
    static HuffmanTable from_counts(const std::vector<std::uint64_t>& counts, int max_length = kMaxHuffmanLength);
    // Stored as: varint used-symbol count, then (varint symbol, u8 length) pairs.
    void write(ByteWriter& out) const;
    static HuffmanTable read(ByteReader& in, std::size_t alphabet_size);

    void encode(BitWriter& out, std::uint32_t symbol) const;
    // Throws InputError (via `in_what`) for a bit pattern that is no code.
    std::uint32_t decode(BitReader& in, const ByteReader& in_what) const;

    const std::vector<std::uint8_t>& lengths() const { return lengths_; }

private:
    void build_canonical();
    std::vector<std::uint8_t> lengths_;
    std::vector<std::uint32_t> codes_;
    // Canonical decoding tables indexed by length.
    std::vector<std::uint32_t> first_code_, first_index_, count_;
    std::vector<std::uint32_t> sorted_symbols_;
};

}  // namespace foldcast::codec
