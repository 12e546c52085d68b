// Scene files (TOML), read with core's TomlSection: every key is checked for name, type and
// range; problems are one line naming the file, line, key, value and what is allowed.
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <string>
#include <vector>

#include "foldcast/core/error.hpp"
#include "foldcast/core/toml_section.hpp"
#include "foldcast/drape/drape.hpp"
#include "foldcast/render/render.hpp"

namespace foldcast::render {
namespace fs = std::filesystem;
namespace {

// Scene-file ranges: "(lo, hi]" when lo_open.
ValueRange range(double lo, double hi, bool lo_open = false) { return {lo, hi, !lo_open, true, ""}; }
const ValueRange kCoordinate = range(-1e6, 1e6);

Vec3f vec3(TomlSection& s, std::string_view key, const Vec3f& fallback, const ValueRange& r = kCoordinate) {
    const auto v = s.numbers(key, 3, r);
    return v ? Vec3f(v->cast<float>()) : fallback;
}
double number(TomlSection& s, std::string_view key, double fallback, const ValueRange& r) {
    return s.number(key, r).value_or(fallback);
}
int integer(TomlSection& s, std::string_view key, int fallback, long long lo, long long hi) {
    return static_cast<int>(s.integer(key, lo, hi).value_or(fallback));
}

constexpr const char* kDefaultLook = "linen";

// A problem between keys: reported at the first of `keys` the table holds (its file and
// line), else at the table.
[[noreturn]] void fail_at(TomlSection& s, std::initializer_list<std::string_view> keys, const std::string& message) {
    for (std::string_view key : keys)
        if (s.has(key)) s.fail(*s.node(key), message);
    s.fail_here(message);
}

void read_garment(TomlSection& s, GarmentSpec& g) {
    const fs::path path = s.path("path").value_or(fs::path{});
    std::string source = s.choice("source", {"drape", "obj", "pc2", "fca"}).value_or("");
    if (source.empty()) {
        source = "drape";
        if (!path.empty()) {
            const std::string ext = path.extension().string();
            if (ext == ".obj")
                source = "obj";
            else if (ext == ".pc2")
                source = "pc2";
            else if (ext == ".fca")
                source = "fca";
            else
                s.fail(*s.node("path"), "garment.path = \"" + path.filename().string() +
                                            "\" has an unknown extension: use .obj, .pc2 or .fca (or set source)");
        }
    }
    g.source = source == "drape" ? GarmentSpec::Source::drape
               : source == "obj" ? GarmentSpec::Source::obj
               : source == "pc2" ? GarmentSpec::Source::pc2
                                 : GarmentSpec::Source::fca;
    if (g.source != GarmentSpec::Source::drape && path.empty())
        fail_at(s, {"source"}, "garment.source = \"" + source + "\" needs garment.path");
    if (!path.empty()) g.path = path;
    if (auto topology = s.path("topology"); topology && !topology->empty()) g.topology = *topology;
    g.frame = integer(s, "frame", g.frame, 0, 1000000);
    g.scale = number(s, "scale", g.scale, range(0.0, 1e6, true));
    g.width_m = number(s, "width_m", g.width_m, range(0.0, 20.0, true));
    g.height_m = number(s, "height_m", g.height_m, range(0.0, 20.0, true));
    g.inset_m = number(s, "inset_m", g.inset_m, range(0.0, 10.0));
    if (2.0 * g.inset_m >= g.width_m)
        fail_at(s, {"inset_m", "width_m"},
                "garment.inset_m = " + std::to_string(g.inset_m) +
                    ": the supports must stay apart (need inset_m < width_m / 2)");
    g.supports = integer(s, "supports", g.supports, 2, 65);
    const double span_m = g.width_m - 2.0 * g.inset_m;
    g.support_drop_m = number(s, "support_drop_m", g.support_drop_m, range(-span_m, span_m));
    g.closure = s.choice("closure", {"hem", "paper"}).value_or(g.closure);
    if (const auto grid = s.integers("grid", 2, 2, 4096)) {
        g.grid_nu = static_cast<int>((*grid)[0]);
        g.grid_nv = static_cast<int>((*grid)[1]);
    } else {  // the default grid widened until every support is a vertex
        g.grid_nu = drape::grid_with_supports_on_vertices({g.grid_nu, g.grid_nv}, g.supports).nu;
    }
    if ((g.grid_nu - 1) % (g.supports - 1) != 0)
        fail_at(s, {"grid", "supports"},
                "garment.grid = [" + std::to_string(g.grid_nu) + ", " + std::to_string(g.grid_nv) +
                    "]: with supports = " + std::to_string(g.supports) +
                    " the first value minus one must be a multiple of " + std::to_string(g.supports - 1) +
                    " (the bays), so that every support is a grid vertex");
    g.animation_frames = integer(s, "animation_frames", g.animation_frames, 0, 100000);
    g.sway_amplitude_m = number(s, "sway_amplitude_m", g.sway_amplitude_m, range(0.0, 10.0));
    g.relax = s.boolean("relax").value_or(g.relax);
    s.finish();
}

void read_camera(TomlSection& s, CameraSpec& c) {
    c.auto_frame = s.boolean("auto").value_or(!(s.has("position") || s.has("target")));
    c.frame_share = number(s, "frame_share", c.frame_share, range(0.0, 1.0, true));
    c.azimuth_deg = number(s, "azimuth_deg", c.azimuth_deg, range(-360.0, 360.0));
    c.elevation_deg = number(s, "elevation_deg", c.elevation_deg, range(-89.0, 89.0));
    c.fov_deg = number(s, "fov_deg", c.fov_deg, range(0.0, 170.0, true));
    c.aperture_m = number(s, "aperture_m", c.aperture_m, range(0.0, 1.0));
    c.focus_distance_m = number(s, "focus_distance_m", c.focus_distance_m, range(0.0, 1e4));
    c.position = vec3(s, "position", c.position);
    c.target = vec3(s, "target", c.target);
    if (!c.auto_frame && (c.position - c.target).norm() < 1e-6f)
        fail_at(s, {"position", "target"}, "camera.position and camera.target must differ");
    s.finish();
}

AreaLight read_light(TomlSection& s, const std::string& default_name) {
    AreaLight l;
    l.name = s.string("name").value_or(default_name);
    l.position = vec3(s, "position", l.position);
    l.target = vec3(s, "target", l.target);
    if (const auto size = s.numbers("size_m", 2, range(1e-4, 100.0))) {
        l.width_m = static_cast<float>((*size)[0]);
        l.height_m = static_cast<float>((*size)[1]);
    }
    const Vec3f colour = s.colour("colour").value_or(Vec3f::Ones());
    const double intensity = number(s, "intensity", 10.0, range(0.0, 1e7));
    l.radiance = colour * static_cast<float>(intensity);
    if ((l.position - l.target).norm() < 1e-6f)
        fail_at(s, {"position", "target"}, "light '" + l.name + "': position and target must differ");
    s.finish();
    return l;
}

}  // namespace

SceneSpec load_scene(const fs::path& file) {
    const std::string name = file.string();
    const toml::table root = read_toml_file(file, "scene file");
    SceneSpec scene;
    scene.file = file;
    TomlSection top(root, "", name);

    if (const toml::table* t = top.table("garment")) {
        TomlSection s(*t, "garment", name);
        read_garment(s, scene.garment);
    }
    // look = "denim", or look = { base = "denim", appearance = { ... } } overriding keys.
    if (const toml::node* n = top.node("look")) {
        scene.look = looks::resolve_look(looks::Library::load_default(), *n, name);
    } else {
        scene.look = looks::Library::load_default().get(kDefaultLook);
    }
    if (const toml::table* t = top.table("camera")) {
        TomlSection s(*t, "camera", name);
        read_camera(s, scene.camera);
    }
    std::string preset = "studio";
    if (const toml::table* t = top.table("lights")) {
        TomlSection s(*t, "lights", name);
        // The preset is the default only when no area lights are listed.
        preset = s.choice("preset", {"studio", "none"}).value_or(t->contains("area") ? "none" : "studio");
        const ValueRange radiance = range(0.0, 1e6);
        if (s.has("environment") && t->get("environment")->is_number()) {
            scene.environment = Vec3f::Constant(static_cast<float>(*s.number("environment", radiance)));
        } else {
            scene.environment = vec3(s, "environment", Vec3f::Constant(preset == "studio" ? 0.02f : 0.0f), radiance);
        }
        scene.exposure_ev = number(s, "exposure_ev", scene.exposure_ev, range(-20.0, 20.0));
        if (const toml::array* area = s.array_of_tables("area")) {
            int i = 0;
            for (const toml::node& e : *area) {
                TomlSection ls(*e.as_table(), "lights.area[" + std::to_string(i) + "]", name);
                scene.lights.push_back(read_light(ls, "area" + std::to_string(i)));
                ++i;
            }
        }
        s.finish();
    } else {
        scene.environment = Vec3f::Constant(0.02f);
    }
    if (const toml::table* t = top.table("backdrop")) {
        TomlSection s(*t, "backdrop", name);
        const std::string kind = s.choice("kind", {"cyclorama", "none"}).value_or("cyclorama");
        scene.backdrop = kind == "none" ? SceneSpec::Backdrop::none : SceneSpec::Backdrop::cyclorama;
        scene.backdrop_colour = s.colour("colour").value_or(scene.backdrop_colour);
        scene.transparent = s.boolean("transparent").value_or(scene.transparent);
        s.finish();
    }
    if (const toml::table* t = top.table("supports")) {
        TomlSection s(*t, "supports", name);
        const std::string kind = s.choice("kind", {"rod", "clips", "none"}).value_or("rod");
        scene.supports = kind == "rod"     ? SceneSpec::Supports::rod
                         : kind == "clips" ? SceneSpec::Supports::clips
                                           : SceneSpec::Supports::none;
        s.finish();
    }
    if (const toml::table* t = top.table("output")) {
        TomlSection s(*t, "output", name);
        scene.width = integer(s, "width", scene.width, 1, 16384);
        scene.height = integer(s, "height", scene.height, 1, 16384);
        scene.spp = integer(s, "spp", scene.spp, 1, 1 << 20);
        scene.seed =
            static_cast<std::uint64_t>(s.integer("seed", 0, 2147483647).value_or(static_cast<long long>(scene.seed)));
        scene.max_depth = integer(s, "max_depth", scene.max_depth, 1, 64);
        s.finish();
    }
    if (const toml::table* t = top.table("turntable")) {
        TomlSection s(*t, "turntable", name);
        scene.turntable_frames = integer(s, "frames", scene.turntable_frames, 1, 100000);
        scene.turntable_fps = number(s, "fps", scene.turntable_fps, range(0.0, 1000.0, true));
        s.finish();
    }
    top.finish();
    scene.studio_preset = preset == "studio";
    return scene;
}

}  // namespace foldcast::render
