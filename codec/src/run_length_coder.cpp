#include "run_length_coder.hpp"

#include <bit>
#include <cstdlib>
#include <stdexcept>

namespace foldcast::codec {
namespace {
constexpr std::uint32_t kEndOfBlock = 0;
constexpr std::uint32_t kSixteenZeros = 15 * 32;

int category(std::int32_t q) { return std::bit_width(static_cast<std::uint32_t>(std::abs(q))); }
std::uint32_t raw_bits(std::int32_t q, int cat) {
    // JPEG convention: negative values are stored as q + 2^cat - 1 (leading bit 0).
    return q > 0 ? static_cast<std::uint32_t>(q) : static_cast<std::uint32_t>(q + ((1 << cat) - 1));
}

template <typename Emit>
void to_symbols(std::span<const std::int32_t> values, Emit&& emit) {
    std::size_t run = 0;
    for (const std::int32_t q : values) {
        if (q == 0) {
            ++run;
            continue;
        }
        if (q > kMaxCodedMagnitude || q < -kMaxCodedMagnitude) throw std::logic_error("coefficient out of range");
        while (run >= 16) {
            emit(kSixteenZeros, 0, 0);
            run -= 16;
        }
        const int cat = category(q);
        emit(static_cast<std::uint32_t>(run * 32 + static_cast<std::size_t>(cat)), raw_bits(q, cat), cat);
        run = 0;
    }
    if (run > 0) emit(kEndOfBlock, 0, 0);
}
}  // namespace

void count_run_length_symbols(std::span<const std::int32_t> values, std::vector<std::uint64_t>& counts) {
    to_symbols(values, [&](std::uint32_t symbol, std::uint32_t, int) { ++counts[symbol]; });
}

void encode_run_length(std::span<const std::int32_t> values, const HuffmanTable& table, BitWriter& out) {
    to_symbols(values, [&](std::uint32_t symbol, std::uint32_t bits, int count) {
        table.encode(out, symbol);
        if (count > 0) out.put(bits, count);
    });
}

void decode_run_length(BitReader& in, const HuffmanTable& table, std::span<std::int32_t> values,
                       const ByteReader& context) {
    std::size_t i = 0;
    while (i < values.size()) {
        const std::uint32_t symbol = table.decode(in, context);
        if (symbol == kEndOfBlock) {
            while (i < values.size()) values[i++] = 0;
            break;
        }
        const std::size_t run = symbol / 32;
        const int cat = static_cast<int>(symbol % 32);
        if (cat == 0 && symbol != kSixteenZeros)
            context.fail("run-length symbol " + std::to_string(symbol) + " is undefined");
        const std::size_t zeros = cat == 0 ? 16 : run;
        if (zeros + (cat > 0 ? 1 : 0) > values.size() - i) context.fail("run-length data runs past its block");
        for (std::size_t k = 0; k < zeros; ++k) values[i++] = 0;
        if (cat > 0) {
            const std::uint32_t bits = in.get(cat);
            const bool negative = (bits >> (cat - 1)) == 0;
            values[i++] =
                negative ? static_cast<std::int32_t>(static_cast<std::int64_t>(bits) - ((std::int64_t(1) << cat) - 1))
                         : static_cast<std::int32_t>(bits);
        }
        if (in.overrun()) context.fail("Huffman data is truncated");
    }
}

}  // namespace foldcast::codec
