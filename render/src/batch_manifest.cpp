#include <toml++/toml.h>

#include <charconv>
#include <cctype>
#include <set>
#include <string>

#include "foldcast/core/error.hpp"
#include "foldcast/render/batch.hpp"

namespace foldcast::render {
namespace fs = std::filesystem;

namespace {

std::string where(const fs::path& file, const toml::node& node) {
    const auto& source = node.source();
    return file.string() + ":" + std::to_string(source.begin.line);
}

void reject_unknown_keys(const toml::table& table, const std::set<std::string>& allowed,
                         const fs::path& file, const std::string& context) {
    for (const auto& [key, value] : table)
        if (!allowed.contains(std::string(key.str()))) {
            std::string list;
            for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
            throw InputError(where(file, value) + ": unknown key '" + context + std::string(key.str()) +
                             "' (allowed: " + list + ")");
        }
}

// Names become directory and file names: keep them portable and unable to escape.
bool portable_name(const std::string& name) {
    if (name.empty() || name.size() > 64 || name.front() == '.' || name.front() == '-') return false;
    for (char c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-')) return false;
    return true;
}

std::string checked_name(const toml::node& node, const fs::path& file, const std::string& key) {
    const auto* text = node.as_string();
    if (text == nullptr || !portable_name(text->get()))
        throw InputError(where(file, node) + ": '" + key +
                         "' must be a string of letters, digits, '_', '.' or '-' (at most 64, not starting with '.' or '-')");
    return text->get();
}

template <typename T>
T number_in(const toml::table& table, const std::string& key, T fallback, double lo, double hi,
            const fs::path& file) {
    const toml::node* node = table.get(key);
    if (node == nullptr) return fallback;
    std::optional<double> value;
    if (const auto* i = node->as_integer()) value = static_cast<double>(i->get());
    if (const auto* f = node->as_floating_point()) value = f->get();
    if (!value || !(*value >= lo && *value <= hi) ||
        (std::is_integral_v<T> && node->as_integer() == nullptr))
        throw InputError(where(file, *node) + ": '" + key + "' must be " +
                         (std::is_integral_v<T> ? "an integer" : "a number") + " in [" +
                         std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return static_cast<T>(*value);
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
    throw InputError("--shard '" + text + "': expected I/N with 0 <= I < N, e.g. 0/4 .. 3/4");
}

BatchManifest load_manifest(const fs::path& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw InputError("cannot read manifest '" + path.string() + "': no such file");
    toml::table root;
    try {
        root = toml::parse_file(path.string());
    } catch (const toml::parse_error& e) {
        throw InputError(path.string() + ":" + std::to_string(e.source().begin.line) + ": " +
                         std::string(e.description()));
    }
    reject_unknown_keys(root, {"output_dir", "width", "height", "spp", "seed", "looks", "garments", "views"}, path, "");
    const fs::path base = fs::absolute(path).parent_path();
    BatchManifest m;
    m.path = path;
    if (const toml::node* dir = root.get("output_dir"); dir != nullptr && !dir->is_string())
        throw InputError(where(path, *dir) + ": 'output_dir' must be a string (a directory path)");
    m.output_dir = base / root["output_dir"].value_or(std::string("catalogue"));
    m.width = number_in<int>(root, "width", m.width, 16, 16384, path);
    m.height = number_in<int>(root, "height", m.height, 16, 16384, path);
    m.spp = number_in<int>(root, "spp", m.spp, 1, 1 << 16, path);
    m.seed = number_in<unsigned>(root, "seed", m.seed, 0, 4294967295.0, path);

    const toml::array* looks = root["looks"].as_array();
    if (looks == nullptr || looks->empty())
        throw InputError(path.string() + ": 'looks' must be a non-empty array of look names");
    for (const toml::node& look : *looks) m.looks.push_back(checked_name(look, path, "looks"));

    const toml::array* garments = root["garments"].as_array();
    if (garments == nullptr || garments->empty() || !garments->is_array_of_tables())
        throw InputError(path.string() + ": needs at least one [[garments]] table with name and scene");
    for (const toml::node& node : *garments) {
        const toml::table& g = *node.as_table();
        reject_unknown_keys(g, {"name", "scene"}, path, "garments.");
        const toml::node* name = g.get("name");
        const toml::node* scene = g.get("scene");
        if (name == nullptr || scene == nullptr || !scene->is_string())
            throw InputError(where(path, node) + ": each [[garments]] needs name and scene (a scene file path)");
        m.garments.push_back({checked_name(*name, path, "garments.name"), base / scene->as_string()->get()});
    }

    const toml::array* views = root["views"].as_array();
    if (views == nullptr || views->empty()) {
        m.views.push_back({"front", 0.0, 0.0});
    } else {
        if (!views->is_array_of_tables()) throw InputError(path.string() + ": 'views' must be [[views]] tables");
        for (const toml::node& node : *views) {
            const toml::table& v = *node.as_table();
            reject_unknown_keys(v, {"name", "azimuth_deg", "elevation_deg"}, path, "views.");
            const toml::node* name = v.get("name");
            if (name == nullptr) throw InputError(where(path, node) + ": each [[views]] needs a name");
            m.views.push_back({checked_name(*name, path, "views.name"),
                               number_in<double>(v, "azimuth_deg", 0.0, -360.0, 360.0, path),
                               number_in<double>(v, "elevation_deg", 0.0, -89.0, 89.0, path)});
        }
    }
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

}  // namespace foldcast::render
