// foldcast batch as a render farm sees it, through the binary: a line per job in a log
// (stderr not a terminal), --status across shards, and a changed shard count refused.
#include <gtest/gtest.h>

#include <fstream>

#include "run_command.hpp"
#include "test_paths.hpp"

namespace foldcast {
namespace {
namespace fs = std::filesystem;

test::CommandResult foldcast(const std::string& arguments) {
    return test::run_command(test::foldcast_binary() + " " + arguments);
}

// Blender's cloth cache frame as the garment; 4 images of 40x30 pixels at 2 spp.
fs::path tiny_catalogue(const fs::path& dir) {
    std::ofstream(dir / "tiny.toml") << "[garment]\npath = \"" << test::test_data("animations/basicCloth.obj").string()
                                     << "\"\nscale = 0.1\n";
    std::ofstream(dir / "catalogue.toml") << "output_dir = \"out\"\nwidth = 40\nheight = 30\nspp = 2\n"
                                             "looks = [\"denim\", \"chiffon\"]\n"
                                             "[[garments]]\nname = \"cloth\"\nscene = \"tiny.toml\"\n"
                                             "[[views]]\nname = \"front\"\n[[views]]\nname = \"side\"\n"
                                             "azimuth_deg = 60\n";
    return dir / "catalogue.toml";
}

bool has_line(const std::string& text, const std::string& prefix) {
    return text.find("\n" + prefix) != std::string::npos || text.rfind(prefix, 0) == 0;
}

TEST(BatchFarmCli, LogsALinePerJobAndSummarisesTheShards) {
    const auto dir = test::temp_dir();
    const std::string manifest = tiny_catalogue(dir).string();
    // stderr into the pipe: no terminal, as in a Slurm log.
    const test::CommandResult first = foldcast("batch " + manifest + " --shard 1/2 --threads 1 2>&1");
    ASSERT_EQ(first.exit_code, 0) << first.out;
    EXPECT_TRUE(has_line(first.out, "shard 1/2: 2 of the catalogue's 4 jobs, images in ")) << first.out;
    EXPECT_TRUE(has_line(first.out, "shard 1/2: job 1 of 2 rendered in ")) << first.out;
    EXPECT_TRUE(has_line(first.out, "shard 1/2: job 2 of 2 rendered in ")) << first.out;
    EXPECT_NE(first.out.find(" s: cloth/chiffon/side.png\n"), std::string::npos) << first.out;
    EXPECT_EQ(first.out.find('\r'), std::string::npos) << "a terminal bar in a log";
    EXPECT_EQ(first.out.find("batch 10%"), std::string::npos) << first.out;

    const test::CommandResult status = foldcast("batch " + manifest + " --status");
    ASSERT_EQ(status.exit_code, 0) << status.out;
    EXPECT_NE(status.out.find("catalogue.toml: 2 of 4 images finished (50%), 2 to do, in "), std::string::npos)
        << status.out;
    EXPECT_TRUE(has_line(status.out, "shard 0/2: 0 of 2 finished\n")) << status.out;
    EXPECT_TRUE(has_line(status.out, "shard 1/2: 2 of 2 finished, outputs-1-of-2.json written\n")) << status.out;
    EXPECT_TRUE(has_line(status.out, "shards with work left: 0 (of 2)\n")) << status.out;
    EXPECT_FALSE(fs::exists(dir / "out" / "cloth" / "denim" / "front.png")) << "--status rendered";

    const test::CommandResult again = foldcast("batch " + manifest + " --shard 1/2 2>&1");
    EXPECT_TRUE(has_line(again.out, "shard 1/2: job 2 of 2 already finished: cloth/chiffon/side.png\n")) << again.out;
    const test::CommandResult quiet = foldcast("batch " + manifest + " --shard 1/2 --quiet 2>&1");
    EXPECT_EQ(quiet.out, "");
}

// On a terminal (util-linux's script gives foldcast one): the bar, not the log lines.
TEST(BatchFarmCli, DrawsABarOnATerminal) {
    if (test::run_command("command -v script >/dev/null").exit_code != 0) GTEST_SKIP() << "no script (bsdutils)";
    const auto dir = test::temp_dir();
    const std::string manifest = tiny_catalogue(dir).string();
    const test::CommandResult tty =
        test::run_command("script -qec '" + test::foldcast_binary() + " batch " + manifest + " --shard 0/2' /dev/null");
    ASSERT_EQ(tty.exit_code, 0) << tty.out;
    EXPECT_NE(tty.out.find("\rbatch      [####################                    ]  50%"), std::string::npos)
        << tty.out;
    EXPECT_NE(tty.out.find("] 100%"), std::string::npos) << tty.out;
    EXPECT_EQ(tty.out.find("job 1 of 2"), std::string::npos) << tty.out;
}

TEST(BatchFarmCli, AnotherShardCountIsExitTwoAndSaysWhatToDo) {
    const auto dir = test::temp_dir();
    const std::string manifest = tiny_catalogue(dir).string();
    ASSERT_EQ(foldcast("batch " + manifest + " --shard 0/2 --quiet").exit_code, 0);
    const test::CommandResult changed = foldcast("batch " + manifest + " --shard 0/3 2>&1");
    EXPECT_EQ(changed.exit_code, 2) << changed.out;
    EXPECT_NE(changed.out.find("foldcast: shard 0/3: '" + (dir / "out").string() +
                               "' holds outputs-*-of-2.json, so this catalogue was split into 2 shards, not 3"),
              std::string::npos)
        << changed.out;
    EXPECT_NE(changed.out.find("run its shards 0..1/2"), std::string::npos) << changed.out;
    EXPECT_EQ(changed.out.find("of the catalogue's"), std::string::npos) << "a start line before the refusal";
    EXPECT_FALSE(fs::exists(dir / "out" / "outputs-0-of-3.json"));
    // The unsharded run that completes a catalogue is always allowed.
    EXPECT_EQ(foldcast("batch " + manifest + " --quiet").exit_code, 0);
    EXPECT_NE(foldcast("batch " + manifest + " --status").out.find(": 4 of 4 images finished (100%), 0 to do"),
              std::string::npos);
}

}  // namespace
}  // namespace foldcast
