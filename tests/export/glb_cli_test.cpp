// drape, decode and export writing .glb files through the built binary, and their refusals:
// exit 2, a line naming the file, nothing left behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "foldcast/core/mesh_io.hpp"
#include "glb_reader.hpp"
#include "run_command.hpp"
#include "test_paths.hpp"

namespace foldcast::test {
namespace glb_cli_test {

namespace fs = std::filesystem;

CommandResult foldcast(const std::string& args) { return run_command(foldcast_binary() + " " + args + " 2>&1"); }

std::vector<std::string> names_in(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

const nlohmann::json& primitive_of(const Glb& glb) { return glb.json["meshes"][0]["primitives"][0]; }

TEST(GlbCli, DrapeWritesTheGarmentWithItsLook) {
    const fs::path dir = temp_dir();
    const CommandResult r = foldcast("drape --grid 16x12 --look denim -o " + (dir / "g.glb").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const Glb glb = parse_glb(read_file((dir / "g.glb").string()));
    EXPECT_EQ(glb.json["accessors"][primitive_of(glb)["attributes"]["POSITION"].get<int>()]["count"], 16 * 12);
    EXPECT_EQ(glb.json["materials"][0]["name"], "denim");
    EXPECT_FALSE(primitive_of(glb).contains("targets"));
    // The same garment as the OBJ the same command writes.
    ASSERT_EQ(foldcast("drape --grid 16x12 --look denim -o " + (dir / "g.obj").string()).exit_code, 0);
    const Mesh obj = read_obj(dir / "g.obj");
    const std::vector<float> p = glb.floats(primitive_of(glb)["attributes"]["POSITION"]);
    ASSERT_EQ(p.size(), 3 * obj.positions.size());
    for (std::size_t i = 0; i < obj.positions.size(); ++i)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(p[3 * i + c], obj.positions[i][c], 1e-6f);
}

TEST(GlbCli, DrapeAndDecodeWriteAnimations) {
    const fs::path dir = temp_dir();
    CommandResult r = foldcast("drape --grid 12x12 --frames 6 --json -q -o " + (dir / "a.glb").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["glb"]["morph_targets"], 5);
    EXPECT_TRUE(j["glb"]["compressed"].get<bool>());
    EXPECT_EQ(parse_glb(read_file((dir / "a.glb").string())).json["animations"].size(), 1u);

    ASSERT_EQ(foldcast("drape --grid 12x12 --frames 6 -q -o " + (dir / "a.fca").string()).exit_code, 0);
    r = foldcast("decode " + (dir / "a.fca").string() + " --look linen -o " + (dir / "d.glb").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    ASSERT_EQ(foldcast("decode " + (dir / "a.fca").string() + " -o " + (dir / "d.pc2").string()).exit_code, 0);
    const auto frames = read_pc2(dir / "d.pc2");
    const Glb glb = parse_glb(read_file((dir / "d.glb").string()));
    EXPECT_EQ(glb.json["materials"][0]["name"], "linen");
    ASSERT_EQ(primitive_of(glb)["targets"].size(), frames.size() - 1);
    const nlohmann::json& node = glb.json["nodes"][0];
    const float step = node["scale"][0];
    const Vec3f centre(node["translation"][0], node["translation"][1], node["translation"][2]);
    const std::vector<float> base = glb.floats(primitive_of(glb)["attributes"]["POSITION"]);
    const std::vector<float> last = glb.floats(primitive_of(glb)["targets"][frames.size() - 2]["POSITION"]);
    for (std::size_t i = 0; i < frames.back().size(); ++i) {
        const Vec3f q(base[3 * i] + last[3 * i], base[3 * i + 1] + last[3 * i + 1], base[3 * i + 2] + last[3 * i + 2]);
        EXPECT_LE((q * step + centre - frames.back()[i]).norm(), step) << "vertex " << i;
    }
}

TEST(GlbCli, ExportWritesASceneGarmentWithItsLook) {
    const fs::path dir = temp_dir();
    std::ofstream(dir / "scene.toml") << "look = \"velvet\"\n[garment]\nsource = \"drape\"\ngrid = [14, 18]\n";
    const CommandResult r =
        foldcast("export " + (dir / "scene.toml").string() + " --json -o " + (dir / "v.glb").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(nlohmann::json::parse(r.out)["look"], "velvet");
    const Glb glb = parse_glb(read_file((dir / "v.glb").string()));
    EXPECT_EQ(glb.json["materials"][0]["name"], "velvet");
    EXPECT_TRUE(glb.json["materials"][0]["extensions"].contains("KHR_materials_sheen"));
    EXPECT_EQ(glb.json["accessors"][primitive_of(glb)["attributes"]["POSITION"].get<int>()]["count"], 14 * 18);
}

TEST(GlbCli, BadInputExitsTwoNamingTheFileAndLeavesNothing) {
    const fs::path dir = temp_dir();
    std::ofstream(dir / "scene.toml") << "look = \"denim\"\n[garment]\nsource = \"drape\"\ngrid = [8, 8]\n";
    std::ofstream(dir / "broken.fca") << "not an fca file at all";
    std::ofstream(dir / "bad.toml") << "look = \"denim\"\n[garment]\nsource = \"drape\"\ngrid = [8, \n";
    const std::string d = dir.string() + "/";
    const struct {
        std::string args, named;
    } cases[] = {
        {"decode " + d + "missing.fca -o " + d + "x.glb", "missing.fca"},
        {"decode " + d + "broken.fca -o " + d + "x.glb", "broken.fca"},
        {"decode " + d + "broken.fca -o " + d + "x.gltf", "x.gltf"},
        {"decode " + d + "broken.fca --look nosuchlook -o " + d + "x.glb", "nosuchlook"},
        {"export " + d + "missing.toml -o " + d + "x.glb", "missing.toml"},
        {"export " + d + "bad.toml -o " + d + "x.glb", "bad.toml"},
        {"export " + d + "scene.toml -o " + d + "x.obj", "x.obj"},
        {"export " + d + "scene.toml -o " + d + "nodir/x.glb", "nodir/x.glb"},
        {"drape --grid 8x8 -o " + d + "nodir/x.glb", "nodir/x.glb"},
        {"drape --grid 8x8 --look nosuchlook -o " + d + "x.glb", "nosuchlook"},
    };
    for (const auto& c : cases) {
        const CommandResult r = foldcast(c.args);
        EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.out;
        EXPECT_NE(r.out.find(c.named), std::string::npos) << c.args << "\n" << r.out;
    }
    EXPECT_EQ(names_in(dir), (std::vector<std::string>{"bad.toml", "broken.fca", "scene.toml"}));
}

}  // namespace glb_cli_test
}  // namespace foldcast::test
