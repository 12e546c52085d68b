#pragma once
// A look is a fabric as a user picks it: mechanics (how it folds, used by drape) and
// appearance (how it shades, used by render).  Looks ship as TOML files in looks/data/.
//
// Units are in the names.  Colours are linear RGB in [0,1] (TOML files give sRGB hex or
// linear triples; the loader converts).
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace toml {
inline namespace v3 {
class node;
class table;
}  // namespace v3
}  // namespace toml

namespace foldcast::looks {

// Default load constant c = 23.9 pi^2 / 12: plate buckling coefficient for in-plane bending.
double default_load_constant();

struct Mechanics {
    double thickness_mm = 0.3;
    double young_mpa = 5.0;
    double poisson = 0.3;
    double gsm = 150.0;  // g/m^2; weight per area w = gsm * 1e-3 * 9.80665 N/m^2
    double load_constant = default_load_constant();

    double weight_n_per_m2() const;
};

enum class Weave { none, plain, twill, satin, knit };
enum class AnisotropyAxis { warp, weft };
// The names used in look files ("plain", "warp", ...).
const char* weave_name(Weave weave);
const char* axis_name(AnisotropyAxis axis);

struct Appearance {
    Eigen::Vector3f base_colour{0.6f, 0.6f, 0.6f};  // linear RGB; the warp yarns' colour
    // Weft yarns' colour where it differs (denim's white weft, shot taffeta); unset = base.
    std::optional<Eigen::Vector3f> weft_colour;
    std::filesystem::path texture;  // optional image, tiled every repeat_mm
    Weave weave = Weave::plain;
    int twill_float = 3;     // twill only: warp floats over this many picks (2/1 or 3/1)
    double repeat_mm = 1.0;  // yarn spacing (weaves) or texture tile size
    double roughness = 0.8;  // GGX, [0,1]
    Eigen::Vector3f sheen_colour{0.0f, 0.0f, 0.0f};
    double sheen_roughness = 0.5;  // Charlie sheen, [0,1]
    double specular = 0.5;         // [0,1], scales F0 around 0.04
    double anisotropy = 0.0;       // [0,1)
    AnisotropyAxis anisotropy_axis = AnisotropyAxis::warp;
    std::filesystem::path normal_map;  // optional tangent-space normal map
    double bump_strength = 1.0;
};

struct Look {
    std::string name;
    std::string description;
    std::filesystem::path source;  // file it was read from ("" for built in code)
    Mechanics mechanics;
    Appearance appearance;
};

// All looks found in a directory of *.toml files (one look each, name = file stem).
class Library {
public:
    // looks/data of the source tree, or $FOLDCAST_LOOKS_DIR when set.
    static Library load_default();
    static Library load_directory(const std::filesystem::path& dir);

    std::vector<std::string> names() const;  // sorted
    bool contains(const std::string& name) const;
    // Throws InputError naming `name` and listing the available looks.
    const Look& get(const std::string& name) const;
    // A look's name, or the path of a look file (anything ending in .toml or holding a '/'),
    // relative paths taken from `base_dir`: what `--look` and a scene's `look = "..."` accept.
    Look find(const std::string& name_or_file, const std::filesystem::path& base_dir = {}) const;
    const std::filesystem::path& directory() const { return directory_; }

private:
    std::filesystem::path directory_;
    std::map<std::string, Look> looks_;
};

// Reads one look file (name = file stem).  Parse errors and invalid values throw InputError
// naming the file (and line), key, value and what is allowed.
Look load_look_file(const std::filesystem::path& file);

// Parses one look table.  `origin` names the file for messages.  Unknown keys, wrong types
// and impossible values throw InputError naming file, key, value and the allowed range.
Look parse_look(const toml::table& table, const std::string& name, const std::string& origin);
// Returns `base` with the keys present in `overrides` replaced (same validation).
Look override_look(const Look& base, const toml::table& overrides, const std::string& origin);

// How scene files choose a fabric: either a look's name (`look = "denim"`) or a table naming
// the base look and overriding some of its keys
// (`look = { base = "denim", appearance = { base_colour = "#202a44" } }`).
Look resolve_look(const Library& library, const toml::node& spec, const std::string& origin);

// The look as a TOML document that parse_look reads back to the same values (6 significant
// digits; colours as linear triples); what `foldcast looks show NAME` prints.
std::string format_look_toml(const Look& look);

}  // namespace foldcast::looks
