// The generated battery: every value-taking flag of every subcommand (read from its --help,
// so a new flag is covered without editing this file) with the values a hostile user, or a
// typo, gives: 0, -1, nan, inf, 1e308, 2^31, 2^63, an empty string and a word.  Each run is
// the real foldcast under a CPU and memory cap; it must exit 0 or 2 (diff: idiff's 0-4) and
// never by a signal, refuse with a first line of ours ("foldcast: ...") that names the flag,
// print no library text, and leave no output behind when it refuses.  `serve` is left out: a value it accepts
// serves until a signal.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <fstream>
#include <mutex>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "run_command.hpp"
#include "battery.hpp"
#include "spawn.hpp"
#include "test_paths.hpp"

namespace foldcast {
namespace {
namespace fs = std::filesystem;

const std::vector<std::string> kValues = {"0",          "-1", "nan", "inf", "1e308", "2147483648", "9223372036854775808",
                                          "",           "abc"};
// 20 CPU seconds and 4 GiB: each base command below takes well under a second.
constexpr test::Limits kCap{20, 4ull << 30};

struct Command {
    std::string name;
    std::vector<std::string> base;     // after "foldcast NAME": a cheap run that succeeds
    std::vector<std::string> outputs;  // files it writes (relative to its own folder)
    std::vector<std::string> skip;     // flags not tried: outputs, given in the base already
};

// The value-taking flags --help lists ("  --width-m FLOAT=0.5 ...", "  -o,--output TEXT ...").
std::vector<std::string> value_flags(const std::string& command) {
    const auto help = test::run_command(test::foldcast_under_test() + " " + command + " --help");
    std::vector<std::string> flags;
    const std::regex option(R"(^\s+(?:-\w,)?(--[\w-]+)\s+(TEXT|FLOAT|INT|UINT)\b)");
    std::istringstream lines(help.out);
    for (std::string line; std::getline(lines, line);) {
        std::smatch m;
        if (std::regex_search(line, m, option)) flags.push_back(m[1]);
    }
    return flags;
}

class FlagBattery : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = test::temp_dir();
        const std::string source = FOLDCAST_SOURCE_DIR;
        write("tiny.toml", "[garment]\ngrid = [9, 9]\n[output]\nwidth = 16\nheight = 16\nspp = 1\n");
        write("batch.toml", "output_dir = \"cat\"\nwidth = 8\nheight = 8\nspp = 1\nlooks = [\"linen\"]\n"
                            "[[garments]]\nname = \"a\"\nscene = \"tiny.toml\"\n");
        std::string pfm = "Pf\n8 8\n-1.0\n";
        for (int i = 0; i < 64; ++i) pfm.append("\0\0\0\0", 4);
        write("a.pfm", pfm);
        write("b.pfm", pfm);
        const auto made = test::run_command(test::foldcast_under_test() + " drape --grid 5x5 --frames 3 -q -o " +
                                            (dir_ / "anim.pc2").string() + " > /dev/null && " +
                                            test::foldcast_under_test() + " encode " + (dir_ / "anim.pc2").string() +
                                            " -q -o " + (dir_ / "anim.fca").string());
        ASSERT_EQ(made.exit_code, 0);
        const std::string photo = test::test_data("photos/two_point_shirt_s3_half.jpg").string();
        const std::string supports = "197.5,50,357.5,48.5", d = dir_.string() + "/";
        commands_ = {
            {"drape", {"--grid", "5x5", "-q", "-o", "OUT.obj"}, {"OUT.obj"}, {"--output"}},
            {"looks", {"--swatches", "OUT.png", "--only", "linen", "--tile", "16x20", "--spp", "1", "-q"},
             {"OUT.png"}, {"--swatches"}},
            {"diff", {d + "a.pfm", d + "b.pfm", "-o", "OUT.png"}, {"OUT.png"}, {"--output"}},
            {"folds", {photo, "-o", "OUT.png", "--supports", supports}, {"OUT.png"}, {"--output"}},
            {"overlay", {photo, "-o", "OUT.png", "--supports", supports, "--scale-px-per-m", "400"}, {"OUT.png"},
             {"--output"}},
            {"encode", {d + "anim.pc2", "-q", "-o", "OUT.fca"}, {"OUT.fca"}, {"--output"}},
            {"decode", {d + "anim.fca", "-o", "OUT.pc2"}, {"OUT.pc2", "OUT.obj"}, {"--output"}},
            {"render", {d + "tiny.toml", "-o", "OUT.png", "--quiet"}, {"OUT.png"}, {"--output"}},
            {"turntable", {d + "tiny.toml", "-o", "OUT.mp4", "--frames", "2", "--quiet"}, {"OUT.mp4", "OUT_frames"},
             {"--output"}},
            {"preview", {d + "tiny.toml", "-o", "OUT.png", "--quiet"}, {"OUT.png"}, {"--output"}},
            {"batch", {d + "batch.toml", "--quiet"}, {"cat"}, {}},
        };
        (void)source;
    }
    void write(const std::string& name, const std::string& bytes) {
        std::ofstream(dir_ / name, std::ios::binary) << bytes;
    }
    fs::path dir_;
    std::vector<Command> commands_;
};

struct Case {
    const Command* command;
    std::string flag, value;
};

// Runs one case in a folder of its own; returns what is wrong with the outcome ("" if nothing).
std::string check(const Case& c, const fs::path& dir) {
    fs::create_directories(dir);
    std::vector<std::string> argv = {test::foldcast_under_test(), c.command->name};
    for (const std::string& a : c.command->base) {
        std::string arg = a;
        if (arg.rfind("OUT", 0) == 0) arg = (dir / arg).string();
        argv.push_back(arg);
    }
    // A manifest's output_dir is relative to the manifest: batch gets a copy in its folder.
    if (c.command->name == "batch") {
        fs::copy_file(argv[2], dir / "batch.toml");
        fs::copy_file(fs::path(argv[2]).parent_path() / "tiny.toml", dir / "tiny.toml");
        argv[2] = (dir / "batch.toml").string();
    }
    argv.push_back(c.flag);
    argv.push_back(c.value);
    std::string line;
    for (std::size_t i = 1; i < argv.size(); ++i) line += " '" + argv[i] + "'";
    const test::Outcome o = test::run_child(argv, dir / "stderr.txt", kCap);
    const bool idiff_codes = c.command->name == "diff";
    if (!o.exited) return line + ": killed by signal " + std::to_string(o.signal) + ": " + o.err;
    if (!(o.exit_code == 0 || o.exit_code == 2 || (idiff_codes && o.exit_code >= 0 && o.exit_code <= 4)))
        return line + ": exit " + std::to_string(o.exit_code) + ": " + o.err;
    for (const char* noise : {"[ WARN", "[ERROR", "TBB Warning", "terminate called", "filesystem error", "[mpeg4",
                              "std::bad_alloc", "what():"})
        if (o.err.find(noise) != std::string::npos) return line + ": library text on stderr: " + o.err;
    const bool refused = o.exit_code == 2 && !(idiff_codes && o.err.rfind("foldcast:", 0) != 0);
    if (refused) {
        if (o.err.rfind("foldcast:", 0) != 0) return line + ": the first line is not ours: " + o.err;
        // Only this flag differs from a run that succeeds: the refusal is about it, and says so
        // in the user's words (not an internal name such as young_pa or keep_fraction).
        const std::string first = o.err.substr(0, o.err.find('\n'));
        if (first.find(c.flag) == std::string::npos)
            return line + ": the first line does not name " + c.flag + ": " + first;
        if (test::longest_digit_run(first) > std::max<std::size_t>(24, test::longest_digit_run(c.value)))
            return line + ": the first line prints a number of " + std::to_string(test::longest_digit_run(first)) +
                   " digits: " + first;
        for (const std::string& out : c.command->outputs)
            if (fs::exists(dir / out)) return line + ": refused, yet " + out + " was written";
    }
    return {};
}

TEST_F(FlagBattery, EveryFlagOfEveryCommandTakesHostileValues) {
    std::vector<Case> cases;
    for (const Command& command : commands_) {
        const std::vector<std::string> flags = value_flags(command.name);
        ASSERT_FALSE(flags.empty()) << command.name << " --help lists no flags";
        for (const std::string& flag : flags) {
            if (std::find(command.skip.begin(), command.skip.end(), flag) != command.skip.end()) continue;
            for (const std::string& value : kValues) cases.push_back({&command, flag, value});
        }
    }
    const std::vector<std::string> failures = test::run_on_two_threads(cases.size(), [&](std::size_t i) {
        const std::string wrong = check(cases[i], dir_ / ("case" + std::to_string(i)));
        fs::remove_all(dir_ / ("case" + std::to_string(i)));
        return wrong;
    });
    std::cout << cases.size() << " cases, " << failures.size() << " failed\n";
    for (const std::string& f : failures) ADD_FAILURE() << f;
}

}  // namespace
}  // namespace foldcast
