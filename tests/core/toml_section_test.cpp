// The one TOML reader: types, ranges, unknown keys and where each message points.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "foldcast/core/error.hpp"
#include "foldcast/core/toml_section.hpp"

namespace foldcast {
namespace {

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(TomlSection, ReadsTypedValuesAndDefaultsStayUnset) {
    const toml::table t = toml::parse("x = 2\ny = 0.5\nflag = true\nname = \"a\"\nv = [1, 2.5, 3]\nn = [4, 5]\n");
    TomlSection s(t, "sec", "f.toml");
    EXPECT_EQ(*s.number("x", {0.0, 10.0}), 2.0);  // integers are numbers
    EXPECT_EQ(*s.number("y", {0.0, 1.0}), 0.5);
    EXPECT_TRUE(*s.boolean("flag"));
    EXPECT_EQ(*s.string("name"), "a");
    EXPECT_EQ((*s.numbers("v", 3, {-10.0, 10.0}))[1], 2.5);
    EXPECT_EQ((*s.integers("n", 2, 0, 10))[1], 5);
    EXPECT_FALSE(s.number("absent", {0.0, 1.0}).has_value());
    EXPECT_NO_THROW(s.finish());
}

TEST(TomlSection, WrongTypesAndRangesNameFileLineKeyAndAllowed) {
    const toml::table t = toml::parse("a = 1\nb = \"wide\"\ngrid = [16.5, 24]\nc = nan\n");
    TomlSection s(t, "output", "scene.toml");
    std::string m = message_of([&] { s.number("a", {2.0, 3.0, false, true, "mm"}); });
    EXPECT_NE(m.find("scene.toml:1: output.a = 1 is out of range: allowed (2, 3] mm"), std::string::npos) << m;
    m = message_of([&] { s.integer("b", 1, 5); });
    EXPECT_NE(m.find("scene.toml:2: output.b = \"wide\" has the wrong type: expected an integer"), std::string::npos)
        << m;
    m = message_of([&] { s.integers("grid", 2, 2, 4096); });
    EXPECT_NE(m.find("output.grid"), std::string::npos) << m;
    EXPECT_NE(m.find("integers"), std::string::npos) << m;
    m = message_of([&] { s.number("c", {0.0, 1.0}); });
    EXPECT_NE(m.find("output.c = nan is out of range"), std::string::npos) << m;
}

TEST(TomlSection, UnknownKeysListTheAllowedOnesInOrder) {
    const toml::table t = toml::parse("width = 3\nwidht = 4\n");
    TomlSection s(t, "output", "scene.toml");
    s.integer("width", 1, 10);
    s.integer("height", 1, 10);
    const std::string m = message_of([&] { s.finish(); });
    EXPECT_NE(m.find("scene.toml:2: unknown key 'output.widht'; allowed in [output]: width, height"), std::string::npos)
        << m;
    TomlSection early(t, "", "f.toml");
    EXPECT_THROW(early.check_keys({"width"}), InputError);  // before any value is read
}

TEST(TomlSection, ChoicesColoursAndPaths) {
    const toml::table t = toml::parse("kind = \"hook\"\nc = \"#ff0000\"\nd = [0.2, 1.5, 0.1]\np = \"sub/x.obj\"\n");
    TomlSection s(t, "supports", "/data/scene.toml");
    const std::string m = message_of([&] { s.choice("kind", {"rod", "clips", "none"}); });
    EXPECT_NE(m.find("is not allowed: use one of rod, clips, none"), std::string::npos) << m;
    EXPECT_FLOAT_EQ((*s.colour("c")).x(), 1.0f);
    EXPECT_THROW(s.colour("d"), InputError);
    EXPECT_EQ(*s.path("p"), std::filesystem::path("/data/sub/x.obj"));
}

TEST(TomlSection, ReadTomlFileRejectsMissingFilesDirectoriesAndBadSyntax) {
    const auto dir = std::filesystem::temp_directory_path() / "foldcast_toml_section_test";
    std::filesystem::create_directories(dir);
    std::string m = message_of([&] { read_toml_file(dir, "scene file"); });
    EXPECT_NE(m.find("is not a file"), std::string::npos) << m;
    m = message_of([&] { read_toml_file(dir / "none.toml", "scene file"); });
    EXPECT_NE(m.find("does not exist"), std::string::npos) << m;
    std::ofstream(dir / "bad.toml") << "a = 1\nb = = 2\n";
    m = message_of([&] { read_toml_file(dir / "bad.toml", "scene file"); });
    EXPECT_NE(m.find("bad.toml:2: not valid TOML"), std::string::npos) << m;
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace foldcast
