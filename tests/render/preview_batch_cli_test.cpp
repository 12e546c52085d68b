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

// A tiny scene: Blender's cloth cache frame as the garment, 48x32 pixels, 2 spp.
// The command's stdout; *status gets its exit status.
std::string run(const std::string& command, int* status) {
    const test::CommandResult result = test::run_command(command);
    *status = result.exit_code;
    return result.out;
}

fs::path tiny_scene(const fs::path& dir) {
    std::ofstream(dir / "tiny.toml") << "[garment]\npath = \"" << test::test_data("animations/basicCloth.obj").string()
                                     << "\"\nscale = 0.1\n[output]\nwidth = 48\nheight = 32\nspp = 2\n";
    return dir / "tiny.toml";
}

TEST(PreviewCli, WritesTheImageAndItsDepth) {
    const auto dir = test::temp_dir();
    int status = -1;
    const std::string out = run(test::foldcast_binary() + " preview " + tiny_scene(dir).string() + " -o " +
                                                  (dir / "p.png").string() + " --aov depth --json 2>&1",
                                              &status);
    ASSERT_EQ(status, 0) << out;
    const auto report = nlohmann::json::parse(out);
    EXPECT_EQ(report["width"], 48);
    EXPECT_EQ(report["height"], 32);
    EXPECT_TRUE(fs::exists(dir / "p.png"));
    EXPECT_TRUE(fs::exists(dir / "p.depth.png"));
}

TEST(PreviewCli, NoEglIsOneLineAndExitTwo) {
    const auto dir = test::temp_dir();
    int status = -1;
    // With no EGL vendor library glvnd has no driver to offer: what a machine without Mesa sees.
    const std::string err = run("__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json " + test::foldcast_binary() +
                                                  " preview " + tiny_scene(dir).string() + " -o " +
                                                  (dir / "p.png").string() + " 2>&1",
                                              &status);
    EXPECT_EQ(status, 2) << err;
    EXPECT_NE(err.find("EGL"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_FALSE(fs::exists(dir / "p.png"));
}

TEST(PreviewCli, TurntablePreviewWritesEveryFrame) {
    const auto dir = test::temp_dir();
    int status = -1;
    const std::string out = run(test::foldcast_binary() + " turntable " + tiny_scene(dir).string() + " -o " +
                                                  (dir / "frames").string() + "/ --frames 5 --preview --quiet 2>&1",
                                              &status);
    ASSERT_EQ(status, 0) << out;
    for (int f = 0; f < 5; ++f) EXPECT_TRUE(fs::exists(dir / "frames" / ("frame_000" + std::to_string(f) + ".png"))) << f;
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
    const std::string manifest = "width = 40\nheight = 30\nspp = 2\nlooks = [\"denim\", \"chiffon\"]\n"
                                 "[[garments]]\nname = \"cloth\"\nscene = \"tiny.toml\"\n"
                                 "[[views]]\nname = \"front\"\n[[views]]\nname = \"side\"\nazimuth_deg = 60\n";
    std::ofstream(dir / "whole.toml") << "output_dir = \"whole\"\n" << manifest;
    std::ofstream(dir / "split.toml") << "output_dir = \"split\"\n" << manifest;
    int status = -1;
    const std::string whole = run(
        test::foldcast_binary() + " batch " + (dir / "whole.toml").string() + " --json --threads 2", &status);
    ASSERT_EQ(status, 0) << whole;
    std::set<std::pair<std::string, std::string>> split;
    for (int i = 0; i < 3; ++i) {
        const std::string shard = run(test::foldcast_binary() + " batch " + (dir / "split.toml").string() +
                                                        " --json --threads 1 --shard " + std::to_string(i) + "/3",
                                                    &status);
        ASSERT_EQ(status, 0) << shard;
        for (const auto& o : outputs(shard)) split.insert(o);
    }
    EXPECT_EQ(outputs(whole).size(), 4u);
    EXPECT_EQ(outputs(whole), split);

    // A second run finds every output finished and verified, and renders nothing.
    const std::string again = run(
        test::foldcast_binary() + " batch " + (dir / "whole.toml").string() + " --json", &status);
    ASSERT_EQ(status, 0);
    for (const auto& o : nlohmann::json::parse(again)) EXPECT_TRUE(o["skipped"].get<bool>());

    const std::string bad = run(
        test::foldcast_binary() + " batch " + (dir / "whole.toml").string() + " --shard 3/3 2>&1", &status);
    EXPECT_EQ(status, 2) << bad;
}

}  // namespace
}  // namespace foldcast
