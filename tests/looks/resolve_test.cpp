// Overriding single keys of a named look, as scene files and the command line do.
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include "foldcast/core/error.hpp"
#include "foldcast/looks/looks.hpp"
#include "shipped_looks.hpp"

using foldcast::InputError;
using namespace foldcast::looks;

namespace {
toml::table parse_toml(std::string_view text, std::string_view origin) { return toml::parse(text, origin); }

}  // namespace

TEST(LookOverride, ReplacesOnlyTheGivenKeys) {
    const Look& denim = foldcast::test::shipped_looks().get("denim");
    const toml::table overrides =
        parse_toml("[appearance]\nbase_colour = \"#000000\"\n[mechanics]\ngsm = 300\n", "scene.toml");
    const Look black = override_look(denim, overrides, "scene.toml");
    EXPECT_EQ(black.name, "denim");
    EXPECT_DOUBLE_EQ(black.mechanics.gsm, 300.0);
    EXPECT_DOUBLE_EQ(black.mechanics.thickness_mm, denim.mechanics.thickness_mm);
    EXPECT_FLOAT_EQ(black.appearance.base_colour.norm(), 0.0f);
    EXPECT_EQ(black.appearance.weave, denim.appearance.weave);
}

TEST(LookOverride, ValidatesLikeALookFile) {
    const toml::table overrides = parse_toml("[mechanics]\nthickness_mm = -1\n", "scene.toml");
    try {
        override_look(foldcast::test::shipped_looks().get("denim"), overrides, "scene.toml");
        FAIL() << "negative thickness accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("scene.toml:2: mechanics.thickness_mm = -1"), std::string::npos)
            << e.what();
    }
}

TEST(ResolveLook, ByNameOrByTableWithBase) {
    const toml::table scene = parse_toml(
        "look = \"satin\"\n"
        "[garment]\nlook = { base = \"chiffon\", appearance = { roughness = 0.2 } }\n",
        "scene.toml");
    const Look satin = resolve_look(foldcast::test::shipped_looks(), *scene.get("look"), "scene.toml");
    EXPECT_EQ(satin.name, "satin");
    const Look chiffon = resolve_look(foldcast::test::shipped_looks(), *scene["garment"]["look"].node(), "scene.toml");
    EXPECT_EQ(chiffon.name, "chiffon");
    EXPECT_DOUBLE_EQ(chiffon.appearance.roughness, 0.2);
    EXPECT_DOUBLE_EQ(chiffon.mechanics.gsm, foldcast::test::shipped_looks().get("chiffon").mechanics.gsm);
}

TEST(ResolveLook, ErrorsNameTheProblem) {
    const toml::table scene = parse_toml(
        "a = \"velour\"\nb = 3\nc = { appearance = { roughness = 0.2 } }\n"
        "d = { base = \"denim\", colour = \"red\" }\n",
        "scene.toml");
    auto message = [&](const char* key) {
        try {
            resolve_look(foldcast::test::shipped_looks(), *scene.get(key), "scene.toml");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(message("a").find("unknown look 'velour'"), std::string::npos);
    EXPECT_NE(message("b").find("scene.toml:2: look = 3 has the wrong type"), std::string::npos);
    EXPECT_NE(message("c").find("needs base = \"NAME\""), std::string::npos);
    EXPECT_NE(message("d").find("scene.toml:4: unknown key 'colour'"), std::string::npos) << message("d");
}
