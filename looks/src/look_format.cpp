// Writing looks out, key by key from the table in look_keys.cpp: TOML (readable back by
// parse_look) and JSON reports.
#include <toml++/toml.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "colour.hpp"
#include "foldcast/looks/looks.hpp"
#include "foldcast/looks/look_json.hpp"
#include "foldcast/looks/look_keys.hpp"

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
    toml::table sections[2];
    for (const LookKey& key : look_keys()) {
        if (!key.written) continue;
        toml::table& table = sections[static_cast<int>(key.section)];
        std::visit(
            [&](const auto& v) {
                using T = std::decay_t<decltype(v)>;
                if constexpr (std::is_same_v<T, Eigen::Vector3f>) table.insert(key.name, colour_array(v));
                // Absolute paths, so the printed look reads back wherever it is saved.
                else if constexpr (std::is_same_v<T, std::filesystem::path>)
                    table.insert(key.name, std::filesystem::absolute(v).string());
                else if constexpr (!std::is_same_v<T, std::monostate>)
                    table.insert(key.name, v);
            },
            key.get(look));
    }
    // Mechanics before appearance, as in the shipped files (one toml::table would sort them);
    // shortest decimal floats, which is how look files are written.
    constexpr auto kFlags = toml::toml_formatter::default_flags | toml::format_flags::relaxed_float_precision;
    const Appearance& a = look.appearance;
    std::ostringstream out;
    out << "# look '" << look.name << "'";
    if (!look.source.empty()) out << " from " << look.source.string();
    out << "\n# colours are linear RGB; base_colour is sRGB " << to_srgb_hex(a.base_colour) << ", sheen_colour sRGB "
        << to_srgb_hex(a.sheen_colour) << "\n"
        << toml::toml_formatter(toml::table{{"description", look.description}}, kFlags) << "\n\n[mechanics]\n"
        << toml::toml_formatter(sections[0], kFlags) << "\n\n[appearance]\n"
        << toml::toml_formatter(sections[1], kFlags) << "\n";
    return out.str();
}

void to_json(nlohmann::json& json, const Look& look) {
    nlohmann::json sections[2] = {nlohmann::json::object(), nlohmann::json::object()};
    for (const LookKey& key : look_keys()) {
        if (!key.written) continue;
        nlohmann::json& section = sections[static_cast<int>(key.section)];
        std::visit(
            [&](const auto& v) {
                using T = std::decay_t<decltype(v)>;
                if constexpr (std::is_same_v<T, Eigen::Vector3f>)
                    section[std::string(key.name)] = colour_json(v);
                else if constexpr (std::is_same_v<T, std::filesystem::path>)
                    section[std::string(key.name)] = v.string();
                else if constexpr (std::is_same_v<T, std::monostate>)
                    section[std::string(key.name)] =
                        key.type == LookKey::Type::file ? nlohmann::json("") : nlohmann::json(nullptr);
                else
                    section[std::string(key.name)] = v;
            },
            key.get(look));
    }
    sections[0]["weight_n_per_m2"] = look.mechanics.weight_n_per_m2();  // derived, for reports
    json = {{"name", look.name},
            {"description", look.description},
            {"source", look.source.string()},
            {"mechanics", sections[0]},
            {"appearance", sections[1]}};
}

}  // namespace foldcast::looks
