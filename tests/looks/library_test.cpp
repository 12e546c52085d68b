// Every shipped look loads, validates and keeps the relations the mechanics data promise.
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "foldcast/core/error.hpp"
#include "foldcast/looks/looks.hpp"
#include "foldcast/looks/look_json.hpp"

namespace fs = std::filesystem;
using foldcast::InputError;
using namespace foldcast::looks;

namespace {
const fs::path kShippedLooks = fs::path(FOLDCAST_SOURCE_DIR) / "looks" / "data";
}

TEST(LooksLibrary, ShipsTheTwelveRequiredLooks) {
    const Library library = Library::load_directory(kShippedLooks);
    for (const char* name : {"cotton_poplin", "denim", "linen", "silk_charmeuse", "satin", "chiffon", "wool_flannel",
                             "wool_crepe", "cotton_jersey", "velvet", "canvas", "polyester_taffeta"})
        EXPECT_TRUE(library.contains(name)) << name;
    EXPECT_GE(library.names().size(), 12u);
}

TEST(LooksLibrary, EveryShippedLookIsCompleteAndInRange) {
    const Library library = Library::load_directory(kShippedLooks);
    for (const auto& name : library.names()) {
        const Look& look = library.get(name);
        SCOPED_TRACE(name);
        EXPECT_EQ(look.name, name);
        EXPECT_FALSE(look.description.empty());
        EXPECT_GT(look.mechanics.thickness_mm, 0.0);
        EXPECT_GT(look.mechanics.young_mpa, 0.0);
        EXPECT_GT(look.mechanics.gsm, 0.0);
        EXPECT_GT(look.mechanics.poisson, -1.0);
        EXPECT_LT(look.mechanics.poisson, 0.5);
        EXPECT_GE(look.appearance.roughness, 0.0);
        EXPECT_LE(look.appearance.roughness, 1.0);
        EXPECT_GT(look.appearance.repeat_mm, 0.0);
        // Each file states the bending rigidity its modulus came from (E = 12(1-nu^2)B/t^3):
        // B must come out in the range KES-FB2 reports for apparel fabrics (~0.002-3 gf cm^2/cm).
        const auto& m = look.mechanics;
        const double t_m = m.thickness_mm * 1e-3;
        const double bending_gf_cm =
            m.young_mpa * 1e6 * t_m * t_m * t_m / (12.0 * (1.0 - m.poisson * m.poisson)) / 9.80665e-5;
        EXPECT_GT(bending_gf_cm, 0.002);
        EXPECT_LT(bending_gf_cm, 3.0);
    }
}

TEST(LooksLibrary, MechanicsOrderFabricsAsTextileDataDo) {
    const Library library = Library::load_directory(kShippedLooks);
    // Bending stiffness per weight decides how many folds form (docs/drape.md, equation 1):
    // S ~ E t^3 / w.  Denim and canvas must be far stiffer for their weight than chiffon/silk.
    auto stiffness_per_weight = [&](const char* name) {
        const auto& m = library.get(name).mechanics;
        return m.young_mpa * std::pow(m.thickness_mm, 3) / (1.0 - m.poisson * m.poisson) / m.gsm;
    };
    EXPECT_GT(stiffness_per_weight("denim"), 5.0 * stiffness_per_weight("chiffon"));
    EXPECT_GT(stiffness_per_weight("canvas"), stiffness_per_weight("denim"));
    EXPECT_GT(stiffness_per_weight("cotton_poplin"), stiffness_per_weight("silk_charmeuse"));
    EXPECT_GT(library.get("denim").mechanics.gsm, library.get("chiffon").mechanics.gsm);
}

TEST(LooksLibrary, SrgbHexIsConvertedToLinear) {
    const Library library = Library::load_directory(kShippedLooks);
    // denim base_colour "#2b3f66": 0x66 = 102 -> (102/255 + 0.055)/1.055)^2.4 = 0.1329
    EXPECT_NEAR(library.get("denim").appearance.base_colour.z(), 0.1329f, 1e-3f);
    ASSERT_TRUE(library.get("denim").appearance.weft_colour.has_value());
    EXPECT_EQ(library.get("denim").appearance.weave, Weave::twill);
    EXPECT_EQ(library.get("denim").appearance.twill_float, 3);
}

TEST(LooksLibrary, UnknownLookNamesTheAvailableOnes) {
    const Library library = Library::load_directory(kShippedLooks);
    try {
        library.get("demin");
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("demin"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("denim"), std::string::npos);
    }
}

TEST(LooksLibrary, DefaultFollowsTheEnvironmentVariable) {
    const fs::path dir = fs::temp_directory_path() / "foldcast_looks_env_test";
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::copy_file(kShippedLooks / "denim.toml", dir / "my_denim.toml");
    ::setenv("FOLDCAST_LOOKS_DIR", dir.c_str(), 1);
    const Library custom = Library::load_default();
    ::unsetenv("FOLDCAST_LOOKS_DIR");
    EXPECT_EQ(custom.names(), std::vector<std::string>{"my_denim"});
    EXPECT_TRUE(Library::load_default().contains("denim"));
    fs::remove_all(dir);
}

TEST(LooksLibrary, MissingDirectoryIsAnInputError) {
    EXPECT_THROW(Library::load_directory("/nonexistent/looks"), InputError);
}

TEST(LooksLibrary, PrintedTomlReadsBackToTheSameLook) {
    const Library library = Library::load_directory(kShippedLooks);
    for (const auto& name : library.names()) {
        SCOPED_TRACE(name);
        const Look& look = library.get(name);
        const toml::table table = toml::parse(format_look_toml(look));
        const Look again = parse_look(table, name, "printed");
        // Printed with 6 significant digits.
        EXPECT_NEAR(again.mechanics.young_mpa, look.mechanics.young_mpa, 1e-5 * look.mechanics.young_mpa);
        EXPECT_NEAR(again.mechanics.load_constant, look.mechanics.load_constant, 1e-4);
        EXPECT_DOUBLE_EQ(again.mechanics.gsm, look.mechanics.gsm);
        EXPECT_DOUBLE_EQ(again.appearance.anisotropy, look.appearance.anisotropy);
        EXPECT_EQ(again.appearance.weave, look.appearance.weave);
        EXPECT_EQ(again.appearance.twill_float, look.appearance.twill_float);
        EXPECT_TRUE(again.appearance.base_colour.isApprox(look.appearance.base_colour, 1e-5f));
        EXPECT_EQ(again.appearance.weft_colour.has_value(), look.appearance.weft_colour.has_value());
    }
}

TEST(LooksLibrary, JsonHasEveryValue) {
    const Library library = Library::load_directory(kShippedLooks);
    const nlohmann::json json = library.get("silk_charmeuse");
    EXPECT_EQ(json["name"], "silk_charmeuse");
    EXPECT_DOUBLE_EQ(json["mechanics"]["gsm"].get<double>(), 82.0);
    EXPECT_EQ(json["appearance"]["weave"], "satin");
    for (const char* key : {"thickness_mm", "young_mpa", "poisson", "gsm", "weight_n_per_m2", "load_constant"})
        EXPECT_TRUE(json["mechanics"].contains(key)) << key;
    for (const char* key :
         {"base_colour", "weft_colour", "texture", "weave", "twill_float", "repeat_mm", "roughness", "sheen_colour",
          "sheen_roughness", "specular", "anisotropy", "anisotropy_axis", "normal_map", "bump_strength"})
        EXPECT_TRUE(json["appearance"].contains(key)) << key;
}
