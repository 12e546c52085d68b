#pragma once
// Deterministic per-pixel random numbers: each value is a hash of (seed, pixel, sample,
// dimension), so a pixel's samples never depend on which thread or in what order it was
// rendered.  The mixer is SplitMix64's finaliser (a bijection with full avalanche).
#include <cstdint>

namespace foldcast::render {

inline std::uint64_t mix64(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

class RandomStream {
public:
    RandomStream(std::uint64_t seed, std::uint64_t pixel, std::uint32_t sample)
        : key_(mix64(mix64(seed ^ 0x9e3779b97f4a7c15ULL) + pixel) ^
               mix64(static_cast<std::uint64_t>(sample) + 0x632be59bd9b4e019ULL)) {}

    // The next dimension in [0, 1).
    float next() { return uniform(dimension_++); }
    std::uint32_t dimension() const { return dimension_; }
    float uniform(std::uint32_t dimension) const {
        const std::uint64_t bits = mix64(key_ + 0x9e3779b97f4a7c15ULL * (dimension + 1));
        return static_cast<float>(bits >> 40) * 0x1.0p-24f;  // 24 bits: exactly representable
    }

private:
    std::uint64_t key_;
    std::uint32_t dimension_ = 0;
};

}  // namespace foldcast::render
