// Writing looks out: TOML (readable back by parse_look) and JSON reports.
#include <toml++/toml.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "colour.hpp"
#include "foldcast/looks.hpp"
#include "foldcast/looks/look_json.hpp"

namespace foldcast::looks {

namespace {
toml::array colour_array(const Eigen::Vector3f& linear) {
    return toml::array{static_cast<double>(linear.x()), static_cast<double>(linear.y()),
                       static_cast<double>(linear.z())};
}

nlohmann::json colour_json(const Eigen::Vector3f& linear) {
    return {{"linear", {linear.x(), linear.y(), linear.z()}}, {"srgb_hex", to_srgb_hex(linear)}};
}
}  // namespace

std::string format_look_toml(const Look& look) {
    const Mechanics& m = look.mechanics;
    const Appearance& a = look.appearance;
    toml::table mechanics{{"thickness_mm", m.thickness_mm}, {"young_mpa", m.young_mpa},
                          {"poisson", m.poisson},           {"gsm", m.gsm},
                          {"load_constant", m.load_constant}};
    toml::table appearance{{"base_colour", colour_array(a.base_colour)},
                           {"weave", weave_name(a.weave)},
                           {"twill_float", a.twill_float},
                           {"repeat_mm", a.repeat_mm},
                           {"roughness", a.roughness},
                           {"sheen_colour", colour_array(a.sheen_colour)},
                           {"sheen_roughness", a.sheen_roughness},
                           {"specular", a.specular},
                           {"anisotropy", a.anisotropy},
                           {"anisotropy_axis", axis_name(a.anisotropy_axis)},
                           {"bump_strength", a.bump_strength}};
    if (a.weft_colour) appearance.insert("weft_colour", colour_array(*a.weft_colour));
    // Absolute paths, so the printed look reads back wherever it is saved.
    if (!a.texture.empty()) appearance.insert("texture", std::filesystem::absolute(a.texture).string());
    if (!a.normal_map.empty())
        appearance.insert("normal_map", std::filesystem::absolute(a.normal_map).string());
    // Mechanics before appearance, as in the shipped files (a toml::table would sort them);
    // shortest decimal floats, which is how look files are written.
    constexpr auto kFlags = toml::toml_formatter::default_flags |
                            toml::format_flags::relaxed_float_precision;
    std::ostringstream out;
    out << "# look '" << look.name << "'";
    if (!look.source.empty()) out << " from " << look.source.string();
    out << "\n# colours are linear RGB; base_colour is sRGB " << to_srgb_hex(a.base_colour)
        << ", sheen_colour sRGB " << to_srgb_hex(a.sheen_colour) << "\n"
        << toml::toml_formatter(toml::table{{"description", look.description}}, kFlags)
        << "\n\n[mechanics]\n"
        << toml::toml_formatter(mechanics, kFlags) << "\n\n[appearance]\n"
        << toml::toml_formatter(appearance, kFlags) << "\n";
    return out.str();
}

void to_json(nlohmann::json& json, const Look& look) {
    const Mechanics& m = look.mechanics;
    const Appearance& a = look.appearance;
    json = {
        {"name", look.name},
        {"description", look.description},
        {"source", look.source.string()},
        {"mechanics",
         {{"thickness_mm", m.thickness_mm},
          {"young_mpa", m.young_mpa},
          {"poisson", m.poisson},
          {"gsm", m.gsm},
          {"weight_n_per_m2", m.weight_n_per_m2()},
          {"load_constant", m.load_constant}}},
        {"appearance",
         {{"base_colour", colour_json(a.base_colour)},
          {"weft_colour", a.weft_colour ? colour_json(*a.weft_colour) : nlohmann::json(nullptr)},
          {"texture", a.texture.string()},
          {"weave", weave_name(a.weave)},
          {"twill_float", a.twill_float},
          {"repeat_mm", a.repeat_mm},
          {"roughness", a.roughness},
          {"sheen_colour", colour_json(a.sheen_colour)},
          {"sheen_roughness", a.sheen_roughness},
          {"specular", a.specular},
          {"anisotropy", a.anisotropy},
          {"anisotropy_axis", axis_name(a.anisotropy_axis)},
          {"normal_map", a.normal_map.string()},
          {"bump_strength", a.bump_strength}}},
    };
}

}  // namespace foldcast::looks
