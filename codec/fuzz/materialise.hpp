#pragma once
// What a fuzz target does with a decoded header: the whole animation when it is small enough
// for the fuzzer's memory limit (as `foldcast decode` refuses up front what exceeds the
// memory it may use), else its first and last frames (at most 2^23 vertices: 96 MiB each),
// which run the same decoding code.
// Any single allocation beyond -malloc_limit_mb is then one the input's bytes did not justify.
#include <cstdint>

#include "foldcast/codec/codec.hpp"

namespace foldcast::codec::fuzz {

inline constexpr std::uint64_t kMaterialisedVertexFrames = std::uint64_t(1) << 25;  // 384 MiB of positions

inline void materialise(const StreamingDecoder& decoder) {
    const std::uint64_t vertex_frames = std::uint64_t(decoder.vertex_count()) * decoder.frame_count();
    if (vertex_frames <= kMaterialisedVertexFrames) {
        const auto anim = decoder.animation();
        (void)anim;
        return;
    }
    (void)decoder.frame(0);
    (void)decoder.frame(decoder.frame_count() - 1);
}

}  // namespace foldcast::codec::fuzz
