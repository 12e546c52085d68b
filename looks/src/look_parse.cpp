// Reading look tables: every key is checked for name, type and range, and every problem is
// reported as one line naming the file (and line), the key, the value and what is allowed.
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "colour.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/looks.hpp"

namespace foldcast::looks {
namespace fs = std::filesystem;

namespace {

constexpr double kStandardGravity = 9.80665;  // m/s^2, as Mechanics::weight_n_per_m2

// An interval of allowed values, printed in interval notation in messages.
struct Range {
    double lo;
    double hi;
    bool lo_inclusive;
    bool hi_inclusive;
    const char* unit;  // shown after the interval ("" for none)

    bool contains(double v) const {
        const bool above = lo_inclusive ? v >= lo : v > lo;
        const bool below = hi_inclusive ? v <= hi : v < hi;
        return above && below;  // false for NaN
    }
    std::string text() const {
        std::ostringstream out;
        out << (lo_inclusive ? '[' : '(') << lo << ", " << hi << (hi_inclusive ? ']' : ')');
        if (*unit) out << ' ' << unit;
        return out.str();
    }
};

// Ranges of every numeric key (docs/looks.md lists the same).
constexpr Range kThicknessMm{0.0, 50.0, false, true, "mm"};
constexpr Range kYoungMpa{0.0, 1.0e5, false, true, "MPa"};
constexpr Range kPoisson{-1.0, 0.5, false, false, ""};
constexpr Range kGsm{0.0, 5000.0, false, true, "g/m^2"};
constexpr Range kWeightNmm2{0.0, 5000.0e-3 * kStandardGravity * 1e-6, false, true, "N/mm^2"};
constexpr Range kLoadConstant{0.0, 1.0e4, false, true, ""};
constexpr Range kRepeatMm{0.0, 1000.0, false, true, "mm"};
constexpr Range kUnit{0.0, 1.0, true, true, ""};
constexpr Range kAnisotropy{0.0, 1.0, true, false, ""};
constexpr Range kTwillFloat{2.0, 3.0, true, true, "(2 or 3)"};
constexpr Range kBumpStrength{0.0, 10.0, true, true, ""};
constexpr Range kColourChannel{0.0, 1.0, true, true, "(linear)"};

std::string value_text(const toml::node& node) {
    std::ostringstream out;
    if (const auto* text = node.as_string())
        out << '"' << text->get() << '"';  // as the user most likely typed it
    else
        node.visit([&](const auto& value) { out << value; });
    std::string text = out.str();
    if (text.size() > 60) text = text.substr(0, 57) + "...";
    return text;
}

// "file:line" of a node (just "file" for nodes built in code, which have no line).
std::string location(const std::string& origin, const toml::node& node) {
    std::string text = origin;
    if (node.source().begin.line > 0) {
        text += ':';
        text += std::to_string(node.source().begin.line);
    }
    return text;
}

std::string join(const std::vector<std::string_view>& words) {
    std::string text;
    for (const auto& word : words) {
        if (!text.empty()) text += ", ";
        text += word;
    }
    return text;
}

// Reads the keys of one table ("" = the top level, "mechanics", "appearance").
class SectionReader {
public:
    SectionReader(const toml::table& table, std::string section, const std::string& origin)
        : table_(table), section_(std::move(section)), origin_(origin) {}

    void check_keys(const std::vector<std::string_view>& allowed) const {
        for (const auto& [key, node] : table_) {
            if (std::find(allowed.begin(), allowed.end(), key.str()) != allowed.end()) continue;
            fail(node, "unknown key '" + qualified(key.str()) + "'; allowed " +
                           (section_.empty() ? std::string("at the top level")
                                             : "in [" + section_ + "]") +
                           ": " + join(allowed));
        }
    }

    bool has(std::string_view key) const { return table_.contains(key); }

    std::optional<double> number(std::string_view key, const Range& range) const {
        const toml::node* node = table_.get(key);
        if (!node) return std::nullopt;
        double value = 0.0;
        if (const auto* integer = node->as_integer())
            value = static_cast<double>(integer->get());
        else if (const auto* floating = node->as_floating_point())
            value = floating->get();
        else
            wrong_type(*node, key, "a number in " + range.text());
        if (!range.contains(value))
            fail(*node, qualified(key) + " = " + value_text(*node) + " is out of range: allowed " +
                            range.text());
        return value;
    }

    std::optional<std::string> string(std::string_view key) const {
        const toml::node* node = table_.get(key);
        if (!node) return std::nullopt;
        const auto* text = node->as_string();
        if (!text) wrong_type(*node, key, "a string");
        return text->get();
    }

    std::optional<std::string> choice(std::string_view key,
                                      const std::vector<std::string_view>& allowed) const {
        const toml::node* node = table_.get(key);
        if (!node) return std::nullopt;
        const auto* text = node->as_string();
        if (!text) wrong_type(*node, key, "one of the strings " + join(allowed));
        if (std::find(allowed.begin(), allowed.end(), text->get()) == allowed.end())
            fail(*node, qualified(key) + " = " + value_text(*node) + " is not allowed: use one of " +
                            join(allowed));
        return text->get();
    }

    // "#RRGGBB" (sRGB) or [r, g, b] (linear, each in [0, 1]).
    std::optional<Eigen::Vector3f> colour(std::string_view key) const {
        const toml::node* node = table_.get(key);
        if (!node) return std::nullopt;
        const std::string expected =
            "an sRGB hex string \"#RRGGBB\" or a linear triple [r, g, b] with each in [0, 1]";
        if (const auto* text = node->as_string()) {
            if (auto linear = parse_srgb_hex(text->get())) return linear;
            fail(*node, qualified(key) + " = " + value_text(*node) + " is not a colour: use " +
                            expected);
        }
        const auto* array = node->as_array();
        if (!array || array->size() != 3) wrong_type(*node, key, expected);
        Eigen::Vector3f linear;
        for (int channel = 0; channel < 3; ++channel) {
            const toml::node& element = *array->get(static_cast<size_t>(channel));
            double value = 0.0;
            if (const auto* integer = element.as_integer())
                value = static_cast<double>(integer->get());
            else if (const auto* floating = element.as_floating_point())
                value = floating->get();
            else
                wrong_type(*node, key, expected);
            if (!kColourChannel.contains(value))
                fail(*node, qualified(key) + " = " + value_text(*node) +
                                " is out of range: each channel must be in " + kColourChannel.text());
            linear[channel] = static_cast<float>(value);
        }
        return linear;
    }

    // A file path, relative to the directory of `origin` unless absolute; it must exist.
    std::optional<fs::path> existing_file(std::string_view key) const {
        const toml::node* node = table_.get(key);
        if (!node) return std::nullopt;
        const auto* text = node->as_string();
        if (!text) wrong_type(*node, key, "a file path (relative to the look file)");
        if (text->get().empty()) return fs::path{};  // "" clears an inherited map
        fs::path path = text->get();
        if (path.is_relative()) path = fs::path(origin_).parent_path() / path;
        std::error_code error;
        if (!fs::is_regular_file(path, error))
            fail(*node, qualified(key) + " = " + value_text(*node) + ": no such file '" +
                            path.string() + "' (paths are relative to the file that names them)");
        return path.lexically_normal();
    }

    const toml::table* subtable(std::string_view key) const {
        const toml::node* node = table_.get(key);
        if (!node) return nullptr;
        const auto* table = node->as_table();
        if (!table) wrong_type(*node, key, "a table ([" + std::string(key) + "])");
        return table;
    }

    [[noreturn]] void fail_here(const std::string& message) const { fail(table_, message); }

    [[noreturn]] void missing(std::string_view key, const std::string& what) const {
        throw InputError(origin_ + ": missing key '" + qualified(key) + "' (" + what + ")");
    }

    [[noreturn]] void fail(const toml::node& node, const std::string& message) const {
        throw InputError(location(origin_, node) + ": " + message);
    }

private:
    std::string qualified(std::string_view key) const {
        return section_.empty() ? std::string(key) : section_ + "." + std::string(key);
    }

    [[noreturn]] void wrong_type(const toml::node& node, std::string_view key,
                                 const std::string& expected) const {
        fail(node, qualified(key) + " = " + value_text(node) + " has the wrong type: expected " +
                       expected);
    }

    const toml::table& table_;
    std::string section_;
    const std::string& origin_;
};

void apply_mechanics(Mechanics& mechanics, const SectionReader& reader, bool complete) {
    reader.check_keys(
        {"thickness_mm", "young_mpa", "poisson", "gsm", "weight_n_mm2", "load_constant"});
    if (auto v = reader.number("thickness_mm", kThicknessMm)) mechanics.thickness_mm = *v;
    else if (complete) reader.missing("thickness_mm", "fabric thickness in mm, " + kThicknessMm.text());
    if (auto v = reader.number("young_mpa", kYoungMpa)) mechanics.young_mpa = *v;
    else if (complete) reader.missing("young_mpa", "effective Young's modulus in MPa, " + kYoungMpa.text());
    if (auto v = reader.number("poisson", kPoisson)) mechanics.poisson = *v;
    if (auto v = reader.number("load_constant", kLoadConstant)) mechanics.load_constant = *v;

    const auto gsm = reader.number("gsm", kGsm);
    const auto weight = reader.number("weight_n_mm2", kWeightNmm2);
    if (gsm && weight)
        reader.fail_here("give either mechanics.gsm or mechanics.weight_n_mm2, not both");
    if (gsm) mechanics.gsm = *gsm;
    if (weight) mechanics.gsm = *weight * 1e6 / kStandardGravity * 1e3;  // N/mm^2 -> g/m^2
    if (complete && !gsm && !weight)
        reader.missing("gsm", "fabric weight in g/m^2, " + kGsm.text() + ", or weight_n_mm2");
}

void apply_appearance(Appearance& appearance, const SectionReader& reader, bool complete) {
    reader.check_keys({"base_colour", "weft_colour", "texture", "weave", "twill_float", "repeat_mm", "roughness", "sheen_colour",
                       "sheen_roughness", "specular", "anisotropy", "anisotropy_axis", "normal_map",
                       "bump_strength"});
    if (auto v = reader.colour("base_colour")) appearance.base_colour = *v;
    if (auto v = reader.colour("weft_colour")) appearance.weft_colour = *v;
    if (auto v = reader.existing_file("texture")) appearance.texture = *v;
    if (complete && !reader.has("base_colour") && !reader.has("texture"))
        reader.missing("base_colour", "\"#RRGGBB\" or [r, g, b] linear, or a texture");
    if (auto v = reader.choice("weave", {"none", "plain", "twill", "satin", "knit"})) {
        const Weave weaves[] = {Weave::none, Weave::plain, Weave::twill, Weave::satin, Weave::knit};
        for (Weave weave : weaves)
            if (*v == weave_name(weave)) appearance.weave = weave;
    } else if (complete) {
        reader.missing("weave", "one of none, plain, twill, satin, knit");
    }
    if (auto v = reader.number("twill_float", kTwillFloat)) {
        if (*v != 2.0 && *v != 3.0)
            reader.fail_here("appearance.twill_float = " + std::to_string(*v) +
                             " is not allowed: use 2 (2/1 twill) or 3 (3/1 twill)");
        appearance.twill_float = static_cast<int>(*v);
    }
    if (auto v = reader.number("repeat_mm", kRepeatMm)) appearance.repeat_mm = *v;
    if (auto v = reader.number("roughness", kUnit)) appearance.roughness = *v;
    if (auto v = reader.colour("sheen_colour")) appearance.sheen_colour = *v;
    if (auto v = reader.number("sheen_roughness", kUnit)) appearance.sheen_roughness = *v;
    if (auto v = reader.number("specular", kUnit)) appearance.specular = *v;
    if (auto v = reader.number("anisotropy", kAnisotropy)) appearance.anisotropy = *v;
    if (auto v = reader.choice("anisotropy_axis", {"warp", "weft"}))
        appearance.anisotropy_axis = *v == "warp" ? AnisotropyAxis::warp : AnisotropyAxis::weft;
    if (auto v = reader.existing_file("normal_map")) appearance.normal_map = *v;
    if (auto v = reader.number("bump_strength", kBumpStrength)) appearance.bump_strength = *v;
}

// `complete`: a look file, which must give the keys without a sensible default; otherwise an
// override, where every key is optional.
// `base_key_allowed`: the table comes from a scene's `look = { base = "NAME", ... }`.
void apply_table(Look& look, const toml::table& table, const std::string& origin, bool complete,
                 bool base_key_allowed = false) {
    const SectionReader top(table, "", origin);
    if (base_key_allowed)
        top.check_keys({"base", "description", "mechanics", "appearance"});
    else
        top.check_keys({"description", "mechanics", "appearance"});
    if (auto v = top.string("description")) look.description = *v;

    static const toml::table kEmpty;
    const toml::table* mechanics = top.subtable("mechanics");
    if (!mechanics && complete) top.missing("mechanics", "a [mechanics] table");
    apply_mechanics(look.mechanics, SectionReader(mechanics ? *mechanics : kEmpty, "mechanics", origin),
                    complete);
    const toml::table* appearance = top.subtable("appearance");
    if (!appearance && complete) top.missing("appearance", "an [appearance] table");
    apply_appearance(look.appearance,
                     SectionReader(appearance ? *appearance : kEmpty, "appearance", origin), complete);
}

}  // namespace

const char* weave_name(Weave weave) {
    switch (weave) {
        case Weave::none: return "none";
        case Weave::plain: return "plain";
        case Weave::twill: return "twill";
        case Weave::satin: return "satin";
        case Weave::knit: return "knit";
    }
    return "none";
}

const char* axis_name(AnisotropyAxis axis) { return axis == AnisotropyAxis::warp ? "warp" : "weft"; }

Look parse_look(const toml::table& table, const std::string& name, const std::string& origin) {
    Look look;
    look.name = name;
    look.source = origin;
    apply_table(look, table, origin, /*complete=*/true);
    return look;
}

Look override_look(const Look& base, const toml::table& overrides, const std::string& origin) {
    Look look = base;
    apply_table(look, overrides, origin, /*complete=*/false);
    return look;
}

Look resolve_look(const Library& library, const toml::node& spec, const std::string& origin) {
    if (const auto* name = spec.as_string()) return library.get(name->get());
    const auto* table = spec.as_table();
    const std::string where = location(origin, spec);
    if (!table)
        throw InputError(where + ": look = " + value_text(spec) +
                         " has the wrong type: expected a look name or a table with base = \"NAME\"");
    const toml::node* base = table->get("base");
    if (!base || !base->is_string()) {
        std::string names;
        for (const auto& known : library.names()) {
            if (!names.empty()) names += ", ";
            names += known;
        }
        throw InputError(where + ": a look table needs base = \"NAME\" (one of " + names + ")");
    }
    Look look = library.get(base->as_string()->get());
    apply_table(look, *table, origin, /*complete=*/false, /*base_key_allowed=*/true);
    return look;
}

}  // namespace foldcast::looks
