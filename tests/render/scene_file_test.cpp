// Scene files: the default scene parses; mistakes are InputErrors naming file, line, key.
#include <gtest/gtest.h>

#include <fstream>

#include "test_paths.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/render/render.hpp"

namespace foldcast::render {
namespace {

std::filesystem::path write_scene(const std::string& text) {
    const auto path = test::temp_dir() / "scene.toml";
    std::ofstream(path) << text;
    return path;
}

std::string error_of(const std::string& text) {
    try {
        load_scene(write_scene(text));
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(SceneFile, DefaultSceneParses) {
    const SceneSpec s = load_scene(std::filesystem::path(FOLDCAST_SOURCE_DIR) / "gallery/default.toml");
    EXPECT_EQ(s.garment.source, GarmentSpec::Source::drape);
    EXPECT_EQ(s.width, 1280);
    EXPECT_EQ(s.height, 720);
    EXPECT_EQ(s.spp, 64);
    EXPECT_TRUE(s.studio_preset);
    EXPECT_TRUE(s.camera.auto_frame);
}

TEST(SceneFile, ReadsEveryTable) {
    const SceneSpec s = load_scene(write_scene(R"(
[garment]
path = "cloth.obj"
scale = 0.5
[camera]
position = [0, 1, 3]
target = [0, 0.5, 0]
fov_deg = 40
[lights]
environment = [0.1, 0.2, 0.3]
[[lights.area]]
name = "top"
position = [0, 3, 0]
target = [0, 0, 0]
size_m = [1, 2]
colour = "#ffffff"
intensity = 4
[backdrop]
kind = "none"
transparent = true
[supports]
kind = "none"
[output]
width = 320
height = 200
spp = 8
seed = 9
)"));
    EXPECT_EQ(s.garment.source, GarmentSpec::Source::obj);
    EXPECT_EQ(s.garment.path.filename(), "cloth.obj");
    EXPECT_FALSE(s.camera.auto_frame);
    EXPECT_FALSE(s.studio_preset);  // explicit lights replace the preset
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_FLOAT_EQ(s.lights[0].radiance.x(), 4.0f);
    EXPECT_FLOAT_EQ(s.lights[0].height_m, 2.0f);
    EXPECT_FLOAT_EQ(s.environment.z(), 0.3f);
    EXPECT_TRUE(s.transparent);
    EXPECT_EQ(s.backdrop, SceneSpec::Backdrop::none);
    EXPECT_EQ(s.supports, SceneSpec::Supports::none);
    EXPECT_EQ(s.seed, 9u);
}

TEST(SceneFile, UnknownKeyNamesFileLineAndKey) {
    const std::string e = error_of("[output]\nwidth = 100\nspp_count = 3\n");
    EXPECT_NE(e.find("scene.toml:3"), std::string::npos) << e;
    EXPECT_NE(e.find("output.spp_count"), std::string::npos) << e;
    const std::string top = error_of("colour = 1\n");
    EXPECT_NE(top.find("scene.toml:1"), std::string::npos) << top;
    EXPECT_NE(top.find("'colour'"), std::string::npos) << top;
}

TEST(SceneFile, BadValuesNameKeyValueAndRange) {
    std::string e = error_of("[camera]\n\nfov_deg = 500\n");
    EXPECT_NE(e.find("scene.toml:3"), std::string::npos) << e;
    EXPECT_NE(e.find("camera.fov_deg"), std::string::npos) << e;
    EXPECT_NE(e.find("500"), std::string::npos) << e;
    e = error_of("[output]\nwidth = \"wide\"\n");
    EXPECT_NE(e.find("output.width"), std::string::npos) << e;
    EXPECT_NE(e.find("integer"), std::string::npos) << e;
    e = error_of("[backdrop]\ncolour = \"#12345\"\n");
    EXPECT_NE(e.find("backdrop.colour"), std::string::npos) << e;
    e = error_of("[supports]\nkind = \"hook\"\n");
    EXPECT_NE(e.find("rod, clips, none"), std::string::npos) << e;  // lists what is allowed
    e = error_of("[garment]\npath = \"x.stl\"\n");
    EXPECT_NE(e.find(".obj, .pc2 or .fca"), std::string::npos) << e;
}

TEST(SceneFile, SupportsAndDropKeys) {
    const SceneSpec curtain = load_scene(std::filesystem::path(FOLDCAST_SOURCE_DIR) / "gallery/curtain.toml");
    EXPECT_EQ(curtain.garment.supports, 5);
    EXPECT_EQ(curtain.garment.support_drop_m, 0.0);
    const SceneSpec s = load_scene(write_scene("[garment]\nsupports = 3\nsupport_drop_m = -0.05\ngrid = [33, 20]\n"));
    EXPECT_EQ(s.garment.supports, 3);
    EXPECT_EQ(s.garment.support_drop_m, -0.05);
    std::string e = error_of("[garment]\nsupports = 1\n");
    EXPECT_NE(e.find("garment.supports"), std::string::npos) << e;
    EXPECT_NE(e.find("[2, 65]"), std::string::npos) << e;
    e = error_of("[garment]\nsupport_drop_m = 1.0\n");  // the default span is 0.36 m
    EXPECT_NE(e.find("garment.support_drop_m"), std::string::npos) << e;
    e = error_of("[garment]\nsupports = 5\ngrid = [64, 64]\n");
    EXPECT_NE(e.find("garment.grid"), std::string::npos) << e;
    EXPECT_NE(e.find("multiple of 4"), std::string::npos) << e;
}

TEST(SceneFile, ClosureKey) {
    EXPECT_EQ(load_scene(write_scene("[garment]\nwidth_m = 0.5\n")).garment.closure, "hem");
    EXPECT_EQ(load_scene(write_scene("[garment]\nclosure = \"paper\"\n")).garment.closure, "paper");
    const std::string e = error_of("[garment]\nclosure = \"papers\"\n");
    EXPECT_NE(e.find("garment.closure"), std::string::npos) << e;
    EXPECT_NE(e.find("hem"), std::string::npos) << e;
    EXPECT_NE(e.find("paper"), std::string::npos) << e;
}

TEST(SceneFile, SyntaxErrorNamesLine) {
    const std::string e = error_of("[output]\nwidth = = 3\n");
    EXPECT_NE(e.find("scene.toml:2"), std::string::npos) << e;
}

TEST(SceneFile, MissingFileIsAnInputError) { EXPECT_THROW(load_scene("/nonexistent/scene.toml"), InputError); }

TEST(SceneFile, ParsesAovList) {
    EXPECT_EQ(parse_aovs("albedo,fold").size(), 2u);
    EXPECT_THROW(parse_aovs("albedo,shadow"), InputError);
}

}  // namespace
}  // namespace foldcast::render
