#pragma once
// The one reader of foldcast's TOML files (looks, scenes, catalogue manifests): typed getters
// with ranges, unknown keys rejected, and every problem reported as one line naming the file
// (and line), the key, the value and what is allowed:
//
//   scene.toml:3: camera.fov_deg = 500 is out of range: allowed (0, 170]
//   look.toml:6: unknown key 'mechanics.thicknes_mm'; allowed in [mechanics]: thickness_mm, ...
#include <toml++/toml.h>

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace foldcast {

// An interval of allowed values, printed in interval notation ("(0, 50] mm").
struct ValueRange {
    double lo = 0.0;
    double hi = 0.0;
    bool lo_inclusive = true;
    bool hi_inclusive = true;
    const char* unit = "";  // shown after the interval ("" for none)

    bool contains(double v) const;  // false for NaN
    std::string text() const;
};

// Parses a TOML file. Throws InputError "<what> FILE: does not exist" (or is not a file), or
// "FILE:LINE: not valid TOML: ..." for syntax errors.
toml::table read_toml_file(const std::filesystem::path& file, std::string_view what);

// "FILE:LINE" of a node ("FILE" for nodes made in code, which have no line).
std::string toml_location(const std::string& origin, const toml::node& node);
// The value as the user most likely typed it (strings quoted), cut at 60 characters.
std::string toml_value_text(const toml::node& node);

// One table of a file. Each getter returns nullopt when the key is absent and throws
// InputError when it is present with the wrong type or out of range; each marks its key as
// known, and finish() rejects every key that no getter asked for.
class TomlSection {
public:
    // `section`: the dotted name of the table ("" at the top level, "lights.area[0]");
    // `origin`: the file, for messages and relative paths.
    TomlSection(const toml::table& table, std::string section, std::string origin);

    bool has(std::string_view key) const { return table_.contains(key); }
    const toml::node* node(std::string_view key);  // marks the key known

    std::optional<double> number(std::string_view key, const ValueRange& range);
    std::optional<long long> integer(std::string_view key, long long lo, long long hi);
    std::optional<bool> boolean(std::string_view key);
    std::optional<std::string> string(std::string_view key);
    std::optional<std::string> choice(std::string_view key, const std::vector<std::string_view>& allowed);
    // An array of exactly `count` numbers, each in `range`.
    std::optional<Eigen::VectorXd> numbers(std::string_view key, int count, const ValueRange& range);
    // An array of exactly `count` integers, each in [lo, hi].
    std::optional<std::vector<long long>> integers(std::string_view key, int count, long long lo, long long hi);
    // "#RRGGBB" (sRGB) or [r, g, b] (linear, each in [0, 1]); returned linear.
    std::optional<Eigen::Vector3f> colour(std::string_view key);
    // A path relative to the folder of `origin` unless absolute ("" stays empty).
    std::optional<std::filesystem::path> path(std::string_view key);
    // As path(), and the file must exist.
    std::optional<std::filesystem::path> existing_file(std::string_view key);
    const toml::table* table(std::string_view key);
    // [[key]] entries: an array whose every element is a table.
    const toml::array* array_of_tables(std::string_view key);

    // Rejects keys no getter asked for, listing the ones that are allowed here.
    void finish() const;
    // Declares every allowed key up front and rejects the others now, before any value is
    // read: a misspelt required key is then reported as unknown, not as missing.
    void check_keys(const std::vector<std::string_view>& allowed);

    std::string qualified(std::string_view key) const;
    const std::string& origin() const { return origin_; }
    [[noreturn]] void fail(const toml::node& node, const std::string& message) const;
    [[noreturn]] void fail_here(const std::string& message) const { fail(table_, message); }
    [[noreturn]] void missing(std::string_view key, const std::string& what) const;
    [[noreturn]] void wrong_type(const toml::node& node, std::string_view key, const std::string& expected) const;

private:
    const toml::table& table_;
    std::string section_;
    std::string origin_;
    std::vector<std::string> known_;  // in the order asked, for the list of allowed keys
};

}  // namespace foldcast
