// Sets that belong together, kept together.  A resumed batch re-renders an image whose look changed: a look read from FOLDCAST_LOOKS_DIR
// is a file the user edits, and its name alone kept the old image as finished.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "run_command.hpp"
#include "spawn.hpp"
#include "test_paths.hpp"

namespace foldcast {
namespace {
namespace fs = std::filesystem;

TEST(ResumedBatch, AnEditedLookFileIsRenderedAgain) {
    const fs::path dir = test::temp_dir();
    fs::copy(fs::path(FOLDCAST_SOURCE_DIR) / "looks/data", dir / "looks");
    std::ofstream(dir / "tiny.toml") << "[garment]\ngrid = [9, 9]\n";
    std::ofstream(dir / "m.toml") << "output_dir = \"cat\"\nwidth = 16\nheight = 16\nspp = 1\nlooks = [\"denim\"]\n"
                                     "[[garments]]\nname = \"a\"\nscene = \"tiny.toml\"\n";
    const std::string run = "FOLDCAST_LOOKS_DIR='" + (dir / "looks").string() + "' '" + test::foldcast_under_test() +
                            "' batch '" + (dir / "m.toml").string() + "' --quiet";
    ASSERT_EQ(test::run_command(run).exit_code, 0);
    EXPECT_NE(test::run_command(run + " --dry-run").out.find(" done "), std::string::npos);
    // The look's warp colour, edited in its file.
    const fs::path denim = dir / "looks" / "denim.toml";
    std::ifstream in(denim);
    std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    in.close();
    const std::size_t at = text.find("#2b3f66");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 7, "#802020");
    std::ofstream(denim) << text;
    const std::string listed = test::run_command(run + " --dry-run").out;
    EXPECT_NE(listed.find(" todo "), std::string::npos) << "the image of the old look is kept as finished: " << listed;
}

// A turntable of fewer frames than the last one into the same OUT_frames/: the earlier run's
// frames past the new count used to stay beside the new MP4 as if they were part of it.
TEST(Turntable, AShorterRunLeavesNoFramesOfTheLongerOne) {
    const fs::path dir = test::temp_dir();
    std::ofstream(dir / "tiny.toml") << "[garment]\ngrid = [9, 9]\n[output]\nwidth = 16\nheight = 16\nspp = 1\n";
    const std::string run = "'" + test::foldcast_under_test() + "' turntable '" + (dir / "tiny.toml").string() +
                            "' -o '" + (dir / "spin.mp4").string() + "' --quiet --frames ";
    ASSERT_EQ(test::run_command(run + "3").exit_code, 0);
    ASSERT_TRUE(fs::exists(dir / "spin_frames" / "frame_0002.png"));
    ASSERT_EQ(test::run_command(run + "2").exit_code, 0);
    EXPECT_TRUE(fs::exists(dir / "spin_frames" / "frame_0001.png"));
    EXPECT_FALSE(fs::exists(dir / "spin_frames" / "frame_0002.png")) << "a frame of the earlier run was left";
}

}  // namespace
}  // namespace foldcast
