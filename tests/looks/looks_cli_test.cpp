// `foldcast looks`: listing, JSON, show, and exit status 2 for input errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "run_command.hpp"

namespace fs = std::filesystem;

namespace {
// Runs the built foldcast with `arguments` (shell syntax), `environment` prefixed (VAR=value).
foldcast::test::CommandResult run(const std::string& arguments, const std::string& environment = "") {
    return foldcast::test::run_command(environment + " " + foldcast::test::foldcast_binary() + " " + arguments);
}
}  // namespace

TEST(LooksCli, ListsEveryLook) {
    const auto result = run("looks");
    ASSERT_EQ(result.exit_code, 0);
    for (const char* name : {"denim", "chiffon", "polyester_taffeta", "velvet"})
        EXPECT_NE(result.out.find(name), std::string::npos) << name;
}

TEST(LooksCli, JsonHasEveryLookWithItsValues) {
    const auto result = run("looks --json");
    ASSERT_EQ(result.exit_code, 0);
    const auto report = nlohmann::json::parse(result.out);
    ASSERT_GE(report["looks"].size(), 12u);
    for (const auto& look : report["looks"]) {
        EXPECT_TRUE(look.contains("name"));
        EXPECT_GT(look["mechanics"]["thickness_mm"].get<double>(), 0.0);
        EXPECT_TRUE(look["appearance"].contains("roughness"));
    }
}

TEST(LooksCli, ShowPrintsOneLook) {
    const auto toml_text = run("looks show denim");
    ASSERT_EQ(toml_text.exit_code, 0);
    EXPECT_NE(toml_text.out.find("weave = 'twill'"), std::string::npos) << toml_text.out;
    const auto json = run("looks show denim --json");
    ASSERT_EQ(json.exit_code, 0);
    EXPECT_EQ(nlohmann::json::parse(json.out)["name"], "denim");
}

TEST(LooksCli, InputErrorsExitTwo) {
    EXPECT_EQ(run("looks show nosuchlook 2>/dev/null").exit_code, 2);
    const fs::path dir = fs::temp_directory_path() / "foldcast_cli_bad_looks";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "bad.toml") << "description = \"x\"\n[mechanics]\nthickness_mm = -1\n"
                                       "young_mpa = 1\ngsm = 100\n[appearance]\nweave = \"plain\"\n"
                                       "base_colour = \"#ffffff\"\n";
    const auto bad = run("looks 2>&1", "FOLDCAST_LOOKS_DIR=" + dir.string());
    EXPECT_EQ(bad.exit_code, 2);
    const std::string& out = bad.out;
    EXPECT_NE(out.find("bad.toml:3: mechanics.thickness_mm = -1"), std::string::npos) << out;
    fs::remove_all(dir);
}
