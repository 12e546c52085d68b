#pragma once
// Every key of a look file in one table. The same rows drive reading look files and scene
// overrides (look_parse.cpp), writing TOML and JSON (look_format.cpp) and the key tables of
// docs/looks.md (`foldcast looks keys` prints them; a test holds the doc to it), so a key
// cannot be added in one place and forgotten in another.
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <Eigen/Core>

#include "foldcast/core/toml_section.hpp"
#include "foldcast/looks/looks.hpp"

namespace foldcast::looks {

enum class LookSection { mechanics, appearance };
const char* section_name(LookSection section);

// A key's value: a number, an integer, a linear colour, a path, a choice's name; or unset
// (an optional key the look does not have, which is then not written).
using LookValue = std::variant<std::monostate, double, long long, Eigen::Vector3f, std::filesystem::path, std::string>;

struct LookKey {
    enum class Type { number, integer, colour, file, choice };

    LookSection section = LookSection::mechanics;
    std::string_view name;
    Type type = Type::number;
    ValueRange range{};                     // number, integer
    std::vector<std::string_view> choices;  // choice
    // A look file must give the key, or its alternative (e.g. gsm or weight_n_mm2); overrides
    // in scene files never have to.
    bool required = false;
    std::string_view alternative;
    bool alternative_excludes = false;  // the alternative is the same value spelt otherwise
    bool written = true;                // by format_look_toml and JSON (false: an alternative spelling)
    // The docs' columns (and messages): unit; what is allowed where the type and range do not
    // say it; the default of an optional key; what it means.
    std::string_view unit, allowed, default_text, meaning;
    std::function<LookValue(const Look&)> get;
    std::function<void(Look&, const LookValue&)> set;
};

// In the order of docs/looks.md: [mechanics] keys, then [appearance] keys.
const std::vector<LookKey>& look_keys();

// What is allowed, as the docs and messages say it ("(0, 50]", "`warp`, `weft`").
std::string allowed_text(const LookKey& key);

// The two Markdown tables of docs/looks.md ("### `[mechanics]` ..." and "### `[appearance]` ...").
std::string look_keys_markdown();

}  // namespace foldcast::looks
