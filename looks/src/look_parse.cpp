// Reading look tables, key by key from the table in look_keys.cpp, with core's TomlSection:
// every problem is one line naming the file (and line), the key, the value and what is allowed.
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
#include "foldcast/core/toml_section.hpp"
#include "foldcast/looks/looks.hpp"
#include "foldcast/looks/look_keys.hpp"

namespace foldcast::looks {
namespace fs = std::filesystem;

namespace {

// One key's value as the table's type says, or nullopt when absent.
std::optional<LookValue> read_value(TomlSection& reader, const LookKey& key) {
    switch (key.type) {
        case LookKey::Type::number:
            if (auto v = reader.number(key.name, key.range)) return *v;
            return std::nullopt;
        case LookKey::Type::integer: {
            // Read as a number so that 2.5 is told what is allowed, not only "wrong type".
            const auto v = reader.number(key.name, key.range);
            if (!v) return std::nullopt;
            if (*v != static_cast<double>(static_cast<long long>(*v)))
                reader.fail(*reader.node(key.name), reader.qualified(key.name) + " = " +
                                                        toml_value_text(*reader.node(key.name)) +
                                                        " is not allowed: use " + allowed_text(key));
            return static_cast<long long>(*v);
        }
        case LookKey::Type::colour:
            if (auto v = reader.colour(key.name)) return *v;
            return std::nullopt;
        case LookKey::Type::file:
            if (auto v = reader.existing_file(key.name)) return *v;
            return std::nullopt;
        case LookKey::Type::choice:
            if (auto v = reader.choice(key.name, key.choices)) return *v;
            return std::nullopt;
    }
    return std::nullopt;
}

// `complete`: a look file, which must give the required keys; otherwise an override, where
// every key is optional.
void apply_section(Look& look, LookSection section, TomlSection&& reader, bool complete) {
    std::vector<std::string_view> names;
    for (const LookKey& key : look_keys())
        if (key.section == section) names.push_back(key.name);
    reader.check_keys(names);
    for (const LookKey& key : look_keys()) {
        if (key.section != section) continue;
        if (key.alternative_excludes && reader.has(key.name) && reader.has(key.alternative))
            reader.fail_here("give either " + reader.qualified(key.name) + " or " + reader.qualified(key.alternative) +
                             ", not both");
        if (complete && key.required && !reader.has(key.name) &&
            (key.alternative.empty() || !reader.has(key.alternative)))
            reader.missing(key.name, std::string(key.meaning) +
                                         (key.alternative.empty() ? "" : ", or " + std::string(key.alternative)));
        if (auto value = read_value(reader, key)) key.set(look, *value);
    }
}

// `base_key_allowed`: the table comes from a scene's `look = { base = "NAME", ... }`.
void apply_table(Look& look, const toml::table& table, const std::string& origin, bool complete,
                 bool base_key_allowed = false) {
    TomlSection top(table, "", origin);
    if (base_key_allowed)
        top.check_keys({"base", "description", "mechanics", "appearance"});
    else
        top.check_keys({"description", "mechanics", "appearance"});
    if (auto v = top.string("description")) look.description = *v;

    static const toml::table kEmpty;
    for (LookSection section : {LookSection::mechanics, LookSection::appearance}) {
        const char* name = section_name(section);
        const toml::table* t = top.table(name);
        if (!t && complete) top.missing(name, std::string("a [") + name + "] table");
        apply_section(look, section, TomlSection(t ? *t : kEmpty, name, origin), complete);
    }
}

}  // namespace

const char* weave_name(Weave weave) {
    switch (weave) {
        case Weave::none:
            return "none";
        case Weave::plain:
            return "plain";
        case Weave::twill:
            return "twill";
        case Weave::satin:
            return "satin";
        case Weave::knit:
            return "knit";
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
    const std::string where = toml_location(origin, spec);
    // An unknown name or a missing look file: said where the scene names it.
    auto named_here = [&](const std::string& key, const toml::node& node, auto&& look) -> Look {
        try {
            return look();
        } catch (const InputError& e) {
            throw InputError(toml_location(origin, node) + ": " + key + " = " + toml_value_text(node) + ": " +
                             e.what());
        }
    };
    if (const auto* name = spec.as_string())
        return named_here("look", spec, [&] { return library.find(name->get(), fs::path(origin).parent_path()); });
    const auto* table = spec.as_table();
    if (!table)
        throw InputError(where + ": look = " + toml_value_text(spec) +
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
    Look look = named_here("look.base", *base, [&] { return library.get(base->as_string()->get()); });
    apply_table(look, *table, origin, /*complete=*/false, /*base_key_allowed=*/true);
    return look;
}

}  // namespace foldcast::looks
