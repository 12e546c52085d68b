#include "spatial_weights.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace foldcast::codec {

SpatialWeights fit_spatial_weights(const std::vector<SpatialReference>& first,
                                   const std::vector<SpatialReference>& second, const std::int32_t* target,
                                   const std::int32_t* temporal) {
    using Vector = Eigen::Matrix<double, kSpatialTaps, 1>;
    using Matrix = Eigen::Matrix<double, kSpatialTaps, kSpatialTaps>;
    Matrix normal = Matrix::Zero();
    Vector right = Vector::Zero();
    auto residual = [&](std::int32_t u, std::size_t c) {
        const std::size_t k = 3 * static_cast<std::size_t>(u) + c;
        return double(target[k]) - double(temporal[k]);
    };
    for (std::size_t v = 0; v < first.size(); ++v) {
        const SpatialReference &s = first[v], &s2 = second[v];
        if (s.c < 0 || s2.c < 0) continue;
        for (std::size_t c = 0; c < 3; ++c) {
            Vector x;
            x << residual(s.a, c), residual(s.b, c), residual(s.c, c), residual(s2.a, c), residual(s2.b, c),
                residual(s2.c, c);
            normal.selfadjointView<Eigen::Lower>().rankUpdate(x);
            right += x * residual(static_cast<std::int32_t>(v), c);
        }
    }
    normal = normal.selfadjointView<Eigen::Lower>();
    // A little ridge: taps that coincide on this mesh (a second parallelogram sharing an
    // edge's corner) make the system singular.
    const double trace = normal.trace();
    if (!(trace > 0.0)) return kParallelogramWeights;
    normal += 1e-6 * trace / kSpatialTaps * Matrix::Identity();
    const Vector w = normal.ldlt().solve(right);
    SpatialWeights out{};
    constexpr double kLow = -(1 << (kWeightBits - 1)), kHigh = (1 << (kWeightBits - 1)) - 1;
    for (int i = 0; i < kSpatialTaps; ++i) {
        const double scaled = std::ldexp(w[i], kWeightShift);
        out[static_cast<std::size_t>(i)] =
            std::isfinite(scaled) ? static_cast<std::int32_t>(std::lround(std::clamp(scaled, kLow, kHigh))) : 0;
    }
    return out;
}

void write_spatial_weights(BitWriter& out, SpatialMode spatial, const SpatialWeights& weights) {
    if (spatial == SpatialMode::none) return;
    const bool own = weights != kParallelogramWeights;
    out.put(own, 1);
    if (!own) return;
    for (std::int32_t w : weights) out.put(static_cast<std::uint32_t>(w) & ((1u << kWeightBits) - 1), kWeightBits);
}

SpatialWeights read_spatial_weights(BitReader& in, SpatialMode spatial) {
    if (spatial == SpatialMode::none || !in.get(1)) return kParallelogramWeights;
    SpatialWeights weights{};
    for (std::int32_t& w : weights) {
        const auto bits = static_cast<std::int32_t>(in.get(kWeightBits));
        w = bits >= (1 << (kWeightBits - 1)) ? bits - (1 << kWeightBits) : bits;
    }
    return weights;
}

}  // namespace foldcast::codec
