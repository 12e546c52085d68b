// The pixel sampler's Owen-scrambled Sobol' points: in every pair of dimensions the first 2^k
// samples of a pixel are a (0,k,2)-net (each elementary box of area 2^-k holds exactly one),
// values lie in [0,1), and they depend only on (seed, pixel, sample, dimension).
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

#include "sobol_sampler.hpp"

namespace foldcast::render {
namespace {

// Draws `dims` 2D pairs for samples 0..n-1 of one pixel.
std::vector<std::vector<Eigen::Vector2f>> draw(std::uint64_t seed, std::uint64_t pixel, int n, int dims) {
    std::vector<std::vector<Eigen::Vector2f>> out(dims);
    for (int s = 0; s < n; ++s) {
        PixelSampler sampler(seed, pixel, static_cast<std::uint32_t>(s));
        for (int d = 0; d < dims; ++d) {
            if (d % 2 == 1) (void)sampler.get1d();  // pairs interleaved with 1D draws, as paths do
            out[d].push_back(sampler.get2d());
        }
    }
    return out;
}

// Every elementary box 2^-a x 2^-(k-a) holds exactly one of the 2^k points.
bool is_net(const std::vector<Eigen::Vector2f>& pts, int k) {
    for (int a = 0; a <= k; ++a) {
        std::set<std::pair<int, int>> boxes;
        for (const auto& p : pts) {
            if (!(p.x() >= 0.0f && p.x() < 1.0f && p.y() >= 0.0f && p.y() < 1.0f)) return false;
            boxes.insert({static_cast<int>(std::ldexp(p.x(), a)), static_cast<int>(std::ldexp(p.y(), k - a))});
        }
        if (boxes.size() != pts.size()) return false;
    }
    return true;
}

TEST(PixelSampler, FirstPowerOfTwoSamplesAreStratifiedInEveryPair) {
    for (const std::uint64_t pixel : {0ull, 1ull, 777ull, 123456ull})
        for (const int k : {2, 4, 6, 8}) {
            const auto dims = draw(3, pixel, 1 << k, 6);
            for (std::size_t d = 0; d < dims.size(); ++d)
                EXPECT_TRUE(is_net(dims[d], k)) << "pixel " << pixel << ", 2^" << k << " samples, pair " << d;
        }
}

TEST(PixelSampler, SplitSamplesAreStratifiedTogether) {
    // The path integrator splits a sample into n at the rod's first hit: the pixel's 16 x 4
    // split samples are one net of 64 in every pair, and a split's values are its own.
    for (const std::uint64_t pixel : {0ull, 777ull, 123456ull}) {
        std::vector<Eigen::Vector2f> first, second;
        for (std::uint32_t s = 0; s < 16; ++s) {
            const PixelSampler sampler(3, pixel, s);
            for (std::uint32_t k = 0; k < 4; ++k) {
                PixelSampler split = sampler.split(k, 4);
                first.push_back(split.get2d());
                (void)split.get1d();
                second.push_back(split.get2d());
            }
        }
        EXPECT_TRUE(is_net(first, 6)) << "pixel " << pixel;
        EXPECT_TRUE(is_net(second, 6)) << "pixel " << pixel;
        PixelSampler plain(3, pixel, 0), split = PixelSampler(3, pixel, 0).split(0, 1);
        EXPECT_NE(plain.get2d(), split.get2d());
    }
}

TEST(PixelSampler, HashedPointsWouldNotPass) {
    // The check above can fail: 64 independent uniform points are almost never a (0,6,2)-net.
    std::vector<Eigen::Vector2f> pts;
    RandomStream rng(5, 6, 7);
    for (int i = 0; i < 64; ++i) pts.emplace_back(rng.next(), rng.next());
    EXPECT_FALSE(is_net(pts, 6));
}

TEST(PixelSampler, PairsAndPixelsAreDecorrelated) {
    // Different pixels and different dimension pairs must not repeat one pattern.
    const auto a = draw(3, 10, 16, 2), b = draw(3, 11, 16, 2);
    int same_pixel = 0, same_pair = 0;
    for (int i = 0; i < 16; ++i) {
        same_pixel += a[0][i] == b[0][i];
        same_pair += a[0][i] == a[1][i];
    }
    EXPECT_LT(same_pixel, 2);
    EXPECT_LT(same_pair, 2);
}

TEST(PixelSampler, DependsOnlyOnSeedPixelSampleAndDimension) {
    PixelSampler a(9, 42, 5), b(9, 42, 5), c(10, 42, 5);
    for (int d = 0; d < 10; ++d) {
        const float x = a.get1d();
        EXPECT_EQ(x, b.get1d());
        EXPECT_NE(x, c.get1d());
    }
}

// get1d/get2d write the scramble of the first Sobol' dimension without the two bit reversals
// that cancel: the same bits as the textbook form, so images do not change.
TEST(PixelSampler, ShortFormOfTheFirstDimensionIsTheOwenScrambleOfIt) {
    std::uint32_t i = 1, seed = 12345;
    for (int k = 0; k < 100000; ++k) {
        i = i * 1664525u + 1013904223u, seed = seed * 22695477u + 1u;
        ASSERT_EQ(reverse_bits(laine_karras_permutation(i, seed)), owen_scramble(sobol_dim0(i), seed))
            << i << " " << seed;
    }
}

TEST(PixelSampler, SecondDimensionByBytesIsTheBitwiseSum) {
    std::uint32_t i = 7;
    for (int k = 0; k < 100000; ++k) {
        i = i * 1664525u + 1013904223u;
        ASSERT_EQ(sobol_dim1(i), sobol_dim1_bitwise(i)) << i;
    }
    for (std::uint32_t small = 0; small < 4096; ++small) ASSERT_EQ(sobol_dim1(small), sobol_dim1_bitwise(small));
    EXPECT_EQ(sobol_dim1(0xffffffffu), sobol_dim1_bitwise(0xffffffffu));
}

TEST(PixelSampler, ReversedSecondDimensionIsTheReversalOfIt) {
    std::uint32_t i = 11;
    for (int k = 0; k < 100000; ++k) {
        i = i * 1664525u + 1013904223u;
        ASSERT_EQ(sobol_dim1_reversed(i), reverse_bits(sobol_dim1_bitwise(i))) << i;
    }
}

}  // namespace
}  // namespace foldcast::render
