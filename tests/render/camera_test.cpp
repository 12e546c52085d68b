// Auto-framing: the garment's projected bounding box spans the intended share of the frame.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "render_fixtures.hpp"

namespace foldcast::render {
namespace {

struct Box {
    double x0 = 1e30, x1 = -1e30, y0 = 1e30, y1 = -1e30;
};

Box projected(const Camera& cam, int w, int h, const std::vector<Vec3f>& pts) {
    Box b;
    for (const Vec3f& p : pts) {
        Eigen::Vector2d px;
        EXPECT_TRUE(project(cam, w, h, p, &px));
        b.x0 = std::min(b.x0, px.x());
        b.x1 = std::max(b.x1, px.x());
        b.y0 = std::min(b.y0, px.y());
        b.y1 = std::max(b.y1, px.y());
    }
    return b;
}

TEST(AutoFraming, BoundingBoxFillsTheShareAndIsCentred) {
    std::vector<Vec3f> pts;
    for (int i = 0; i <= 20; ++i)
        for (int j = 0; j <= 20; ++j) pts.emplace_back(-0.3f + 0.03f * i, -0.04f * j, 0.05f * std::sin(0.7f * j));
    for (const double share : {0.5, 0.8})
        for (const auto& [w, h] : {std::pair{1280, 720}, std::pair{480, 640}}) {
            CameraSpec spec;
            spec.frame_share = share;
            spec.azimuth_deg = 25.0;
            spec.elevation_deg = 10.0;
            const Camera cam = frame_camera(spec, {pts}, static_cast<double>(w) / h);
            const Box b = projected(cam, w, h, pts);
            const double fx = (b.x1 - b.x0) / w, fy = (b.y1 - b.y0) / h;
            EXPECT_NEAR(std::max(fx, fy), share, 1e-3) << w << "x" << h;
            EXPECT_NEAR(0.5 * (b.x0 + b.x1), 0.5 * w, 1e-3 * w);
            EXPECT_NEAR(0.5 * (b.y0 + b.y1), 0.5 * h, 1e-3 * h);
        }
}

TEST(AutoFraming, RenderedGarmentCoversTheShare) {
    // Transparent backdrop, no supports: the alpha mask is the garment's silhouette.
    SceneSpec s = test::cloth_scene(160, 120, 2);
    s.supports = SceneSpec::Supports::none;
    s.backdrop = SceneSpec::Backdrop::none;
    s.transparent = true;
    s.camera.frame_share = 0.6;
    const RenderResult r = render_still(s, {});
    int x0 = 1 << 30, x1 = -1, y0 = 1 << 30, y1 = -1;
    for (int y = 0; y < r.beauty.height; ++y)
        for (int x = 0; x < r.beauty.width; ++x)
            if (r.beauty.at(x, y)[3] > 0.5f) {
                x0 = std::min(x0, x);
                x1 = std::max(x1, x);
                y0 = std::min(y0, y);
                y1 = std::max(y1, y);
            }
    ASSERT_GE(x1, 0);
    const double fx = (x1 - x0 + 1) / 160.0, fy = (y1 - y0 + 1) / 120.0;
    EXPECT_NEAR(std::max(fx, fy), 0.6, 0.03);
    EXPECT_NEAR(0.5 * (x0 + x1 + 1), 80.0, 3.0);
    EXPECT_NEAR(0.5 * (y0 + y1 + 1), 60.0, 3.0);
}

TEST(Camera, ManualCameraLooksAtTheTarget) {
    CameraSpec spec;
    spec.auto_frame = false;
    spec.position = Vec3f(1, 2, 3);
    spec.target = Vec3f(0, 0.5f, 0);
    const Camera cam = frame_camera(spec, {}, 1.5);
    Eigen::Vector2d px;
    ASSERT_TRUE(project(cam, 300, 200, spec.target, &px));
    EXPECT_NEAR(px.x(), 150.0, 1e-6);
    EXPECT_NEAR(px.y(), 100.0, 1e-6);
    EXPECT_FALSE(project(cam, 300, 200, Vec3f(2, 3.5f, 6), &px));  // behind the camera
}

}  // namespace
}  // namespace foldcast::render
