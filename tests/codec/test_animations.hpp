#pragma once
// Animations for codec tests: the Blender cache shipped in tests/data and a synthetic
// regular-grid cloth (a travelling wave), the shape of foldcast's own garments.
#include <cmath>

#include "foldcast/core/mesh_io.hpp"
#include "test_paths.hpp"

namespace foldcast::test {

inline Animation basic_cloth() {
    return read_pc2_animation(test_data("animations/basicCloth.pc2"), test_data("animations/basicCloth.obj"), 24.0);
}

inline Animation wave_grid(int nu, int nv, int frames) {
    Animation a;
    a.fps = 30.0;
    for (int j = 0; j + 1 < nv; ++j)
        for (int i = 0; i + 1 < nu; ++i) {
            const auto v = static_cast<std::uint32_t>(j * nu + i);
            a.topology.triangles.push_back({v, v + 1, v + static_cast<std::uint32_t>(nu)});
            a.topology.triangles.push_back(
                {v + 1, v + static_cast<std::uint32_t>(nu) + 1, v + static_cast<std::uint32_t>(nu)});
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) a.topology.uvs.emplace_back(0.01f * float(i), 0.01f * float(j));
    for (int t = 0; t < frames; ++t) {
        std::vector<Vec3f> f;
        const double s = double(t) / 30.0;
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) {
                const double x = 0.5 * i / (nu - 1), y = -0.7 * j / (nv - 1);
                const double z = 0.03 * std::sin(12.0 * x - 3.0 * s) * std::cos(5.0 * y + s) * std::min(1.0, s);
                f.emplace_back(float(x * (1.0 - 0.1 * std::min(1.0, s))), float(y), float(z));
            }
        a.frames.push_back(std::move(f));
    }
    return a;
}

}  // namespace foldcast::test
