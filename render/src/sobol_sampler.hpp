#pragma once
// Low-discrepancy samples for the path tracer: Owen-scrambled Sobol' points, padded per pair
// of dimensions (pbrt-v4's PaddedSobolSampler, with Burley's hash-based Owen scrambling,
// "Practical Hash-based Owen Scrambling", JCGT 2020).
//
// Sample i of a pixel is point shuffle(i) of a 2D Sobol' (0,2)-sequence whose bits are
// Owen-scrambled, with the shuffle and the scramble seeded by (seed, pixel, dimension).  So
// the first 2^k samples of every pixel form a stratified (0,k,2)-net in every pair of
// dimensions, successive pairs are decorrelated, and each value depends only on (seed,
// pixel, sample, dimension): the image is the same whatever thread renders which pixel.
#include <Eigen/Core>
#include <cstdint>

#include "random_stream.hpp"

namespace foldcast::render {

constexpr std::uint32_t reverse_bits(std::uint32_t x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
    return (x >> 16) | (x << 16);
}

// Laine and Karras' hash: a random permutation of x that only lets each bit depend on the
// bits below it; on bit-reversed values that is a nested uniform (Owen) scramble.
inline std::uint32_t laine_karras_permutation(std::uint32_t x, std::uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

// Owen scrambling of a 32-bit fixed-point value in [0, 1).
inline std::uint32_t owen_scramble(std::uint32_t x, std::uint32_t seed) {
    return reverse_bits(laine_karras_permutation(reverse_bits(x), seed));
}

// The first two dimensions of Sobol's sequence as 32-bit fixed point: van der Corput and
// the (0,2)-sequence's second dimension.
inline std::uint32_t sobol_dim0(std::uint32_t index) { return reverse_bits(index); }
// Bit by bit: the generator matrix's column v_b (v_0 = 2^31, v_(b+1) = v_b ^ (v_b >> 1)) for
// each set bit b of the index.
constexpr std::uint32_t sobol_dim1_bitwise(std::uint32_t index) {
    std::uint32_t v = 1u << 31, x = 0;
    for (; index != 0; index >>= 1, v ^= v >> 1)
        if (index & 1u) x ^= v;
    return x;
}

namespace detail {
// The same XOR sums a byte of the index at a time: the scrambled indices the sampler feeds in
// use all 32 bits, and 32 data-dependent branches per value cost more than four look-ups.
// `reversed`: the same sums with every column's bits reversed, i.e. reverse_bits of the value
// (reversal distributes over XOR), for the Owen scramble that reverses it anyway.
struct SobolDim1Tables {
    std::uint32_t byte[4][256] = {};
    std::uint32_t reversed[4][256] = {};
    constexpr SobolDim1Tables() {
        std::uint32_t column[32] = {};
        std::uint32_t v = 1u << 31;
        for (int b = 0; b < 32; ++b, v ^= v >> 1) column[b] = v;
        for (int k = 0; k < 4; ++k)
            for (int value = 0; value < 256; ++value) {
                std::uint32_t x = 0;
                for (int b = 0; b < 8; ++b)
                    if (value & (1 << b)) x ^= column[8 * k + b];
                byte[k][value] = x;
                reversed[k][value] = reverse_bits(x);
            }
    }
};
inline constexpr SobolDim1Tables kSobolDim1Tables{};

inline std::uint32_t sobol_dim1_from(const std::uint32_t (&t)[4][256], std::uint32_t index) {
    return t[0][index & 0xffu] ^ t[1][(index >> 8) & 0xffu] ^ t[2][(index >> 16) & 0xffu] ^ t[3][index >> 24];
}
}  // namespace detail

inline std::uint32_t sobol_dim1(std::uint32_t index) {
    return detail::sobol_dim1_from(detail::kSobolDim1Tables.byte, index);
}
// reverse_bits(sobol_dim1(index)) by the reversed tables.
inline std::uint32_t sobol_dim1_reversed(std::uint32_t index) {
    return detail::sobol_dim1_from(detail::kSobolDim1Tables.reversed, index);
}

inline float to_unit_float(std::uint32_t x) { return static_cast<float>(x >> 8) * 0x1.0p-24f; }

class PixelSampler {
public:
    PixelSampler(std::uint64_t seed, std::uint64_t pixel, std::uint32_t sample)
        : key_(mix64(mix64(seed ^ 0x2545f4914f6cdd1dULL) + pixel)), reversed_sample_(reverse_bits(sample)) {}

    // The next dimension in [0, 1).  owen_scramble(sobol_dim0(i), s) is written out as
    // reverse_bits(laine_karras_permutation(i, s)): sobol_dim0 reverses the bits that the
    // scramble would reverse back (the same bits, two reversals fewer).  The shuffled index
    // owen_scramble(sample, s) starts from the sample's reversal, kept from the constructor.
    float get1d() {
        const std::uint64_t h = next_hash();
        const std::uint32_t i = shuffled_index(static_cast<std::uint32_t>(h));
        return to_unit_float(reverse_bits(laine_karras_permutation(i, static_cast<std::uint32_t>(h >> 32))));
    }
    // The next two dimensions in [0, 1)^2, stratified together.  The second is
    // owen_scramble(sobol_dim1(i), s), its first reversal by the reversed tables.
    Eigen::Vector2f get2d() {
        const std::uint64_t h = next_hash();
        const std::uint64_t h2 = mix64(h);
        const std::uint32_t i = shuffled_index(static_cast<std::uint32_t>(h));
        return {to_unit_float(reverse_bits(laine_karras_permutation(i, static_cast<std::uint32_t>(h >> 32)))),
                to_unit_float(
                    reverse_bits(laine_karras_permutation(sobol_dim1_reversed(i), static_cast<std::uint32_t>(h2))))};
    }

    // Passes over the next two dimensions (a pair whose values would go unused), so that
    // the ones after keep their numbers.
    void skip2d() { ++dimension_; }

    // Sample k of n that this sample splits into, on dimensions of their own: the n samples of
    // every sample of the pixel are one padded Sobol' sequence of n times as many points, so
    // the pixel's 16 n points are stratified together (a (0,2)-net in each pair when n and the
    // sample count are powers of two).
    PixelSampler split(std::uint32_t k, std::uint32_t n) const {
        PixelSampler s(*this);
        s.key_ = mix64(key_ ^ 0x5851f42d4c957f2dULL);
        s.reversed_sample_ = reverse_bits(reverse_bits(reversed_sample_) * n + k);
        s.dimension_ = 0;
        return s;
    }

private:
    std::uint64_t next_hash() { return mix64(key_ + 0x9e3779b97f4a7c15ULL * ++dimension_); }
    // owen_scramble(sample, seed).
    std::uint32_t shuffled_index(std::uint32_t seed) const {
        return reverse_bits(laine_karras_permutation(reversed_sample_, seed));
    }

    std::uint64_t key_;
    std::uint32_t reversed_sample_;
    std::uint32_t dimension_ = 0;
};

}  // namespace foldcast::render
