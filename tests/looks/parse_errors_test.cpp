// Invalid look files are errors naming the file, key, value and what is allowed.
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include <fstream>
#include <string>

#include "foldcast/core/error.hpp"
#include "foldcast/looks/looks.hpp"

namespace fs = std::filesystem;
using foldcast::InputError;
using namespace foldcast::looks;

namespace {

const char* kOrigin = "mem/test_look.toml";

// A valid look; `extra_mechanics` / `extra_appearance` lines are appended to their tables
// (TOML forbids duplicate keys, so tests replace a key by leaving it out of the base).
std::string look_text(const std::string& mechanics, const std::string& appearance, const std::string& top = "") {
    return top + "description = \"test\"\n[mechanics]\n" + mechanics + "\n[appearance]\nweave = \"plain\"\n" +
           appearance + "\n";
}
const std::string kMechanics = "thickness_mm = 0.3\nyoung_mpa = 5.0\ngsm = 150\n";
const std::string kAppearance = "base_colour = \"#808080\"\n";

Look parse_text(const std::string& text) {
    return parse_look(toml::parse(std::string_view(text), std::string_view(kOrigin)), "test_look", kOrigin);
}

// Parsing must throw InputError whose message names the file and contains every fragment.
void expect_error(const std::string& text, std::initializer_list<const char*> fragments) {
    try {
        parse_text(text);
        ADD_FAILURE() << "no error for:\n" << text;
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find(kOrigin), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
        for (const char* fragment : fragments)
            EXPECT_NE(message.find(fragment), std::string::npos) << "'" << fragment << "' missing from: " << message;
    }
}

std::string mechanics_with(const std::string& line) {
    return look_text("young_mpa = 5.0\ngsm = 150\npoisson = 0.3\nthickness_mm = 0.3\n" + line, kAppearance);
}

}  // namespace

TEST(LookParse, MinimalLookParsesWithDefaults) {
    const Look look = parse_text(look_text(kMechanics, kAppearance));
    EXPECT_DOUBLE_EQ(look.mechanics.thickness_mm, 0.3);
    EXPECT_DOUBLE_EQ(look.mechanics.poisson, 0.3);
    EXPECT_DOUBLE_EQ(look.mechanics.load_constant, default_load_constant());
    EXPECT_NEAR(look.appearance.base_colour.x(), 0.2159f, 1e-3f);  // sRGB 128 -> linear
}

TEST(LookParse, LinearTripleAndIntegersAreAccepted) {
    const Look look =
        parse_text(look_text("thickness_mm = 1\nyoung_mpa = 2\ngsm = 100\n", "base_colour = [0.25, 0.5, 1]\n"));
    EXPECT_DOUBLE_EQ(look.mechanics.thickness_mm, 1.0);
    EXPECT_FLOAT_EQ(look.appearance.base_colour.y(), 0.5f);
}

TEST(LookParse, WeightInNewtonsPerSquareMillimetreConvertsToGsm) {
    const Look look =
        parse_text(look_text("thickness_mm = 0.3\nyoung_mpa = 5\nweight_n_mm2 = 1.470997e-6\n", kAppearance));
    EXPECT_NEAR(look.mechanics.gsm, 150.0, 1e-3);
    expect_error(look_text(kMechanics + "weight_n_mm2 = 1e-6\n", kAppearance), {"gsm", "weight_n_mm2", "not both"});
}

TEST(LookParse, UnknownKeysAreNamedWithTheAllowedOnes) {
    expect_error(look_text(kMechanics, kAppearance, "colour = \"red\"\n"),
                 {"unknown key 'colour'", "description, mechanics, appearance"});
    expect_error(look_text(kMechanics + "thicknes_mm = 0.2\n", kAppearance),
                 {"unknown key 'mechanics.thicknes_mm'", "thickness_mm", ":6"});
    expect_error(look_text(kMechanics, kAppearance + "glossiness = 0.2\n"),
                 {"unknown key 'appearance.glossiness'", "roughness"});
}

TEST(LookParse, WrongTypesAreNamed) {
    expect_error(mechanics_with("gsm_x = 1"), {"unknown key 'mechanics.gsm_x'"});
    expect_error(look_text("thickness_mm = \"thin\"\nyoung_mpa = 5\ngsm = 150\n", kAppearance),
                 {"mechanics.thickness_mm", "\"thin\"", "wrong type", "number", "(0, 50] mm"});
    expect_error(look_text(kMechanics, "base_colour = 5\n"), {"appearance.base_colour", "wrong type", "#RRGGBB"});
    expect_error(look_text(kMechanics, kAppearance + "anisotropy_axis = 1\n"),
                 {"appearance.anisotropy_axis", "wrong type", "warp, weft"});
    expect_error("description = \"x\"\nmechanics = 3\n[appearance]\nweave=\"plain\"\n",
                 {"mechanics = 3", "wrong type", "table"});
    expect_error("description = 7\n[mechanics]\n" + kMechanics + "[appearance]\n" + kAppearance,
                 {"description = 7", "string"});
}

TEST(LookParse, ImpossibleMechanicsAreOutOfRange) {
    expect_error(look_text("thickness_mm = 0\nyoung_mpa = 5\ngsm = 150\n", kAppearance),
                 {"mechanics.thickness_mm = 0", "out of range", "(0, 50] mm"});
    expect_error(look_text("thickness_mm = -0.2\nyoung_mpa = 5\ngsm = 150\n", kAppearance),
                 {"mechanics.thickness_mm = -0.2", "(0, 50] mm"});
    expect_error(look_text("thickness_mm = nan\nyoung_mpa = 5\ngsm = 150\n", kAppearance),
                 {"mechanics.thickness_mm = nan"});
    expect_error(look_text("thickness_mm = 0.3\nyoung_mpa = 5\ngsm = 0\n", kAppearance),
                 {"mechanics.gsm = 0", "(0, 5000] g/m^2"});
    expect_error(look_text("thickness_mm = 0.3\nyoung_mpa = -5\ngsm = 10\n", kAppearance),
                 {"mechanics.young_mpa = -5", "MPa"});
    expect_error(look_text(kMechanics + "poisson = 0.5\n", kAppearance), {"mechanics.poisson = 0.5", "(-1, 0.5)"});
    expect_error(look_text(kMechanics + "poisson = -1\n", kAppearance), {"mechanics.poisson = -1", "(-1, 0.5)"});
    expect_error(look_text(kMechanics + "load_constant = 0\n", kAppearance), {"mechanics.load_constant = 0"});
}

TEST(LookParse, ImpossibleAppearanceIsOutOfRange) {
    expect_error(look_text(kMechanics, kAppearance + "roughness = 1.1\n"), {"appearance.roughness = 1.1", "[0, 1]"});
    expect_error(look_text(kMechanics, kAppearance + "roughness = -0.1\n"), {"appearance.roughness = -0.1", "[0, 1]"});
    expect_error(look_text(kMechanics, kAppearance + "sheen_roughness = 2\n"),
                 {"appearance.sheen_roughness = 2", "[0, 1]"});
    expect_error(look_text(kMechanics, kAppearance + "specular = 3\n"), {"appearance.specular = 3", "[0, 1]"});
    expect_error(look_text(kMechanics, kAppearance + "anisotropy = 1.0\n"), {"appearance.anisotropy = 1.0", "[0, 1)"});
    expect_error(look_text(kMechanics, kAppearance + "repeat_mm = 0\n"), {"appearance.repeat_mm = 0", "(0, 1000] mm"});
    expect_error(look_text(kMechanics, kAppearance + "bump_strength = -1\n"),
                 {"appearance.bump_strength = -1", "[0, 10]"});
    expect_error(look_text(kMechanics, "base_colour = [0.2, 1.5, 0.1]\n"), {"appearance.base_colour", "1.5", "[0, 1]"});
    expect_error(look_text(kMechanics, "base_colour = [0.2, 0.5]\n"), {"appearance.base_colour", "wrong type"});
    expect_error(look_text(kMechanics, "base_colour = \"#12345g\"\n"),
                 {"appearance.base_colour = \"#12345g\"", "not a colour"});
    expect_error(look_text(kMechanics, kAppearance + "sheen_colour = \"red\"\n"),
                 {"appearance.sheen_colour", "not a colour"});
}

TEST(LookParse, ChoicesListWhatIsAllowed) {
    expect_error(look_text(kMechanics, kAppearance)
                     .replace(look_text(kMechanics, kAppearance).find("\"plain\""), 7, "\"herringbone\""),
                 {"appearance.weave = \"herringbone\"", "none, plain, twill, satin, knit"});
    expect_error(look_text(kMechanics, kAppearance + "anisotropy_axis = \"bias\"\n"),
                 {"appearance.anisotropy_axis = \"bias\"", "warp, weft"});
    expect_error(look_text(kMechanics, kAppearance + "twill_float = 4\n"), {"appearance.twill_float = 4", "[2, 3]"});
    expect_error(look_text(kMechanics, kAppearance + "twill_float = 2.5\n"),
                 {"appearance.twill_float", "2 (2/1 twill) or 3 (3/1 twill)"});
}

TEST(LookParse, MissingRequiredKeysAreNamed) {
    expect_error(look_text("young_mpa = 5\ngsm = 150\n", kAppearance), {"missing key 'mechanics.thickness_mm'"});
    expect_error(look_text("thickness_mm = 0.3\ngsm = 150\n", kAppearance), {"missing key 'mechanics.young_mpa'"});
    expect_error(look_text("thickness_mm = 0.3\nyoung_mpa = 5\n", kAppearance), {"missing key 'mechanics.gsm'"});
    expect_error("description = \"x\"\n[mechanics]\n" + kMechanics, {"missing key 'appearance'"});
    expect_error(look_text(kMechanics, ""), {"missing key 'appearance.base_colour'"});
}

TEST(LookParse, TexturePathsAreRelativeToTheLookFileAndMustExist) {
    const fs::path dir = fs::temp_directory_path() / "foldcast_looks_texture_test";
    fs::remove_all(dir);
    fs::create_directories(dir / "maps");
    std::ofstream(dir / "maps" / "weave.png") << "not really a png; existence is checked here";
    std::ofstream(dir / "textured.toml") << look_text(kMechanics, kAppearance + "texture = \"maps/weave.png\"\n");
    const Look look = load_look_file(dir / "textured.toml");
    EXPECT_EQ(look.name, "textured");
    EXPECT_EQ(look.appearance.texture, (dir / "maps" / "weave.png").lexically_normal());

    std::ofstream(dir / "missing.toml") << look_text(kMechanics, kAppearance + "normal_map = \"maps/none.png\"\n");
    try {
        load_look_file(dir / "missing.toml");
        ADD_FAILURE() << "missing normal map accepted";
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("missing.toml:"), std::string::npos) << message;
        EXPECT_NE(message.find("appearance.normal_map"), std::string::npos) << message;
        EXPECT_NE(message.find("no such file"), std::string::npos) << message;
    }
    fs::remove_all(dir);
}

TEST(LookParse, TomlSyntaxErrorsNameFileAndLine) {
    const fs::path file = fs::temp_directory_path() / "foldcast_broken_look.toml";
    std::ofstream(file) << "description = \"x\"\n[mechanics\nthickness_mm = 0.3\n";
    try {
        load_look_file(file);
        ADD_FAILURE() << "broken TOML accepted";
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find(file.string() + ":2:"), std::string::npos) << message;
        EXPECT_NE(message.find("not valid TOML"), std::string::npos) << message;
    }
    fs::remove(file);
    EXPECT_THROW(load_look_file("/nonexistent/look.toml"), InputError);
}
