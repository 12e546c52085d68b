// Conventions every subcommand follows: bad flag values are named by the flag (the libraries
// name their own parameters; app maps them), a look may be a file, and progress written to a
// log is a few lines, not thousands of carriage returns.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "run_command.hpp"
#include "test_paths.hpp"

namespace fs = std::filesystem;
using foldcast::test::foldcast_binary;
using foldcast::test::run_command;

namespace {

fs::path fresh_dir(const std::string& name) {
    const fs::path dir = foldcast::test::temp_dir() / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string read(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

TEST(CliConventions, BadValuesAreNamedByTheirFlag) {
    const fs::path dir = fresh_dir("cli_flags");
    const std::string err = (dir / "err.txt").string();
    const std::string scene = std::string(FOLDCAST_SOURCE_DIR) + "/gallery/default.toml";
    struct Case {
        std::string args, flag;
    };
    const std::string pc2 = std::string(FOLDCAST_TEST_DATA) + "/animations/basicCloth.pc2";
    for (const Case& c :
         {Case{"render " + scene + " -o x.png --aov albedo,shadow", "--aov"},
          Case{"preview " + scene + " -o x.png --aov albedo", "--aov"},
          Case{"encode " + pc2 + " -o x.fca --profile fast", "--profile"},
          Case{"encode " + pc2 + " -o x.fca --max-error-m -1", "--max-error-m"},
          Case{"batch " + std::string(FOLDCAST_SOURCE_DIR) + "/gallery/catalogue.toml --shard 3/2", "--shard"}}) {
        const auto r =
            run_command("cd '" + dir.string() + "' && " + foldcast_binary() + " " + c.args + " 2> '" + err + "'");
        EXPECT_EQ(r.exit_code, 2) << c.args;
        const std::string message = read(err);
        EXPECT_NE(message.find(c.flag), std::string::npos) << c.args << ": " << message;
    }
}

TEST(CliConventions, LookMayBeAFile) {
    const fs::path dir = fresh_dir("cli_look_file");
    std::ifstream in(std::string(FOLDCAST_SOURCE_DIR) + "/looks/data/linen.toml");
    std::stringstream text;
    text << in.rdbuf();
    std::string look = text.str();
    const auto at = look.find("thickness_mm");
    ASSERT_NE(at, std::string::npos);
    look.replace(at, look.find('\n', at) - at, "thickness_mm = 0.123");
    std::ofstream(dir / "mine.toml") << look;
    const auto r =
        run_command("cd '" + dir.string() + "' && " + foldcast_binary() + " drape --quiet --look ./mine.toml --json");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NEAR(nlohmann::json::parse(r.out)["cloth"]["thickness_m"].get<double>(), 0.123e-3, 1e-12);
    const auto missing =
        run_command("cd '" + dir.string() + "' && " + foldcast_binary() + " drape --quiet --look ./nope.toml 2>&1");
    EXPECT_EQ(missing.exit_code, 2);
    EXPECT_NE(missing.out.find("look file"), std::string::npos) << missing.out;
}

TEST(CliConventions, ProgressToALogIsALinePerTenPercent) {
    const fs::path dir = fresh_dir("cli_progress");
    const auto r = run_command("cd '" + dir.string() + "' && " + foldcast_binary() +
                               " drape --grid 16x16 --frames 200 -o anim.pc2 2> log.txt");
    ASSERT_EQ(r.exit_code, 0);
    const std::string log = read(dir / "log.txt");
    EXPECT_EQ(log.find('\r'), std::string::npos) << log;
    int lines = 0;
    for (char c : log) lines += c == '\n';
    EXPECT_GT(lines, 0);
    EXPECT_LE(lines, 40) << log;  // 11 per stage at most, a few stages
}

}  // namespace
