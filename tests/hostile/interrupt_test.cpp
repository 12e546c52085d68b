// Issue #17 items 1 and 2: SIGINT or SIGTERM at any moment of a write leaves every output of
// the command old or every one new (never a mix), and no temporary file behind.  Each case
// runs the real foldcast once to time it, then interrupts it at spread-out moments of that
// time; what is checked holds whatever moment the signal lands on.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "run_command.hpp"
#include "spawn.hpp"
#include "test_paths.hpp"

namespace foldcast {
namespace {
namespace fs = std::filesystem;
using Files = std::map<std::string, std::string>;  // file name -> bytes

std::string bytes_of(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Every regular file under `dir` (names relative to it).
Files snapshot(const fs::path& dir) {
    Files files;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = bytes_of(e.path());
    return files;
}

void restore(const fs::path& dir, const Files& files) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const auto& [name, bytes] : files) {
        fs::create_directories((dir / name).parent_path());
        std::ofstream(dir / name, std::ios::binary) << bytes;
    }
}

std::vector<std::string> foldcast(std::vector<std::string> args) {
    args.insert(args.begin(), test::foldcast_under_test());
    return args;
}

std::string names(const Files& files) {
    std::string list;
    for (const auto& [name, bytes] : files) list += " " + name;
    return list;
}

// Runs `args` (writing into `dir`) with `old_files` in place, interrupted at `trials` moments
// spread over its uninterrupted run time; after each, the files in `dir` must be exactly
// `old_files` or exactly what an uninterrupted run leaves.  Prints how many trials ended with
// each (a log of how often the signal landed after the commit).
void expect_all_old_or_all_new(const fs::path& dir, const Files& old_files, const std::vector<std::string>& args,
                               int trials) {
    restore(dir, old_files);
    const test::Outcome full = test::run_child(foldcast(args), dir.parent_path() / "stderr.txt");
    ASSERT_TRUE(full.exited && full.exit_code == 0) << full.err;
    const Files new_files = snapshot(dir);
    ASSERT_NE(new_files, old_files) << "the command must change its outputs for this test to mean anything";
    int old_seen = 0, new_seen = 0;
    for (int k = 0; k < trials; ++k) {
        restore(dir, old_files);
        // Outputs are written at the end of a run: most moments fall in its second half.
        const double fraction = 0.3 + 0.75 * (k + 0.5) / trials;
        const auto delay = std::chrono::microseconds(static_cast<long long>(full.seconds * 1e6 * fraction));
        const int sig = k % 2 == 0 ? SIGINT : SIGTERM;
        const test::Outcome o = test::interrupt_after(foldcast(args), dir.parent_path() / "stderr.txt", delay, sig);
        const Files now = snapshot(dir);
        if (now == old_files)
            ++old_seen;
        else if (now == new_files)
            ++new_seen;
        else
            ADD_FAILURE() << "signal " << sig << " after " << delay.count() << " us left a mix: files" << names(now)
                          << " (old:" << names(old_files) << "; new:" << names(new_files) << ")";
        EXPECT_TRUE(o.signal == sig || (o.exited && o.exit_code == 0))
            << "exit " << o.exit_code << " signal " << o.signal << ": " << o.err;
    }
    std::printf("%d trials: %d left the old files, %d the new ones\n", trials, old_seen, new_seen);
}

TEST(Interrupt, DecodeReplacesPc2AndObjTogether) {
    const auto dir = test::temp_dir();
    const fs::path out = dir / "out";
    fs::create_directories(out);
    ASSERT_EQ(test::run_command(test::foldcast_under_test() + " drape -q --grid 8x8 --frames 4 -o " +
                                (out / "anim.pc2").string() + " >/dev/null 2>&1")
                  .exit_code,
              0);
    const Files old_files = snapshot(out);
    ASSERT_EQ(test::run_command(test::foldcast_under_test() + " drape -q --grid 128x128 --frames 24 -o " +
                                (dir / "big.fca").string() + " >/dev/null 2>&1")
                  .exit_code,
              0);
    expect_all_old_or_all_new(out, old_files, {"decode", (dir / "big.fca").string(), "-o", (out / "anim.pc2").string()},
                              12);
}

TEST(Interrupt, DrapeReplacesPc2AndObjTogether) {
    const auto dir = test::temp_dir();
    const fs::path out = dir / "out";
    fs::create_directories(out);
    ASSERT_EQ(test::run_command(test::foldcast_under_test() + " drape -q --grid 8x8 --frames 4 -o " +
                                (out / "anim.pc2").string() + " >/dev/null 2>&1")
                  .exit_code,
              0);
    expect_all_old_or_all_new(out, snapshot(out),
                              {"drape", "-q", "--grid", "96x96", "--frames", "16", "-o", (out / "anim.pc2").string()},
                              10);
}

TEST(Interrupt, RenderReplacesTheImageAndItsAovsTogether) {
    const auto dir = test::temp_dir();
    const std::string scene = std::string(FOLDCAST_SOURCE_DIR) + "/gallery/default.toml";
    for (const char* ext : {".png", ".exr"}) {
        const fs::path out = dir / (std::string("out") + (ext + 1));
        fs::create_directories(out);
        const std::string target = (out / (std::string("still") + ext)).string();
        const std::vector<std::string> common = {"render",
                                                 scene,
                                                 "-o",
                                                 target,
                                                 "--quiet",
                                                 "--width",
                                                 "64",
                                                 "--height",
                                                 "48",
                                                 "--spp",
                                                 "2",
                                                 "--aov",
                                                 "albedo,normal,depth,fold",
                                                 "--seed"};
        auto with_seed = [&](const char* seed) {
            auto args = common;
            args.push_back(seed);
            return args;
        };
        ASSERT_TRUE(test::run_child(foldcast(with_seed("1")), dir / "stderr.txt").exit_code == 0);
        expect_all_old_or_all_new(out, snapshot(out), with_seed("2"), 10);
    }
}

TEST(Interrupt, TurntableReplacesFramesAndVideoTogether) {
    const auto dir = test::temp_dir();
    const fs::path out = dir / "out";
    fs::create_directories(out);
    const std::string scene = std::string(FOLDCAST_SOURCE_DIR) + "/gallery/default.toml";
    auto args = [&](const char* spp) {
        return std::vector<std::string>{"turntable", scene,      "-o", (out / "spin.mp4").string(),
                                        "--quiet",   "--frames", "3",  "--width",
                                        "32",        "--height", "32", "--spp",
                                        spp};
    };
    ASSERT_TRUE(test::run_child(foldcast(args("1")), dir / "stderr.txt").exit_code == 0);
    expect_all_old_or_all_new(out, snapshot(out), args("3"), 8);
    // The temporal filter holds traced frames in memory and writes in the same transaction.
    std::vector<std::string> temporal = args("2");
    temporal.insert(temporal.end(), {"--denoise", "--temporal"});
    expect_all_old_or_all_new(out, snapshot(out), temporal, 8);
    // A shorter turntable over a longer one: the old frames past its count go in the same
    // interrupt-protected commit, never leaving old frames 3-4 beside the new 0-2.
    std::vector<std::string> longer = args("1");
    longer[6] = "5";
    ASSERT_TRUE(test::run_child(foldcast(longer), dir / "stderr.txt").exit_code == 0);
    ASSERT_TRUE(fs::exists(out / "spin_frames" / "frame_0004.png"));
    expect_all_old_or_all_new(out, snapshot(out), args("2"), 8);
    ASSERT_TRUE(test::run_child(foldcast(args("2")), dir / "stderr.txt").exit_code == 0);
    EXPECT_FALSE(fs::exists(out / "spin_frames" / "frame_0004.png"));
}

// Commands that write one file or a resumable set: no temporary may survive an interrupt,
// and a resumed batch finishes every image.
TEST(Interrupt, EncodeAndBatchLeaveNoTemporaries) {
    const auto dir = test::temp_dir();
    const std::vector<std::string> encode = {"encode", test::test_data("animations/basicCloth.pc2").string(), "-o",
                                             (dir / "cloth.fca").string()};
    const std::string manifest = (dir / "catalogue.toml").string();
    std::ofstream(manifest)
        << "output_dir = \"cat\"\nwidth = 32\nheight = 32\nspp = 1\nlooks = [\"linen\", \"denim\"]\n"
           "[[garments]]\nname = \"panel\"\nscene = \""
        << FOLDCAST_SOURCE_DIR << "/gallery/default.toml\"\n";
    const std::vector<std::string> batch = {"batch", manifest, "--quiet"};
    for (const auto& args : {encode, batch}) {
        const test::Outcome full = test::run_child(foldcast(args), dir / "stderr.txt");
        ASSERT_EQ(full.exit_code, 0) << full.err;
        for (int k = 0; k < 8; ++k) {
            fs::remove_all(dir / "cat");
            fs::remove(dir / "cloth.fca");
            const auto delay = std::chrono::microseconds(static_cast<long long>(full.seconds * 1e6 * (k + 0.5) / 8));
            test::interrupt_after(foldcast(args), dir / "stderr.txt", delay, k % 2 == 0 ? SIGINT : SIGTERM);
            for (const auto& e : fs::recursive_directory_iterator(dir))
                EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos)
                    << e.path() << " after " << delay.count() << " us";
        }
    }
    const test::Outcome resumed = test::run_child(foldcast(batch), dir / "stderr.txt");
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    for (const char* look : {"linen", "denim"}) {
        EXPECT_TRUE(fs::exists(dir / "cat" / "panel" / look / "front.png.sha256")) << look;
    }
    for (const auto& e : fs::recursive_directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

}  // namespace
}  // namespace foldcast
