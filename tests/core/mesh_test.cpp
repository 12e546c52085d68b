#include <gtest/gtest.h>

#include "foldcast/core/error.hpp"
#include "foldcast/core/mesh.hpp"

namespace foldcast {
namespace {

std::vector<Vec3f> quad_positions() { return {Vec3f(0, 0, 0), Vec3f(1, 0, 0), Vec3f(1, 1, 0), Vec3f(0, 1, 0)}; }

TEST(VertexNormals, FlatQuadFacesPlusZ) {
    const auto n = vertex_normals(quad_positions(), {{0, 1, 2}, {0, 2, 3}});
    ASSERT_EQ(n.size(), 4u);
    for (const Vec3f& v : n) EXPECT_NEAR((v - Vec3f(0, 0, 1)).norm(), 0.0f, 1e-6f);
}

TEST(VertexNormals, AreaWeighted) {
    // A large triangle in the xy plane and a tiny one in the xz plane share vertex 0.
    std::vector<Vec3f> p{Vec3f(0, 0, 0), Vec3f(10, 0, 0), Vec3f(0, 10, 0), Vec3f(0, 0, 0.1f)};
    const auto n = vertex_normals(p, {{0, 1, 2}, {0, 3, 1}});
    EXPECT_GT(n[0].z(), 0.99f);
    EXPECT_NEAR(n[0].norm(), 1.0f, 1e-6f);
}

TEST(Validate, RejectsOutOfRangeIndex) {
    Mesh m;
    m.positions = quad_positions();
    m.topology.triangles = {{0, 1, 4}};
    EXPECT_THROW(validate(m, "test"), InputError);
}

TEST(Validate, RejectsNonFinitePosition) {
    Mesh m;
    m.positions = quad_positions();
    m.positions[2].y() = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(validate(m, "test"), InputError);
}

TEST(Validate, RejectsRaggedAnimation) {
    Animation a;
    a.frames = {quad_positions(), {Vec3f(0, 0, 0)}};
    EXPECT_THROW(validate(a, "test"), InputError);
}

TEST(Bounds, CoversAllFrames) {
    Animation a;
    a.frames = {quad_positions(), quad_positions()};
    a.frames[1][0] = Vec3f(-1, -2, -3);
    const Bounds b = bounds(a);
    EXPECT_EQ(b.min, Vec3f(-1, -2, -3));
    EXPECT_EQ(b.max, Vec3f(1, 1, 0));
    EXPECT_NEAR(b.diagonal(), std::sqrt(4.0f + 9.0f + 9.0f), 1e-5f);
}

}  // namespace
}  // namespace foldcast
