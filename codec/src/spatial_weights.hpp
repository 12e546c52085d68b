#pragma once
// Weighted spatial prediction (profile `cascade`, format 5; docs/codec.md): the temporal
// residual of a vertex predicted from six decoded neighbours, the corners a, b, c of its
// parallelogram and a2, b2, c2 of a second one, with weights the encoder fits to each frame
// by least squares and sends (8 bits each, in 64ths).  At the noise floor of the closed loop
// the parallelogram's r_a + r_b - r_c adds three neighbours' quantisation noise at full
// weight; spread over six, the noise averages down.  Integers, so the encoder and every
// decoder agree bit for bit.
#include <array>
#include <cstdint>
#include <vector>

#include "bit_stream.hpp"
#include "foldcast/core/mesh.hpp"
#include "predictive_profile.hpp"

namespace foldcast::codec {

// Coordinate c of the weighted prediction of a vertex with parallelograms s and s2
// (spatial_taps) from the residuals r (3 per vertex); where s2 is missing, the
// parallelogram of s whatever the weights.
template <typename Residual>
inline std::int64_t weighted_prediction(const SpatialReference& s, const SpatialReference& s2, const SpatialWeights& w,
                                        const Residual* r, int c) {
    if (s.c < 0 || s2.c < 0) return spatial_prediction(s, r, c);
    auto at = [&](std::int32_t u) {
        return std::int64_t(r[3 * static_cast<std::size_t>(u) + static_cast<std::size_t>(c)]);
    };
    const std::int64_t sum =
        w[0] * at(s.a) + w[1] * at(s.b) + w[2] * at(s.c) + w[3] * at(s2.a) + w[4] * at(s2.b) + w[5] * at(s2.c);
    return (sum + (std::int64_t(1) << (kWeightShift - 1))) >> kWeightShift;
}

// A frame's spatial prediction of coordinate c: with the frame's own weights where it has
// them, else (own null) the parallelogram, the same value as its weights give in fewer steps.
template <typename Residual>
inline std::int64_t frame_spatial_prediction(const SpatialReference& s, const SpatialReference& s2,
                                             const SpatialWeights* own, const Residual* r, int c) {
    return own ? weighted_prediction(s, s2, *own, r, c) : spatial_prediction(s, r, c);
}

// The frame's own weights, or null where they are the parallelogram's.
inline const SpatialWeights* own_weights(const SpatialWeights& w) { return w == kParallelogramWeights ? nullptr : &w; }

// The weights that best predict the frame's temporal residuals target - temporal (3 per
// vertex) from its neighbours' true residuals, rounded and clamped to what the file can
// carry.  The closed loop then predicts from decoded residuals; the encoder keeps the
// weights only where they beat the parallelogram's.
SpatialWeights fit_spatial_weights(const std::vector<SpatialReference>& first,
                                   const std::vector<SpatialReference>& second, const std::int32_t* target,
                                   const std::int32_t* temporal);

// A frame's weights in the side information of an extended file, after its mode: nothing
// for a frame without spatial prediction, else one bit (its own weights follow) and then
// kSpatialTaps two's-complement values of kWeightBits.
void write_spatial_weights(BitWriter& out, SpatialMode spatial, const SpatialWeights& weights);
SpatialWeights read_spatial_weights(BitReader& in, SpatialMode spatial);

}  // namespace foldcast::codec
