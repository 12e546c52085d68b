// Scene files (TOML): every key is checked for name, type and range; problems are one line
// naming the file, line, key, value and what is allowed.
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "foldcast/core/error.hpp"
#include "foldcast/render.hpp"

namespace foldcast::render {
namespace fs = std::filesystem;
namespace {

std::string where(const std::string& file, const toml::node& node) {
    std::ostringstream s;
    s << file;
    if (node.source().begin.line > 0) s << ":" << node.source().begin.line;
    return s.str();
}

// One table of the scene file: typed getters with ranges, and a check that no unknown key
// was given (typos must not be silently ignored).
class Section {
public:
    Section(const toml::table& table, std::string prefix, const std::string& file)
        : table_(table), prefix_(std::move(prefix)), file_(file) {}

    [[noreturn]] void fail(const toml::node& node, const std::string& key, const std::string& what) const {
        throw InputError(where(file_, node) + ": key '" + full(key) + "' " + what);
    }
    std::string full(const std::string& key) const { return prefix_.empty() ? key : prefix_ + "." + key; }
    const toml::node* get(const std::string& key) {
        used_.insert(key);
        return table_.get(key);
    }
    bool has(const std::string& key) const { return table_.contains(key); }

    double number(const std::string& key, double fallback, double lo, double hi, bool lo_open = false) {
        const toml::node* n = get(key);
        if (!n) return fallback;
        std::optional<double> v = n->value<double>();
        if (!n->is_number() || !v) fail(*n, key, "must be a number");
        const bool ok = (lo_open ? *v > lo : *v >= lo) && *v <= hi && std::isfinite(*v);
        if (!ok) {
            std::ostringstream s;
            s << "= " << *v << " is out of range: allowed " << (lo_open ? "(" : "[") << lo << ", " << hi << "]";
            fail(*n, key, s.str());
        }
        return *v;
    }
    int integer(const std::string& key, int fallback, long long lo, long long hi) {
        const toml::node* n = get(key);
        if (!n) return fallback;
        if (!n->is_integer()) fail(*n, key, "must be an integer");
        const long long v = *n->value<long long>();
        if (v < lo || v > hi)
            fail(*n, key, "= " + std::to_string(v) + " is out of range: allowed [" + std::to_string(lo) + ", " +
                              std::to_string(hi) + "]");
        return static_cast<int>(v);
    }
    bool boolean(const std::string& key, bool fallback) {
        const toml::node* n = get(key);
        if (!n) return fallback;
        if (!n->is_boolean()) fail(*n, key, "must be true or false");
        return *n->value<bool>();
    }
    std::string string(const std::string& key, const std::string& fallback, const std::vector<std::string>& allowed = {}) {
        const toml::node* n = get(key);
        if (!n) return fallback;
        if (!n->is_string()) fail(*n, key, "must be a string");
        std::string v = *n->value<std::string>();
        if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), v) == allowed.end()) {
            std::string list;
            for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
            fail(*n, key, "= \"" + v + "\" is not one of: " + list);
        }
        return v;
    }
    // [x, y, z] (or [x, y] for n = 2) of numbers.
    Eigen::VectorXd vector(const std::string& key, int count, const Eigen::VectorXd& fallback,
                           double lo = -1e6, double hi = 1e6) {
        const toml::node* n = get(key);
        if (!n) return fallback;
        const toml::array* arr = n->as_array();
        if (!arr || static_cast<int>(arr->size()) != count)
            fail(*n, key, "must be an array of " + std::to_string(count) + " numbers");
        Eigen::VectorXd v(count);
        for (int i = 0; i < count; ++i) {
            const toml::node& e = *arr->get(static_cast<std::size_t>(i));
            if (!e.is_number()) fail(*n, key, "must be an array of " + std::to_string(count) + " numbers");
            v[i] = *e.value<double>();
            if (!std::isfinite(v[i]) || v[i] < lo || v[i] > hi) {
                std::ostringstream s;
                s << "has element " << v[i] << " out of range: allowed [" << lo << ", " << hi << "]";
                fail(*n, key, s.str());
            }
        }
        return v;
    }
    Vec3f vec3(const std::string& key, const Vec3f& fallback, double lo = -1e6, double hi = 1e6) {
        return vector(key, 3, fallback.cast<double>(), lo, hi).cast<float>();
    }
    // "#rrggbb" (sRGB) or [r, g, b] linear in [0, 1].
    Vec3f colour(const std::string& key, const Vec3f& fallback) {
        const toml::node* n = get(key);
        if (!n) return fallback;
        if (n->is_string()) {
            const std::string s = *n->value<std::string>();
            if (s.size() != 7 || s[0] != '#' || s.find_first_not_of("0123456789abcdefABCDEF", 1) != std::string::npos)
                fail(*n, key, "= \"" + s + "\" is not a colour: use \"#rrggbb\" (sRGB) or [r, g, b] (linear, 0..1)");
            Vec3f c;
            for (int i = 0; i < 3; ++i) {
                const float v = static_cast<float>(std::stoi(s.substr(1 + 2 * i, 2), nullptr, 16)) / 255.0f;
                c[i] = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
            }
            return c;
        }
        return vec3(key, fallback, 0.0, 1.0);
    }
    const toml::table* subtable(const std::string& key) {
        const toml::node* n = get(key);
        if (!n) return nullptr;
        if (!n->is_table()) fail(*n, key, "must be a table");
        return n->as_table();
    }
    void finish() const {
        for (const auto& [k, v] : table_) {
            const std::string key(k.str());
            if (!used_.count(key)) fail(v, key, "is unknown here (check the spelling; see docs/render.md)");
        }
    }

private:
    const toml::table& table_;
    std::string prefix_;
    const std::string& file_;
    std::set<std::string> used_;
};

constexpr const char* kDefaultLook = "linen";

fs::path resolve(const fs::path& base_dir, const std::string& p) {
    const fs::path path(p);
    return path.is_absolute() ? path : base_dir / path;
}

void read_garment(Section& s, GarmentSpec& g, const fs::path& dir) {
    const std::string path = s.string("path", "");
    std::string source = s.string("source", "", {"drape", "obj", "pc2", "fca"});
    if (source.empty()) {
        source = "drape";
        if (!path.empty()) {
            const std::string ext = fs::path(path).extension().string();
            if (ext == ".obj") source = "obj";
            else if (ext == ".pc2") source = "pc2";
            else if (ext == ".fca") source = "fca";
            else
                s.fail(*s.get("path"), "path", "= \"" + path + "\" has an unknown extension: use .obj, .pc2 or .fca (or set source)");
        }
    }
    g.source = source == "drape" ? GarmentSpec::Source::drape
               : source == "obj" ? GarmentSpec::Source::obj
               : source == "pc2" ? GarmentSpec::Source::pc2
                                 : GarmentSpec::Source::fca;
    if (g.source != GarmentSpec::Source::drape && path.empty())
        throw InputError("garment.source = \"" + source + "\" needs garment.path");
    if (!path.empty()) g.path = resolve(dir, path);
    const std::string topo = s.string("topology", "");
    if (!topo.empty()) g.topology = resolve(dir, topo);
    g.frame = s.integer("frame", g.frame, 0, 1000000);
    g.scale = s.number("scale", g.scale, 0.0, 1e6, true);
    g.width_m = s.number("width_m", g.width_m, 0.0, 20.0, true);
    g.height_m = s.number("height_m", g.height_m, 0.0, 20.0, true);
    g.inset_m = s.number("inset_m", g.inset_m, 0.0, 10.0);
    if (2.0 * g.inset_m >= g.width_m)
        throw InputError("garment.inset_m = " + std::to_string(g.inset_m) +
                         ": the supports must stay apart (need inset_m < width_m / 2)");
    if (s.has("grid")) {
        const Eigen::VectorXd grid = s.vector("grid", 2, Eigen::Vector2d(g.grid_nu, g.grid_nv), 2, 4096);
        g.grid_nu = static_cast<int>(grid[0]);
        g.grid_nv = static_cast<int>(grid[1]);
    }
    g.animation_frames = s.integer("animation_frames", g.animation_frames, 0, 100000);
    g.sway_amplitude_m = s.number("sway_amplitude_m", g.sway_amplitude_m, 0.0, 10.0);
    g.relax = s.boolean("relax", g.relax);
    s.finish();
}

void read_camera(Section& s, CameraSpec& c) {
    c.auto_frame = s.boolean("auto", !(s.has("position") || s.has("target")));
    c.frame_share = s.number("frame_share", c.frame_share, 0.0, 1.0, true);
    c.azimuth_deg = s.number("azimuth_deg", c.azimuth_deg, -360.0, 360.0);
    c.elevation_deg = s.number("elevation_deg", c.elevation_deg, -89.0, 89.0);
    c.fov_deg = s.number("fov_deg", c.fov_deg, 0.0, 170.0, true);
    c.aperture_m = s.number("aperture_m", c.aperture_m, 0.0, 1.0);
    c.focus_distance_m = s.number("focus_distance_m", c.focus_distance_m, 0.0, 1e4);
    c.position = s.vec3("position", c.position);
    c.target = s.vec3("target", c.target);
    if (!c.auto_frame && (c.position - c.target).norm() < 1e-6f)
        throw InputError("camera.position and camera.target must differ");
    s.finish();
}

AreaLight read_light(Section& s, const std::string& default_name) {
    AreaLight l;
    l.name = s.string("name", default_name);
    l.position = s.vec3("position", l.position);
    l.target = s.vec3("target", l.target);
    const Eigen::VectorXd size = s.vector("size_m", 2, Eigen::Vector2d(l.width_m, l.height_m), 1e-4, 100.0);
    l.width_m = static_cast<float>(size[0]);
    l.height_m = static_cast<float>(size[1]);
    const Vec3f colour = s.colour("colour", Vec3f::Ones());
    const double intensity = s.number("intensity", 10.0, 0.0, 1e7);
    l.radiance = colour * static_cast<float>(intensity);
    if ((l.position - l.target).norm() < 1e-6f) throw InputError("light '" + l.name + "': position and target must differ");
    s.finish();
    return l;
}

}  // namespace

SceneSpec load_scene(const fs::path& file) {
    const std::string name = file.string();
    if (!fs::exists(file)) throw InputError("scene file " + name + ": does not exist");
    toml::table root;
    try {
        root = toml::parse_file(name);
    } catch (const toml::parse_error& e) {
        std::ostringstream s;
        s << name << ":" << e.source().begin.line << ": TOML syntax error: " << e.description();
        throw InputError(s.str());
    }
    SceneSpec scene;
    scene.file = file;
    const fs::path dir = file.parent_path();
    Section top(root, "", name);

    if (const toml::table* t = top.subtable("garment")) {
        Section s(*t, "garment", name);
        read_garment(s, scene.garment, dir);
    }
    // look = "denim", or look = { base = "denim", appearance = { ... } } overriding keys.
    if (const toml::node* n = top.get("look")) {
        scene.look = looks::resolve_look(looks::Library::load_default(), *n, name);
    } else {
        scene.look = looks::Library::load_default().get(kDefaultLook);
    }
    if (const toml::table* t = top.subtable("camera")) {
        Section s(*t, "camera", name);
        read_camera(s, scene.camera);
    }
    std::string preset = "studio";
    if (const toml::table* t = top.subtable("lights")) {
        Section s(*t, "lights", name);
        // The preset is the default only when no area lights are listed.
        preset = s.string("preset", t->contains("area") ? "none" : "studio", {"studio", "none"});
        if (s.has("environment")) {
            const toml::node* e = t->get("environment");
            if (e->is_number()) {
                scene.environment = Vec3f::Constant(static_cast<float>(s.number("environment", 0.0, 0.0, 1e6)));
            } else {
                scene.environment = s.vec3("environment", scene.environment, 0.0, 1e6);
            }
        } else {
            scene.environment = Vec3f::Constant(preset == "studio" ? 0.02f : 0.0f);
        }
        scene.exposure_ev = s.number("exposure_ev", scene.exposure_ev, -20.0, 20.0);
        if (const toml::node* a = s.get("area")) {
            const toml::array* arr = a->as_array();
            if (!arr) s.fail(*a, "area", "must be an array of tables ([[lights.area]])");
            int i = 0;
            for (const toml::node& e : *arr) {
                if (!e.is_table()) s.fail(e, "area", "entries must be tables ([[lights.area]])");
                Section ls(*e.as_table(), "lights.area[" + std::to_string(i) + "]", name);
                scene.lights.push_back(read_light(ls, "area" + std::to_string(i)));
                ++i;
            }
        }
        s.finish();
    } else {
        scene.environment = Vec3f::Constant(0.02f);
    }
    if (const toml::table* t = top.subtable("backdrop")) {
        Section s(*t, "backdrop", name);
        const std::string kind = s.string("kind", "cyclorama", {"cyclorama", "none"});
        scene.backdrop = kind == "none" ? SceneSpec::Backdrop::none : SceneSpec::Backdrop::cyclorama;
        scene.backdrop_colour = s.colour("colour", scene.backdrop_colour);
        scene.transparent = s.boolean("transparent", scene.transparent);
        s.finish();
    }
    if (const toml::table* t = top.subtable("supports")) {
        Section s(*t, "supports", name);
        const std::string kind = s.string("kind", "rod", {"rod", "clips", "none"});
        scene.supports = kind == "rod" ? SceneSpec::Supports::rod
                         : kind == "clips" ? SceneSpec::Supports::clips
                                           : SceneSpec::Supports::none;
        s.finish();
    }
    if (const toml::table* t = top.subtable("output")) {
        Section s(*t, "output", name);
        scene.width = s.integer("width", scene.width, 1, 16384);
        scene.height = s.integer("height", scene.height, 1, 16384);
        scene.spp = s.integer("spp", scene.spp, 1, 1 << 20);
        scene.seed = static_cast<std::uint64_t>(s.integer("seed", static_cast<int>(scene.seed), 0, 2147483647));
        scene.max_depth = s.integer("max_depth", scene.max_depth, 1, 64);
        s.finish();
    }
    if (const toml::table* t = top.subtable("turntable")) {
        Section s(*t, "turntable", name);
        scene.turntable_frames = s.integer("frames", scene.turntable_frames, 1, 100000);
        scene.turntable_fps = s.number("fps", scene.turntable_fps, 0.0, 1000.0, true);
        s.finish();
    }
    top.finish();
    scene.studio_preset = preset == "studio";
    return scene;
}

}  // namespace foldcast::render
