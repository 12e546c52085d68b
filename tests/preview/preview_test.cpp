#include <gtest/gtest.h>

#include <cmath>

#include "foldcast/preview/preview.hpp"

namespace foldcast::preview {
namespace {

// A unit square in the z = 0 plane facing +z, at (cx, cy) with side `side`.
Mesh square(float cx, float cy, float side, float z = 0.0f) {
    const float h = side / 2.0f;
    Mesh m;
    m.positions = {Vec3f(cx - h, cy - h, z), Vec3f(cx + h, cy - h, z), Vec3f(cx + h, cy + h, z),
                   Vec3f(cx - h, cy + h, z)};
    m.topology.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

// Camera on +z at distance 3 whose view half-height at z = 0 is exactly 1 m.
PreviewScene scene_with(const std::vector<const Mesh*>& meshes) {
    PreviewScene scene;
    for (const Mesh* m : meshes) scene.objects.push_back({m, {}, true});
    scene.camera.position = Vec3f(0, 0, 3);
    scene.camera.vertical_fov_deg = 2.0f * std::atan(1.0f / 3.0f) * 180.0f / 3.14159265f;
    scene.lights = {{Vec3f(0, 0, 4), Vec3f(20, 20, 20)}};
    scene.transparent_background = true;
    return scene;
}

TEST(Preview, SquareCoversTheProjectedArea) {
    PreviewRenderer renderer(64, 64, 4);
    const Mesh quad = square(0, 0, 1);
    const PreviewImage image = renderer.render(scene_with({&quad}));
    ASSERT_EQ(image.rgba.size(), 64u * 64u * 4u);
    int covered = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const bool inside = x >= 16 && x < 48 && y >= 16 && y < 48;
            const bool drawn = std::isfinite(image.depth[y * 64 + x]);
            EXPECT_EQ(drawn, inside) << "pixel " << x << "," << y;
            EXPECT_EQ(image.rgba[(y * 64 + x) * 4 + 3], inside ? 1.0f : 0.0f) << "alpha at " << x << "," << y;
            covered += drawn;
        }
    EXPECT_EQ(covered, 32 * 32);
}

TEST(Preview, DepthIsDistanceFromTheCamera) {
    PreviewRenderer renderer(64, 64, 1);
    const Mesh quad = square(0, 0, 1.5f);
    const PreviewImage image = renderer.render(scene_with({&quad}));
    for (int y : {20, 31, 40})
        for (int x : {20, 32, 45}) {
            const float px = ((x + 0.5f) / 64.0f * 2.0f - 1.0f);  // metres at z = 0
            const float py = -((y + 0.5f) / 64.0f * 2.0f - 1.0f);
            const float expected = std::sqrt(9.0f + px * px + py * py);
            EXPECT_NEAR(image.depth[y * 64 + x], expected, 1e-4f) << x << "," << y;
        }
}

TEST(Preview, ImageIsTopRowFirst) {
    PreviewRenderer renderer(64, 64, 1);
    const Mesh upper = square(0, 0.5f, 0.5f);  // only in the upper half of the view
    const PreviewImage image = renderer.render(scene_with({&upper}));
    EXPECT_TRUE(std::isfinite(image.depth[20 * 64 + 32]));
    EXPECT_FALSE(std::isfinite(image.depth[44 * 64 + 32]));
}

TEST(Preview, KeyLightCastsShadows) {
    PreviewRenderer renderer(64, 64, 1);
    const Mesh back = square(0, 0, 1.8f);
    const Mesh blocker = square(0.45f, 0.45f, 0.4f, 1.0f);  // between the light and the back square's corner
    PreviewScene scene = scene_with({&back, &blocker});
    scene.lights = {{Vec3f(1.8f, 1.8f, 4.0f), Vec3f(20, 20, 20)}};
    const PreviewImage image = renderer.render(scene);
    auto red = [&](int x, int y) { return image.rgba[(y * 64 + x) * 4]; };
    // The blocker's shadow falls on the back square down-left of the blocker: towards
    // -x/-y from it along the light direction.
    const Vec3f shadow_point = Vec3f(0.45f, 0.45f, 1.0f) + (Vec3f(0.45f, 0.45f, 1.0f) - Vec3f(1.8f, 1.8f, 4.0f)) / 3.0f;
    ASSERT_NEAR(shadow_point.z(), 0.0f, 1e-5f);
    // Project onto the image: the back square lies in z = 0 where the view is 2 m high.
    const int sx = static_cast<int>((shadow_point.x() + 1.0f) / 2.0f * 64.0f);
    const int sy = static_cast<int>((1.0f - shadow_point.y()) / 2.0f * 64.0f);
    // The shadow spans |x|, |y| < 0.27 m on the back square; (-0.6, 0.6) is lit.
    const int lit_x = static_cast<int>((-0.6f + 1.0f) / 2.0f * 64.0f);
    const int lit_y = static_cast<int>((1.0f - 0.6f) / 2.0f * 64.0f);
    // In shadow only the ambient term remains: a small fraction of the lit radiance.
    EXPECT_LT(red(sx, sy) * 3.0f, red(lit_x, lit_y)) << "shadow " << red(sx, sy) << " lit " << red(lit_x, lit_y);
}

TEST(Preview, RepeatedRendersAreIdentical) {
    PreviewRenderer renderer(48, 32, 4);
    const Mesh quad = square(0.1f, -0.2f, 0.9f);
    const PreviewImage a = renderer.render(scene_with({&quad}));
    const PreviewImage b = renderer.render(scene_with({&quad}));
    EXPECT_EQ(a.rgba, b.rgba);
    EXPECT_EQ(a.width, 48);
    EXPECT_EQ(a.height, 32);
}

}  // namespace
}  // namespace foldcast::preview
