#include <toml++/toml.h>

#include <charconv>
#include <cctype>
#include <set>
#include <string>

#include "foldcast/core/error.hpp"
#include "foldcast/core/toml_section.hpp"
#include "foldcast/batch/catalogue.hpp"

namespace foldcast::batch {
namespace fs = std::filesystem;

namespace {

// Names become directory and file names: keep them portable and unable to escape.
bool portable_name(const std::string& name) {
    if (name.empty() || name.size() > 64 || name.front() == '.' || name.front() == '-') return false;
    for (char c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-')) return false;
    return true;
}

std::string checked_name(TomlSection& s, std::string_view key) {
    const toml::node* node = s.node(key);
    if (node == nullptr) s.missing(key, "a name: letters, digits, '_', '.' or '-'");
    const auto* text = node->as_string();
    if (text == nullptr || !portable_name(text->get()))
        s.fail(*node, s.qualified(key) + " = " + toml_value_text(*node) +
                          " is not allowed: use a string of letters, digits, '_', '.' or '-' "
                          "(at most 64, not starting with '.' or '-')");
    return text->get();
}

std::string checked_name(const TomlSection& s, const toml::node& node, std::string_view key) {
    const auto* text = node.as_string();
    if (text == nullptr || !portable_name(text->get()))
        s.fail(node, s.qualified(key) + " entry " + toml_value_text(node) +
                         " is not allowed: use a string of letters, digits, '_', '.' or '-' "
                         "(at most 64, not starting with '.' or '-')");
    return text->get();
}

}  // namespace

Shard parse_shard(const std::string& text) {
    int index = -1, count = 0;
    const char* end = text.data() + text.size();
    auto [slash, e1] = std::from_chars(text.data(), end, index);
    if (e1 == std::errc() && slash != end && *slash == '/') {
        auto [rest, e2] = std::from_chars(slash + 1, end, count);
        if (e2 == std::errc() && rest == end && index >= 0 && count >= 1 && index < count) return {index, count};
    }
    throw InputError("shard '" + text + "': expected I/N with 0 <= I < N, e.g. 0/4 .. 3/4");
}

BatchManifest load_manifest(const fs::path& path) {
    const toml::table root = read_toml_file(path, "manifest");
    const std::string origin = path.string();
    TomlSection top(root, "", origin);
    const fs::path base = fs::absolute(path).parent_path();
    BatchManifest m;
    m.path = path;
    m.output_dir = base / top.string("output_dir").value_or("catalogue");
    m.width = static_cast<int>(top.integer("width", 16, 16384).value_or(m.width));
    m.height = static_cast<int>(top.integer("height", 16, 16384).value_or(m.height));
    m.spp = static_cast<int>(top.integer("spp", 1, 1 << 16).value_or(m.spp));
    m.seed = static_cast<unsigned>(top.integer("seed", 0, 4294967295LL).value_or(m.seed));

    const toml::node* looks = top.node("looks");
    const toml::array* look_list = looks ? looks->as_array() : nullptr;
    if (look_list == nullptr || look_list->empty())
        throw InputError(origin + ": 'looks' must be a non-empty array of look names");
    for (const toml::node& look : *look_list) m.looks.push_back(checked_name(top, look, "looks"));

    const toml::node* garments_node = top.node("garments");
    if (garments_node == nullptr)
        throw InputError(origin + ": needs at least one [[garments]] table with name and scene");
    const toml::array* garments = top.array_of_tables("garments");
    for (const toml::node& node : *garments) {
        TomlSection g(*node.as_table(), "garments", origin);
        const std::string name = checked_name(g, "name");
        const std::string scene = g.string("scene").value_or("");
        if (scene.empty()) g.missing("scene", "the garment's scene file, relative to the manifest");
        g.finish();
        m.garments.push_back({name, base / scene});
    }

    if (top.has("views")) {
        for (const toml::node& node : *top.array_of_tables("views")) {
            TomlSection v(*node.as_table(), "views", origin);
            const std::string name = checked_name(v, "name");
            const double azimuth = v.number("azimuth_deg", {-360.0, 360.0}).value_or(0.0);
            const double elevation = v.number("elevation_deg", {-89.0, 89.0}).value_or(0.0);
            v.finish();
            m.views.push_back({name, azimuth, elevation});
        }
    } else {
        m.views.push_back({"front", 0.0, 0.0});
    }
    top.finish();
    auto unique = [&](auto names, const std::string& what) {
        std::set<std::string> seen;
        for (const std::string& n : names)
            if (!seen.insert(n).second) throw InputError(path.string() + ": " + what + " '" + n + "' appears twice");
    };
    std::vector<std::string> garment_names, view_names;
    for (const auto& g : m.garments) garment_names.push_back(g.name);
    for (const auto& v : m.views) view_names.push_back(v.name);
    unique(garment_names, "garment");
    unique(m.looks, "look");
    unique(view_names, "view");
    return m;
}

std::vector<BatchJob> all_jobs(const BatchManifest& manifest) {
    std::vector<BatchJob> jobs;
    for (const BatchGarment& garment : manifest.garments)
        for (const std::string& look : manifest.looks)
            for (const BatchView& view : manifest.views) {
                BatchJob job;
                job.index = jobs.size();
                job.garment = garment;
                job.look = look;
                job.view = view;
                job.output = manifest.output_dir / garment.name / look / (view.name + ".png");
                jobs.push_back(std::move(job));
            }
    return jobs;
}

std::vector<BatchJob> shard_jobs(const BatchManifest& manifest, Shard shard) {
    std::vector<BatchJob> mine;
    for (BatchJob& job : all_jobs(manifest))
        if (job.index % static_cast<std::size_t>(shard.count) == static_cast<std::size_t>(shard.index))
            mine.push_back(std::move(job));
    return mine;
}

}  // namespace foldcast::batch
