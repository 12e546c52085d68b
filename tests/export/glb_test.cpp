// The .glb writer: static garments keep their floats exactly, animations come back from
// meshoptimizer's decoders within the quantization error, looks become materials.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>

#include <cmath>
#include <filesystem>

#include "foldcast/core/error.hpp"
#include "foldcast/export/gltf.hpp"
#include "glb_reader.hpp"
#include "shipped_looks.hpp"
#include "test_paths.hpp"

namespace foldcast::gltf {
namespace glb_test {

using test::Glb;
using test::parse_glb;

// An nu x nv grid of cloth 0.3 x 0.4 m (UVs in metres) waving in z; frame f's phase f.
Animation waving_grid(int nu, int nv, int frames) {
    Animation a;
    a.fps = 24.0;
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) a.topology.uvs.emplace_back(0.3f * i / (nu - 1), 0.4f * j / (nv - 1));
    for (int j = 0; j + 1 < nv; ++j)
        for (int i = 0; i + 1 < nu; ++i) {
            const auto v = static_cast<std::uint32_t>(j * nu + i), w = static_cast<std::uint32_t>(nu);
            a.topology.triangles.push_back({v, v + w, v + 1});
            a.topology.triangles.push_back({v + 1, v + w, v + w + 1});
        }
    for (int f = 0; f < frames; ++f) {
        std::vector<Vec3f> p;
        for (const Vec2f& uv : a.topology.uvs)
            p.emplace_back(uv.x() - 0.15f, -uv.y(), 0.02f * std::sin(40.0f * uv.x() + 0.7f * f) * uv.y());
        a.frames.push_back(p);
    }
    return a;
}

GlbOptions with_look(const std::string& name) {
    GlbOptions o;
    o.look = test::shipped_looks().get(name);
    o.texture_px = 64;
    return o;
}

TEST(Glb, StaticGarmentKeepsItsFloats) {
    const Animation a = waving_grid(7, 5, 1);
    const Mesh mesh = a.frame_mesh(0);
    GlbSummary summary;
    const Glb glb = parse_glb(glb_bytes(mesh, with_look("denim"), &summary));
    EXPECT_EQ(summary.vertices, 35u);
    EXPECT_EQ(summary.morph_targets, 0u);
    EXPECT_EQ(summary.max_position_error_m, 0.0);
    EXPECT_FALSE(glb.json.contains("extensionsRequired"));
    const nlohmann::json& primitive = glb.json["meshes"][0]["primitives"][0];
    const std::vector<float> p = glb.floats(primitive["attributes"]["POSITION"]);
    const std::vector<float> uv = glb.floats(primitive["attributes"]["TEXCOORD_0"]);
    const std::vector<float> n = glb.floats(primitive["attributes"]["NORMAL"]);
    const std::vector<float> t = glb.floats(primitive["attributes"]["TANGENT"]);
    ASSERT_EQ(p.size(), 3 * mesh.positions.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        for (int c = 0; c < 3; ++c) EXPECT_EQ(p[3 * i + c], mesh.positions[i][c]);
        for (int c = 0; c < 2; ++c) EXPECT_EQ(uv[2 * i + c], mesh.topology.uvs[i][c]);
        const Eigen::Vector3f normal(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
        const Eigen::Vector3f tangent(t[4 * i], t[4 * i + 1], t[4 * i + 2]);
        EXPECT_NEAR(normal.norm(), 1.0f, 1e-5f);
        EXPECT_NEAR(tangent.norm(), 1.0f, 1e-5f);
        EXPECT_NEAR(normal.dot(tangent), 0.0f, 1e-5f);
        EXPECT_EQ(std::abs(t[4 * i + 3]), 1.0f);
        // The tangent follows +u (the warp), the bitangent -v (glTF's normal-map convention).
        EXPECT_GT(tangent.x(), 0.9f);
        EXPECT_GT((normal.cross(tangent) * t[4 * i + 3]).y(), 0.9f) << "v runs down the cloth: -v is +y";
    }
    const std::vector<std::uint32_t> indices = glb.indices(primitive["indices"]);
    ASSERT_EQ(indices.size(), 3 * mesh.topology.triangles.size());
    for (std::size_t k = 0; k < indices.size(); ++k) EXPECT_EQ(indices[k], mesh.topology.triangles[k / 3][k % 3]);
}

TEST(Glb, LookBecomesAMaterialWithItsWeaveAtPhysicalScale) {
    const Glb glb = parse_glb(glb_bytes(waving_grid(4, 4, 1).frame_mesh(0), with_look("denim")));
    const nlohmann::json& m = glb.json["materials"][0];
    EXPECT_EQ(m["name"], "denim");
    EXPECT_TRUE(m["doubleSided"].get<bool>());
    EXPECT_EQ(m["pbrMetallicRoughness"]["metallicFactor"], 0.0);
    EXPECT_NEAR(m["pbrMetallicRoughness"]["roughnessFactor"].get<double>(), 0.85, 1e-9);
    // Denim: 3/1 twill, 0.45 mm yarns, 4 yarns a repeat; a tile of 16 yarns = 7.2 mm.
    const nlohmann::json& scale =
        m["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"]["scale"];
    EXPECT_NEAR(scale[0].get<double>(), 1.0 / 0.0072, 1e-6);
    EXPECT_NEAR(scale[1].get<double>(), 1.0 / 0.0072, 1e-6);
    EXPECT_TRUE(m.contains("normalTexture"));
    EXPECT_TRUE(m["extensions"].contains("KHR_materials_sheen"));
    EXPECT_GT(m["extensions"]["KHR_materials_anisotropy"]["anisotropyStrength"].get<double>(), 0.0);
    EXPECT_NEAR(m["extensions"]["KHR_materials_specular"]["specularColorFactor"][0].get<double>(), 0.5, 1e-9);
    // The images are PNGs of the asked size, and the weave shows: warp and weft differ.
    for (const auto& image : glb.json["images"]) {
        const std::string bytes = glb.view_bytes(image["bufferView"]);
        const cv::Mat decoded = cv::imdecode(std::vector<unsigned char>(bytes.begin(), bytes.end()), cv::IMREAD_COLOR);
        ASSERT_FALSE(decoded.empty());
        EXPECT_EQ(decoded.cols, 64);
        EXPECT_EQ(decoded.rows, 64);
    }
    const std::string colour = glb.view_bytes(glb.json["images"][0]["bufferView"]);
    cv::Mat c = cv::imdecode(std::vector<unsigned char>(colour.begin(), colour.end()), cv::IMREAD_COLOR);
    double lo = 0, hi = 0;
    cv::minMaxLoc(c.reshape(1), &lo, &hi);
    EXPECT_GT(hi - lo, 40.0);
}

TEST(Glb, EveryShippedLookBecomesAMaterial) {
    const Mesh mesh = waving_grid(4, 4, 1).frame_mesh(0);
    for (const std::string& name : test::shipped_looks().names()) {
        const looks::Look& look = test::shipped_looks().get(name);
        const Glb glb = parse_glb(glb_bytes(mesh, with_look(name)));
        const nlohmann::json& m = glb.json["materials"][0];
        const bool woven = look.appearance.weave != looks::Weave::none;
        EXPECT_EQ(m["pbrMetallicRoughness"].contains("baseColorTexture"), woven) << name;
        EXPECT_EQ(m.contains("extensions") && m["extensions"].contains("KHR_materials_sheen"),
                  look.appearance.sheen_colour.maxCoeff() > 0.0f)
            << name;
        EXPECT_EQ(m["extensions"].contains("KHR_materials_anisotropy"), look.appearance.anisotropy > 0.0) << name;
    }
}

TEST(Glb, AnimationDecodesWithinTheQuantizationError) {
    const Animation a = waving_grid(9, 6, 5);
    GlbSummary summary;
    const Glb glb = parse_glb(glb_bytes(a, with_look("satin"), &summary));
    EXPECT_TRUE(summary.compressed);
    EXPECT_EQ(summary.morph_targets, 4u);
    const nlohmann::json& required = glb.json["extensionsRequired"];
    EXPECT_NE(std::find(required.begin(), required.end(), "KHR_mesh_quantization"), required.end());
    EXPECT_NE(std::find(required.begin(), required.end(), "EXT_meshopt_compression"), required.end());
    const nlohmann::json& node = glb.json["nodes"][0];
    const float step = node["scale"][0];
    const Eigen::Vector3f centre(node["translation"][0], node["translation"][1], node["translation"][2]);
    // 15-bit positions over the largest side (0.4 m): 0.4 / 32766 m a step.
    EXPECT_NEAR(step, 0.4 / 32766, 1e-7);
    EXPECT_LE(summary.max_position_error_m, std::sqrt(3.0) / 2 * step * 1.001);
    const nlohmann::json& primitive = glb.json["meshes"][0]["primitives"][0];
    const std::vector<float> base = glb.floats(primitive["attributes"]["POSITION"]);
    double worst = 0.0;
    for (std::size_t f = 0; f < a.frame_count(); ++f) {
        std::vector<float> delta(base.size(), 0.0f);
        if (f > 0) delta = glb.floats(primitive["targets"][f - 1]["POSITION"]);
        for (std::size_t i = 0; i < a.vertex_count(); ++i) {
            const Eigen::Vector3f q(base[3 * i] + delta[3 * i], base[3 * i + 1] + delta[3 * i + 1],
                                    base[3 * i + 2] + delta[3 * i + 2]);
            worst = std::max<double>(worst, (q * step + centre - a.frames[f][i]).norm());
        }
    }
    EXPECT_LE(worst, summary.max_position_error_m * 1.0001 + 1e-9);
    EXPECT_GT(worst, 0.0);
    // Each target is on at its frame only.
    const nlohmann::json& sampler = glb.json["animations"][0]["samplers"][0];
    const std::vector<float> times = glb.floats(sampler["input"]), weights = glb.floats(sampler["output"]);
    ASSERT_EQ(times.size(), 5u);
    EXPECT_NEAR(times[4], 4 / 24.0, 1e-6);
    ASSERT_EQ(weights.size(), 5u * 4u);
    for (std::size_t k = 0; k < 5; ++k)
        for (std::size_t t = 0; t < 4; ++t) EXPECT_EQ(weights[k * 4 + t], k == t + 1 ? 1.0f : 0.0f);
    // The indices survive the index codec (which may rotate a triangle's corners).
    const std::vector<std::uint32_t> indices = glb.indices(primitive["indices"]);
    ASSERT_EQ(indices.size(), 3 * a.topology.triangles.size());
    for (std::size_t k = 0; k < a.topology.triangles.size(); ++k) {
        std::array<std::uint32_t, 3> got{indices[3 * k], indices[3 * k + 1], indices[3 * k + 2]};
        auto want = a.topology.triangles[k];
        while (got[0] != want[0]) std::rotate(got.begin(), got.begin() + 1, got.end());
        EXPECT_EQ(got, want) << "triangle " << k;
    }
}

TEST(Glb, UncompressedAnimationHasFloatDeltas) {
    const Animation a = waving_grid(5, 5, 3);
    GlbOptions o = with_look("linen");
    o.compress = false;
    const Glb glb = parse_glb(glb_bytes(a, o));
    EXPECT_FALSE(glb.json.contains("extensionsRequired"));
    const nlohmann::json& primitive = glb.json["meshes"][0]["primitives"][0];
    const std::vector<float> d = glb.floats(primitive["targets"][1]["POSITION"]);
    for (std::size_t i = 0; i < a.vertex_count(); ++i)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(d[3 * i + c], a.frames[2][i][c] - a.frames[0][i][c]);
}

TEST(Glb, SameInputSameBytes) {
    const Animation a = waving_grid(6, 6, 4);
    EXPECT_EQ(glb_bytes(a, with_look("denim")), glb_bytes(a, with_look("denim")));
}

TEST(Glb, BadInputIsAnInputErrorAndWritesNothing) {
    const auto dir = test::temp_dir();
    Animation empty;
    EXPECT_THROW(glb_bytes(empty, {}), InputError);
    Animation broken = waving_grid(3, 3, 2);
    broken.topology.triangles.push_back({0, 1, 99});
    EXPECT_THROW(glb_bytes(broken, {}), InputError);
    Animation too_long = waving_grid(2, 2, 1);
    too_long.frames.resize(2001, too_long.frames[0]);
    try {
        glb_bytes(too_long, {});
        FAIL() << "2001 frames accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("2000"), std::string::npos) << e.what();
    }
    try {
        write_glb(dir / "missing" / "out.glb", waving_grid(3, 3, 1), {});
        FAIL() << "a missing directory accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("out.glb"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(std::filesystem::is_empty(dir));
}

}  // namespace glb_test
}  // namespace foldcast::gltf
