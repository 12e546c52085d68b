#pragma once
// Quantised coefficients -> Huffman symbols, the way baseline JPEG codes AC coefficients:
// symbol = (zero run 0..15) * 32 + category, category = bit length of |q| (1..31) followed
// by `category` raw bits; (0, 0) ends a block of zeros, (15, 0) stands for 16 zeros.
// Thresholding leaves long zero runs, which this represents cheaply.
#include <cstdint>
#include <span>
#include <vector>

#include "huffman.hpp"

namespace foldcast::codec {

constexpr std::size_t kRunLengthAlphabet = 16 * 32;
constexpr std::int32_t kMaxCodedMagnitude = (1 << 30) - 1;

// Adds the symbols `values` will produce to `counts` (size kRunLengthAlphabet).
void count_run_length_symbols(std::span<const std::int32_t> values, std::vector<std::uint64_t>& counts);
void encode_run_length(std::span<const std::int32_t> values, const HuffmanTable& table, BitWriter& out);
// Fills `values` exactly; throws InputError via `context` on malformed data.
void decode_run_length(BitReader& in, const HuffmanTable& table, std::span<std::int32_t> values,
                       const ByteReader& context);

}  // namespace foldcast::codec
