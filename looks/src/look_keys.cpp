#include "foldcast/looks/look_keys.hpp"

#include <sstream>

// Rows are designated initializers naming only what differs from LookKey's defaults; GCC 12
// warns about every member left to its default initializer, which here is the point.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace foldcast::looks {

const char* section_name(LookSection section) { return section == LookSection::mechanics ? "mechanics" : "appearance"; }

namespace {

constexpr double kStandardGravity = 9.80665;  // m/s^2, as Mechanics::weight_n_per_m2

using Type = LookKey::Type;

// get/set of a double member of look.mechanics or look.appearance.
template <typename Part>
LookKey number_key(LookKey key, Part Look::*part, double Part::*member) {
    key.type = Type::number;
    key.get = [part, member](const Look& l) -> LookValue { return l.*part.*member; };
    key.set = [part, member](Look& l, const LookValue& v) { l.*part.*member = std::get<double>(v); };
    return key;
}

LookKey colour_key(LookKey key, Eigen::Vector3f Appearance::*member) {
    key.section = LookSection::appearance;
    key.type = Type::colour;
    key.unit = "colour";
    key.allowed = "see above";
    key.get = [member](const Look& l) -> LookValue { return l.appearance.*member; };
    key.set = [member](Look& l, const LookValue& v) { l.appearance.*member = std::get<Eigen::Vector3f>(v); };
    return key;
}

LookKey file_key(LookKey key, std::filesystem::path Appearance::*member) {
    key.section = LookSection::appearance;
    key.type = Type::file;
    key.unit = "path";
    key.allowed = "existing file";
    key.default_text = "none";
    key.get = [member](const Look& l) -> LookValue {
        if ((l.appearance.*member).empty()) return std::monostate{};
        return l.appearance.*member;
    };
    key.set = [member](Look& l, const LookValue& v) { l.appearance.*member = std::get<std::filesystem::path>(v); };
    return key;
}

// [mechanics]: what the drape model reads.
void add_mechanics_keys(std::vector<LookKey>& keys) {
    constexpr auto mech = LookSection::mechanics;
    keys.push_back(number_key({.section = mech,
                               .name = "thickness_mm",
                               .range = {0.0, 50.0, false, true, "mm"},
                               .required = true,
                               .unit = "mm",
                               .meaning = "fabric thickness t (KES-FB3 T0, at 0.5 gf/cm^2)"},
                              &Look::mechanics, &Mechanics::thickness_mm));
    keys.push_back(number_key({.section = mech,
                               .name = "young_mpa",
                               .range = {0.0, 1.0e5, false, true, "MPa"},
                               .required = true,
                               .unit = "MPa",
                               .meaning = "effective Young's modulus E (see below)"},
                              &Look::mechanics, &Mechanics::young_mpa));
    keys.push_back(number_key({.section = mech,
                               .name = "poisson",
                               .range = {-1.0, 0.5, false, false, ""},
                               .unit = "-",
                               .default_text = "0.3",
                               .meaning = "Poisson's ratio nu"},
                              &Look::mechanics, &Mechanics::poisson));
    keys.push_back(number_key({.section = mech,
                               .name = "gsm",
                               .range = {0.0, 5000.0, false, true, "g/m^2"},
                               .required = true,
                               .alternative = "weight_n_mm2",
                               .alternative_excludes = true,
                               .unit = "g/m^2",
                               .meaning = "weight per area; w = gsm * 1e-3 * 9.80665 N/m^2"},
                              &Look::mechanics, &Mechanics::gsm));
    keys.push_back({.section = mech,
                    .name = "weight_n_mm2",
                    .type = Type::number,
                    .range = {0.0, 5000.0e-3 * kStandardGravity * 1e-6, false, true, "N/mm^2"},
                    .written = false,
                    .unit = "N/mm^2",
                    .default_text = "-",
                    .meaning = "alternative to `gsm`: weight per area w in the drape model's mm units",
                    .get = [](const Look&) -> LookValue { return std::monostate{}; },
                    .set =
                        [](Look& l, const LookValue& v) {
                            l.mechanics.gsm = std::get<double>(v) * 1e6 / kStandardGravity * 1e3;  // N/mm^2 -> g/m^2
                        }});
    keys.push_back(number_key({.section = mech,
                               .name = "load_constant",
                               .range = {0.0, 1.0e4, false, true, ""},
                               .unit = "-",
                               .default_text = "23.9 pi^2/12 = 19.657",
                               .meaning = "plate buckling coefficient c"},
                              &Look::mechanics, &Mechanics::load_constant));
}

// [appearance]: the yarns' colours and the weave.
void add_colour_and_weave_keys(std::vector<LookKey>& keys) {
    constexpr auto app = LookSection::appearance;
    keys.push_back(colour_key({.name = "base_colour",
                               .required = true,
                               .alternative = "texture",
                               .meaning = "albedo of the (warp) yarns, linear RGB"},
                              &Appearance::base_colour));
    keys.push_back(
        {.section = app,
         .name = "weft_colour",
         .type = Type::colour,
         .unit = "colour",
         .allowed = "see above",
         .default_text = "= base",
         .meaning = "weft yarns' colour where it differs (denim's ecru weft; a shot fabric's second colour)",
         .get = [](const Look& l) -> LookValue {
             if (!l.appearance.weft_colour) return std::monostate{};
             return *l.appearance.weft_colour;
         },
         .set = [](Look& l, const LookValue& v) { l.appearance.weft_colour = std::get<Eigen::Vector3f>(v); }});
    keys.push_back(file_key({.name = "texture", .meaning = "image tiled every `repeat_mm`"}, &Appearance::texture));
    keys.push_back({.section = app,
                    .name = "weave",
                    .type = Type::choice,
                    .choices = {"none", "plain", "twill", "satin", "knit"},
                    .required = true,
                    .unit = "-",
                    .meaning = "procedural structure (looks/src/weave*.cpp)",
                    .get = [](const Look& l) -> LookValue { return std::string(weave_name(l.appearance.weave)); },
                    .set =
                        [](Look& l, const LookValue& v) {
                            for (Weave w : {Weave::none, Weave::plain, Weave::twill, Weave::satin, Weave::knit})
                                if (std::get<std::string>(v) == weave_name(w)) l.appearance.weave = w;
                        }});
    keys.push_back(
        {.section = app,
         .name = "twill_float",
         .type = Type::integer,
         .range = {2.0, 3.0, true, true, "(2 or 3)"},
         .unit = "yarns",
         .allowed = "2 (2/1 twill) or 3 (3/1 twill)",
         .default_text = "3",
         .meaning = "twill only: warp floats over this many picks",
         .get = [](const Look& l) -> LookValue { return static_cast<long long>(l.appearance.twill_float); },
         .set = [](Look& l,
                   const LookValue& v) { l.appearance.twill_float = static_cast<int>(std::get<long long>(v)); }});
}

// [appearance]: the surface's BSDF and its perturbation.
void add_surface_keys(std::vector<LookKey>& keys) {
    constexpr auto app = LookSection::appearance;
    keys.push_back(number_key({.section = app,
                               .name = "repeat_mm",
                               .range = {0.0, 1000.0, false, true, "mm"},
                               .unit = "mm",
                               .default_text = "1.0",
                               .meaning = "yarn spacing (weaves) or texture tile size"},
                              &Look::appearance, &Appearance::repeat_mm));
    keys.push_back(number_key({.section = app,
                               .name = "roughness",
                               .range = {0.0, 1.0},
                               .unit = "-",
                               .default_text = "0.8",
                               .meaning = "GGX specular roughness"},
                              &Look::appearance, &Appearance::roughness));
    keys.push_back(
        colour_key({.name = "sheen_colour", .default_text = "black", .meaning = "Charlie sheen colour (fuzz, pile)"},
                   &Appearance::sheen_colour));
    keys.push_back(number_key({.section = app,
                               .name = "sheen_roughness",
                               .range = {0.0, 1.0},
                               .unit = "-",
                               .default_text = "0.5",
                               .meaning = "Charlie sheen roughness"},
                              &Look::appearance, &Appearance::sheen_roughness));
    keys.push_back(number_key({.section = app,
                               .name = "specular",
                               .range = {0.0, 1.0},
                               .unit = "-",
                               .default_text = "0.5",
                               .meaning = "specular strength (scales F0 around 0.04)"},
                              &Look::appearance, &Appearance::specular));
    keys.push_back(number_key({.section = app,
                               .name = "anisotropy",
                               .range = {0.0, 1.0, true, false, ""},
                               .unit = "-",
                               .default_text = "0",
                               .meaning = "GGX anisotropy"},
                              &Look::appearance, &Appearance::anisotropy));
    keys.push_back(
        {.section = app,
         .name = "anisotropy_axis",
         .type = Type::choice,
         .choices = {"warp", "weft"},
         .unit = "-",
         .default_text = "`warp`",
         .meaning = "direction of the highlight's stretch (warp = u)",
         .get = [](const Look& l) -> LookValue { return std::string(axis_name(l.appearance.anisotropy_axis)); },
         .set =
             [](Look& l, const LookValue& v) {
                 l.appearance.anisotropy_axis =
                     std::get<std::string>(v) == "warp" ? AnisotropyAxis::warp : AnisotropyAxis::weft;
             }});
    keys.push_back(file_key({.name = "normal_map", .meaning = "tangent-space normal map, tiled every `repeat_mm`"},
                            &Appearance::normal_map));
    keys.push_back(number_key({.section = app,
                               .name = "bump_strength",
                               .range = {0.0, 10.0},
                               .unit = "-",
                               .default_text = "1",
                               .meaning = "scales the procedural/normal-map perturbation"},
                              &Look::appearance, &Appearance::bump_strength));
}

std::vector<LookKey> make_keys() {
    std::vector<LookKey> keys;
    add_mechanics_keys(keys);
    add_colour_and_weave_keys(keys);
    add_surface_keys(keys);
    return keys;
}

}  // namespace

std::string allowed_text(const LookKey& key) {
    if (!key.allowed.empty()) return std::string(key.allowed);
    if (key.type == LookKey::Type::choice) {
        std::string text;
        for (const auto& c : key.choices) {
            text += text.empty() ? "`" : ", `";
            text += c;
            text += '`';
        }
        return text;
    }
    ValueRange r = key.range;
    r.unit = "";
    return r.text();
}

const std::vector<LookKey>& look_keys() {
    static const std::vector<LookKey> keys = make_keys();
    return keys;
}

std::string look_keys_markdown() {
    std::ostringstream out;
    for (LookSection section : {LookSection::mechanics, LookSection::appearance}) {
        if (section == LookSection::appearance) out << "\n";
        out << "### `[" << section_name(section) << "]` (required table)\n\n"
            << "| key | unit | allowed | default | meaning |\n|---|---|---|---|---|\n";
        for (const LookKey& key : look_keys()) {
            if (key.section != section) continue;
            std::string default_text(key.default_text);
            if (key.required)
                default_text =
                    key.alternative.empty() ? "required" : "required (or `" + std::string(key.alternative) + "`)";
            out << "| `" << key.name << "` | " << key.unit << " | " << allowed_text(key) << " | " << default_text
                << " | " << key.meaning << " |\n";
        }
    }
    return out.str();
}

}  // namespace foldcast::looks
