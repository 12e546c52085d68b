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

// Two triangles per cell of a cols x rows vertex grid (row-major).
inline std::vector<Triangle> grid_triangles(std::size_t cols, std::size_t rows) {
    std::vector<Triangle> tris;
    for (std::size_t r = 0; r + 1 < rows; ++r)
        for (std::size_t c = 0; c + 1 < cols; ++c) {
            const auto v = static_cast<std::uint32_t>(r * cols + c);
            const auto below = v + static_cast<std::uint32_t>(cols);
            tris.push_back({v, v + 1, below});
            tris.push_back({v + 1, below + 1, below});
        }
    return tris;
}

inline Animation wave_grid(int nu, int nv, int frames) {
    Animation a;
    a.fps = 30.0;
    a.topology.triangles = grid_triangles(std::size_t(nu), std::size_t(nv));
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
