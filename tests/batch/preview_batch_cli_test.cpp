// foldcast preview, turntable --preview and batch, end to end through the binary.
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "run_command.hpp"
#include "test_paths.hpp"

namespace foldcast {
namespace {
namespace fs = std::filesystem;

// foldcast with `arguments` (stdout captured; add 2>&1 for stderr).
test::CommandResult foldcast(const std::string& arguments) {
    return test::run_command(test::foldcast_binary() + " " + arguments);
}

// A tiny scene: Blender's cloth cache frame as the garment, 48x32 pixels, 2 spp.
fs::path tiny_scene(const fs::path& dir) {
    std::ofstream(dir / "tiny.toml") << "[garment]\npath = \"" << test::test_data("animations/basicCloth.obj").string()
                                     << "\"\nscale = 0.1\n[output]\nwidth = 48\nheight = 32\nspp = 2\n";
    return dir / "tiny.toml";
}

TEST(PreviewCli, WritesTheImageAndItsDepth) {
    const auto dir = test::temp_dir();
    const test::CommandResult r = foldcast("preview " + tiny_scene(dir).string() + " -o " + (dir / "p.png").string() +
                                           " --aov depth --json 2>&1");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto report = nlohmann::json::parse(r.out);
    EXPECT_EQ(report["width"], 48);
    EXPECT_EQ(report["height"], 32);
    EXPECT_TRUE(fs::exists(dir / "p.png"));
    EXPECT_TRUE(fs::exists(dir / "p.depth.png"));
}

TEST(PreviewCli, NoEglIsOneLineAndExitTwo) {
    const auto dir = test::temp_dir();
    // With no EGL vendor library glvnd has no driver to offer: what a machine without Mesa sees.
    const test::CommandResult r =
        test::run_command("__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json " + test::foldcast_binary() + " preview " +
                          tiny_scene(dir).string() + " -o " + (dir / "p.png").string() + " 2>&1");
    const std::string& err = r.out;
    EXPECT_EQ(r.exit_code, 2) << err;
    EXPECT_NE(err.find("EGL"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_FALSE(fs::exists(dir / "p.png"));
}

TEST(PreviewCli, TurntablePreviewWritesEveryFrame) {
    const auto dir = test::temp_dir();
    const test::CommandResult r = foldcast("turntable " + tiny_scene(dir).string() + " -o " +
                                           (dir / "frames").string() + "/ --frames 5 --preview --quiet 2>&1");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    for (int f = 0; f < 5; ++f)
        EXPECT_TRUE(fs::exists(dir / "frames" / ("frame_000" + std::to_string(f) + ".png"))) << f;
    EXPECT_FALSE(fs::exists(dir / "frames" / "frame_0005.png"));
}

std::set<std::pair<std::string, std::string>> outputs(const std::string& json_text) {
    std::set<std::pair<std::string, std::string>> set;
    for (const auto& o : nlohmann::json::parse(json_text))
        set.insert({o["path"].get<std::string>(), o["sha256"].get<std::string>()});
    return set;
}

TEST(BatchCli, ShardsTogetherRenderExactlyTheUnshardedCatalogue) {
    const auto dir = test::temp_dir();
    tiny_scene(dir);
    const std::string manifest =
        "width = 40\nheight = 30\nspp = 2\nlooks = [\"denim\", \"chiffon\"]\n"
        "[[garments]]\nname = \"cloth\"\nscene = \"tiny.toml\"\n"
        "[[views]]\nname = \"front\"\n[[views]]\nname = \"side\"\nazimuth_deg = 60\n";
    std::ofstream(dir / "whole.toml") << "output_dir = \"whole\"\n" << manifest;
    std::ofstream(dir / "split.toml") << "output_dir = \"split\"\n" << manifest;
    const std::string whole_toml = (dir / "whole.toml").string();
    const test::CommandResult whole = foldcast("batch " + whole_toml + " --json --threads 2");
    ASSERT_EQ(whole.exit_code, 0) << whole.out;
    std::set<std::pair<std::string, std::string>> split;
    for (int i = 0; i < 3; ++i) {
        const test::CommandResult shard = foldcast("batch " + (dir / "split.toml").string() +
                                                   " --json --threads 1 --shard " + std::to_string(i) + "/3");
        ASSERT_EQ(shard.exit_code, 0) << shard.out;
        for (const auto& o : outputs(shard.out)) split.insert(o);
    }
    EXPECT_EQ(outputs(whole.out).size(), 4u);
    EXPECT_EQ(outputs(whole.out), split);

    // A second run finds every output finished and verified, and renders nothing.
    const test::CommandResult again = foldcast("batch " + whole_toml + " --json");
    ASSERT_EQ(again.exit_code, 0);
    for (const auto& o : nlohmann::json::parse(again.out)) EXPECT_TRUE(o["skipped"].get<bool>());

    const test::CommandResult bad = foldcast("batch " + whole_toml + " --shard 3/3 2>&1");
    EXPECT_EQ(bad.exit_code, 2) << bad.out;
}

}  // namespace
}  // namespace foldcast
