#include "foldcast/core/toml_section.hpp"

#include <algorithm>
#include <sstream>

#include "foldcast/core/colour.hpp"
#include "foldcast/core/error.hpp"

namespace foldcast {
namespace fs = std::filesystem;

bool ValueRange::contains(double v) const {
    const bool above = lo_inclusive ? v >= lo : v > lo;
    const bool below = hi_inclusive ? v <= hi : v < hi;
    return above && below;
}

std::string ValueRange::text() const {
    std::ostringstream out;
    out << (lo_inclusive ? '[' : '(') << lo << ", " << hi << (hi_inclusive ? ']' : ')');
    if (*unit) out << ' ' << unit;
    return out.str();
}

toml::table read_toml_file(const fs::path& file, std::string_view what) {
    std::error_code error;
    if (!fs::exists(file, error)) throw InputError(std::string(what) + " " + file.string() + ": does not exist");
    if (!fs::is_regular_file(file, error))
        throw InputError(std::string(what) + " " + file.string() + ": is not a file (a directory?)");
    try {
        return toml::parse_file(file.string());
    } catch (const toml::parse_error& e) {
        throw InputError(file.string() + ":" + std::to_string(e.source().begin.line) +
                         ": not valid TOML: " + std::string(e.description()));
    }
}

std::string toml_location(const std::string& origin, const toml::node& node) {
    std::string text = origin;
    if (node.source().begin.line > 0) {
        text += ':';  // one char: GCC 12's -Wrestrict misfires on "literal" + string here
        text += std::to_string(node.source().begin.line);
    }
    return text;
}

std::string toml_value_text(const toml::node& node) {
    std::ostringstream out;
    if (const auto* text = node.as_string())
        out << '"' << text->get() << '"';
    else
        node.visit([&](const auto& value) { out << value; });
    std::string text = out.str();
    if (text.size() > 60) text = text.substr(0, 57) + "...";
    return text;
}

namespace {
std::string join(const std::vector<std::string_view>& words) {
    std::string text;
    for (const auto& word : words) {
        if (!text.empty()) text += ", ";
        text += word;
    }
    return text;
}
std::optional<double> as_number(const toml::node& node) {
    if (const auto* integer = node.as_integer()) return static_cast<double>(integer->get());
    if (const auto* floating = node.as_floating_point()) return floating->get();
    return std::nullopt;
}
}  // namespace

TomlSection::TomlSection(const toml::table& table, std::string section, std::string origin)
    : table_(table), section_(std::move(section)), origin_(std::move(origin)) {}

std::string TomlSection::qualified(std::string_view key) const {
    return section_.empty() ? std::string(key) : section_ + "." + std::string(key);
}

void TomlSection::fail(const toml::node& node, const std::string& message) const {
    throw InputError(toml_location(origin_, node) + ": " + message);
}

void TomlSection::missing(std::string_view key, const std::string& what) const {
    throw InputError(origin_ + ": missing key '" + qualified(key) + "' (" + what + ")");
}

void TomlSection::wrong_type(const toml::node& node, std::string_view key, const std::string& expected) const {
    fail(node, qualified(key) + " = " + toml_value_text(node) + " has the wrong type: expected " + expected);
}

const toml::node* TomlSection::node(std::string_view key) {
    if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.emplace_back(key);
    return table_.get(key);
}

std::optional<double> TomlSection::number(std::string_view key, const ValueRange& range) {
    const toml::node* n = node(key);
    if (!n) return std::nullopt;
    const std::optional<double> value = as_number(*n);
    if (!value) wrong_type(*n, key, "a number in " + range.text());
    if (!range.contains(*value))
        fail(*n, qualified(key) + " = " + toml_value_text(*n) + " is out of range: allowed " + range.text());
    return value;
}

std::optional<long long> TomlSection::integer(std::string_view key, long long lo, long long hi) {
    const toml::node* n = node(key);
    if (!n) return std::nullopt;
    const ValueRange range{static_cast<double>(lo), static_cast<double>(hi)};
    const auto* value = n->as_integer();
    if (!value) wrong_type(*n, key, "an integer in " + range.text());
    if (value->get() < lo || value->get() > hi)
        fail(*n, qualified(key) + " = " + toml_value_text(*n) + " is out of range: allowed " + range.text());
    return value->get();
}

std::optional<bool> TomlSection::boolean(std::string_view key) {
    const toml::node* n = node(key);
    if (!n) return std::nullopt;
    const auto* value = n->as_boolean();
    if (!value) wrong_type(*n, key, "true or false");
    return value->get();
}

std::optional<std::string> TomlSection::string(std::string_view key) {
    const toml::node* n = node(key);
    if (!n) return std::nullopt;
    const auto* text = n->as_string();
    if (!text) wrong_type(*n, key, "a string");
    return text->get();
}

std::optional<std::string> TomlSection::choice(std::string_view key, const std::vector<std::string_view>& allowed) {
    const toml::node* n = node(key);
    if (!n) return std::nullopt;
    const auto* text = n->as_string();
    if (!text) wrong_type(*n, key, "one of the strings " + join(allowed));
    if (std::find(allowed.begin(), allowed.end(), text->get()) == allowed.end())
        fail(*n, qualified(key) + " = " + toml_value_text(*n) + " is not allowed: use one of " + join(allowed));
    return text->get();
}

std::optional<Eigen::VectorXd> TomlSection::numbers(std::string_view key, int count, const ValueRange& range) {
    const toml::node* n = node(key);
    if (!n) return std::nullopt;
    const std::string expected = "an array of " + std::to_string(count) + " numbers in " + range.text();
    const auto* array = n->as_array();
    if (!array || static_cast<int>(array->size()) != count) wrong_type(*n, key, expected);
    Eigen::VectorXd values(count);
    for (int i = 0; i < count; ++i) {
        const std::optional<double> v = as_number(*array->get(static_cast<std::size_t>(i)));
        if (!v) wrong_type(*n, key, expected);
        if (!range.contains(*v))
            fail(*n, qualified(key) + " = " + toml_value_text(*n) + " is out of range: each element must be in " +
                         range.text());
        values[i] = *v;
    }
    return values;
}

std::optional<std::vector<long long>> TomlSection::integers(std::string_view key, int count, long long lo,
                                                            long long hi) {
    const toml::node* n = node(key);
    if (!n) return std::nullopt;
    const ValueRange range{static_cast<double>(lo), static_cast<double>(hi)};
    const std::string expected = "an array of " + std::to_string(count) + " integers in " + range.text();
    const auto* array = n->as_array();
    if (!array || static_cast<int>(array->size()) != count) wrong_type(*n, key, expected);
    std::vector<long long> values;
    for (const toml::node& element : *array) {
        const auto* v = element.as_integer();
        if (!v) wrong_type(*n, key, expected);
        if (v->get() < lo || v->get() > hi)
            fail(*n, qualified(key) + " = " + toml_value_text(*n) + " is out of range: each element must be in " +
                         range.text());
        values.push_back(v->get());
    }
    return values;
}

std::optional<Eigen::Vector3f> TomlSection::colour(std::string_view key) {
    const toml::node* n = node(key);
    if (!n) return std::nullopt;
    const std::string expected = "an sRGB hex string \"#RRGGBB\" or a linear triple [r, g, b] with each in [0, 1]";
    if (const auto* text = n->as_string()) {
        const std::string& s = text->get();
        if (s.size() != 7 || s[0] != '#' || s.find_first_not_of("0123456789abcdefABCDEF", 1) != std::string::npos)
            fail(*n, qualified(key) + " = " + toml_value_text(*n) + " is not a colour: use " + expected);
        Eigen::Vector3f linear;
        for (int c = 0; c < 3; ++c)
            linear[c] = srgb_to_linear(static_cast<float>(std::stoi(s.substr(1 + 2 * c, 2), nullptr, 16)) / 255.0f);
        return linear;
    }
    const auto* array = n->as_array();
    if (!array || array->size() != 3) wrong_type(*n, key, expected);
    Eigen::Vector3f linear;
    for (int c = 0; c < 3; ++c) {
        const std::optional<double> v = as_number(*array->get(static_cast<std::size_t>(c)));
        if (!v) wrong_type(*n, key, expected);
        if (!(*v >= 0.0 && *v <= 1.0))
            fail(*n, qualified(key) + " = " + toml_value_text(*n) +
                         " is out of range: each channel must be in [0, 1] (linear)");
        linear[c] = static_cast<float>(*v);
    }
    return linear;
}

std::optional<fs::path> TomlSection::path(std::string_view key) {
    const toml::node* n = node(key);
    if (!n) return std::nullopt;
    const auto* text = n->as_string();
    if (!text) wrong_type(*n, key, "a file path (relative to " + origin_ + ")");
    if (text->get().empty()) return fs::path{};
    fs::path p = text->get();
    if (p.is_relative()) p = fs::path(origin_).parent_path() / p;
    return p.lexically_normal();
}

std::optional<fs::path> TomlSection::existing_file(std::string_view key) {
    std::optional<fs::path> p = path(key);
    if (!p || p->empty()) return p;
    std::error_code error;
    if (!fs::is_regular_file(*p, error))
        fail(*table_.get(key), qualified(key) + " = " + toml_value_text(*table_.get(key)) + ": no such file '" +
                                   p->string() + "' (paths are relative to the file that names them)");
    return p;
}

const toml::table* TomlSection::table(std::string_view key) {
    const toml::node* n = node(key);
    if (!n) return nullptr;
    const auto* t = n->as_table();
    if (!t) wrong_type(*n, key, "a table ([" + qualified(key) + "])");
    return t;
}

const toml::array* TomlSection::array_of_tables(std::string_view key) {
    const toml::node* n = node(key);
    if (!n) return nullptr;
    const auto* array = n->as_array();
    if (!array || !array->is_array_of_tables()) wrong_type(*n, key, "[[" + qualified(key) + "]] tables");
    return array;
}

void TomlSection::check_keys(const std::vector<std::string_view>& allowed) {
    for (std::string_view key : allowed)
        if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.emplace_back(key);
    finish();
}

void TomlSection::finish() const {
    for (const auto& [key, value] : table_) {
        if (std::find(known_.begin(), known_.end(), key.str()) != known_.end()) continue;
        std::string allowed;
        for (const auto& k : known_) {
            if (!allowed.empty()) allowed += ", ";
            allowed += k;
        }
        fail(value, "unknown key '" + qualified(key.str()) + "'; allowed " +
                        (section_.empty() ? std::string("at the top level") : "in [" + section_ + "]") + ": " +
                        (allowed.empty() ? std::string("none") : allowed));
    }
}

}  // namespace foldcast
