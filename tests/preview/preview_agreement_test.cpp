// The preview must show what the path tracer shows: same silhouette, same depth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "foldcast/render/render.hpp"
#include "foldcast/preview/preview.hpp"

namespace foldcast::preview {
using render::Image;
using render::load_scene;
namespace {

struct Renders {
    RenderResult traced, rasterised;
};

const Renders& default_scene_renders() {
    static const Renders renders = [] {
        SceneSpec scene = load_scene(std::string(FOLDCAST_SOURCE_DIR) + "/gallery/default.toml");
        scene.transparent = true;  // alpha = foreground: garment, rod, clips and wires
        RenderOptions options;
        options.width = 640;
        options.height = 360;
        options.spp = 16;
        options.aovs = {Aov::depth};
        return Renders{render_still(scene, options), preview_still(scene, options, 4)};
    }();
    return renders;
}

TEST(PreviewAgreement, SilhouetteMatchesTheRayTracer) {
    const Renders& r = default_scene_renders();
    ASSERT_EQ(r.traced.beauty.width, r.rasterised.beauty.width);
    ASSERT_EQ(r.traced.beauty.height, r.rasterised.beauty.height);
    std::size_t both = 0, either = 0;
    for (int y = 0; y < r.traced.beauty.height; ++y)
        for (int x = 0; x < r.traced.beauty.width; ++x) {
            const bool a = r.traced.beauty.at(x, y)[3] >= 0.5f;
            const bool b = r.rasterised.beauty.at(x, y)[3] >= 0.5f;
            both += a && b;
            either += a || b;
        }
    ASSERT_GT(either, 1000u) << "the garment should cover a good part of the frame";
    const double iou = static_cast<double>(both) / static_cast<double>(either);
    RecordProperty("silhouette_iou", std::to_string(iou));
    EXPECT_GE(iou, 0.98);
}

TEST(PreviewAgreement, DepthMatchesTheRayTracer) {
    const Renders& r = default_scene_renders();
    ASSERT_EQ(r.traced.aovs.size(), 1u);
    ASSERT_EQ(r.rasterised.aovs.size(), 1u);
    const Image& traced = r.traced.aovs[0].image;
    const Image& rasterised = r.rasterised.aovs[0].image;
    // Interior pixels only (all 8 neighbours covered in both): at silhouettes the tracer's
    // jittered samples and the rasteriser's pixel centre may see different surfaces.
    auto covered = [&](int x, int y) {
        return std::isfinite(*rasterised.at(x, y)) && *traced.at(x, y) > 0.0f && std::isfinite(*traced.at(x, y));
    };
    std::vector<double> relative;
    for (int y = 1; y + 1 < traced.height; ++y)
        for (int x = 1; x + 1 < traced.width; ++x) {
            bool interior = true;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) interior = interior && covered(x + dx, y + dy);
            if (interior) relative.push_back(std::abs(*rasterised.at(x, y) / *traced.at(x, y) - 1.0));
        }
    ASSERT_GT(relative.size(), 1000u);
    std::sort(relative.begin(), relative.end());
    EXPECT_LT(relative[relative.size() / 2], 0.002) << "median relative depth difference";
    EXPECT_LT(relative[relative.size() * 95 / 100], 0.01) << "95th percentile";
}

}  // namespace
}  // namespace foldcast::preview
