// foldcast drape: solve the folds of a cloth hanging from two supports, report them and
// write the garment grid (OBJ/PLY) or the animation of the folds forming (PC2 + OBJ).
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>

#include "commands.hpp"
#include "foldcast/codec/codec.hpp"
#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/core/mesh_io.hpp"
#include "foldcast/drape/drape.hpp"
#include "foldcast/drape/relax.hpp"
#include "foldcast/export/gltf.hpp"
#include "foldcast/looks/looks.hpp"
#include "gltf_report.hpp"
#include "progress_bar.hpp"
#include "resource_estimates.hpp"

namespace foldcast::app {

namespace {
namespace fs = std::filesystem;

// Defaults: a typical cotton shirting panel, 0.5 m x 0.7 m, supports 0.1 m in from each side.
struct DrapeOptions {
    bool uncompressed = false;  // x.glb animations: floats, or quantized + meshopt within
    double max_error_m = 0.0;   // this position error (0: the finest)
    double width_m = 0.5, height_m = 0.7, inset_m = 0.1;
    int supports = 2;
    double support_drop_m = 0.0;
    double thickness_mm = 0.3, young_mpa = 5.0, gsm = 150.0, weight_n_mm2 = 0.0;
    double poisson = 0.3, load_constant = looks::default_load_constant();
    std::string look, grid = "64x64", output, closure = "hem";
    int frames = 60;
    double fps = 30.0, sway_m = 0.0, sway_period_s = 2.0;
    bool json = false, verbose = false, quiet = false, no_relax = false, force = false;
};

struct Flags {  // which options the user gave (they override a look)
    CLI::Option *thickness, *young, *gsm, *weight, *poisson, *load, *frames, *grid;
};

std::string number(double v) {
    std::ostringstream s;
    s.precision(6);
    s << v;
    return s.str();
}

void require(bool ok, const std::string& flag, double value, const std::string& allowed) {
    if (!ok) throw InputError(flag + " " + number(value) + ": must be " + allowed);
}
void require_positive(const std::string& flag, double value) {
    require(std::isfinite(value) && value > 0.0, flag, value, "a finite number > 0");
}

drape::GridSize parse_grid(const std::string& text) {
    // "NUxNV": two decimal integers around one 'x', nothing else.
    const auto x = text.find('x');
    const auto parse = [](const char* first, const char* last, int& value) {
        const auto [end, ec] = std::from_chars(first, last, value);
        return ec == std::errc() && end == last && first != last;
    };
    drape::GridSize g{0, 0};
    if (x != std::string::npos && parse(text.data(), text.data() + x, g.nu) &&
        parse(text.data() + x + 1, text.data() + text.size(), g.nv) && g.nu >= 2 && g.nv >= 2 && g.nu <= 4096 &&
        g.nv <= 4096)
        return g;
    throw InputError("--grid " + text + ": must be NUxNV with 2..4096 vertices each way, e.g. 64x64");
}

enum class OutputKind { none, obj, ply, pc2, fca, glb };
OutputKind output_kind(const std::string& path) {
    if (path.empty()) return OutputKind::none;
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".obj") return OutputKind::obj;
    if (ext == ".ply") return OutputKind::ply;
    if (ext == ".pc2") return OutputKind::pc2;
    if (ext == ".fca") return OutputKind::fca;
    if (ext == ".glb") return OutputKind::glb;
    throw InputError("-o " + path + ": unknown extension '" + ext +
                     "' (allowed: .obj, .ply or .glb for the garment, .pc2, .fca or .glb for the animation)");
}

drape::ClothParams cloth_params(const DrapeOptions& o, const Flags& flags) {
    looks::Mechanics m;
    m.thickness_mm = o.thickness_mm;
    m.young_mpa = o.young_mpa;
    m.gsm = o.gsm;
    m.poisson = o.poisson;
    m.load_constant = o.load_constant;
    if (!o.look.empty()) {
        const looks::Mechanics base = looks::Library::load_default().find(o.look).mechanics;
        if (!flags.thickness->count()) m.thickness_mm = base.thickness_mm;
        if (!flags.young->count()) m.young_mpa = base.young_mpa;
        if (!flags.gsm->count()) m.gsm = base.gsm;
        if (!flags.poisson->count()) m.poisson = base.poisson;
        if (!flags.load->count()) m.load_constant = base.load_constant;
    }
    require_positive("--width-m", o.width_m);
    require_positive("--height-m", o.height_m);
    require(std::isfinite(o.inset_m) && o.inset_m >= 0.0 && o.inset_m < 0.5 * o.width_m, "--inset-m", o.inset_m,
            ">= 0 and less than half the width (" + number(0.5 * o.width_m) + " m)");
    require_positive("--thickness-mm", m.thickness_mm);
    require_positive("--young-mpa", m.young_mpa);
    if (flags.weight->count())
        require_positive("--weight-n-mm2", o.weight_n_mm2);
    else
        require_positive("--gsm", m.gsm);
    require(std::isfinite(m.poisson) && m.poisson >= 0.0 && m.poisson < 0.5, "--poisson", m.poisson, ">= 0 and < 0.5");
    require_positive("--load-constant", m.load_constant);
    require(o.supports >= 2 && o.supports <= 65, "--supports", o.supports, "2..65");
    require(std::isfinite(o.support_drop_m) && std::abs(o.support_drop_m) <= o.width_m - 2.0 * o.inset_m,
            "--support-drop-m", o.support_drop_m,
            "finite with |drop| <= the support span (" + number(o.width_m - 2.0 * o.inset_m) + " m)");
    drape::ClothParams p = drape::cloth_from_look(m, o.width_m, o.height_m, o.inset_m);
    p.supports = o.supports;
    p.support_drop_m = o.support_drop_m;
    if (!drape::closure_from_name(o.closure, p.closure))
        throw InputError("--closure \"" + o.closure + "\": must be hem or paper");
    if (flags.weight->count()) p.weight_n_per_m2 = o.weight_n_mm2 * 1e6;  // N/mm^2 -> N/m^2
    return p;
}

const char* regime_name(drape::FoldSolution::Regime r) {
    switch (r) {
        case drape::FoldSolution::Regime::wrinkled:
            return "wrinkled";
        case drape::FoldSolution::Regime::no_wrinkles:
            return "no_wrinkles";
        case drape::FoldSolution::Regime::no_feasible_folds:
            return "no_feasible_folds";
    }
    return "?";
}

nlohmann::json hem_report(const std::vector<Vec3f>& positions, drape::GridSize grid) {
    const drape::HemShape hem = drape::hem_shape(positions, grid);
    return {{"width_m", hem.width_m}, {"centre_y_m", hem.centre_y_m}, {"corners_y_m", hem.corners_y_m}};
}

nlohmann::json report(const drape::ClothParams& p, const drape::FoldSolution& s, const drape::Garment& g,
                      const DrapeOptions& o, drape::GridSize grid) {
    nlohmann::json j = {
        {"folds", s.folds},
        {"Q", s.Q},
        {"zmax_m", s.zmax_m},
        {"fold_length_m", s.fold_length_m},
        {"amplitudes_m", s.amplitudes_m},
        {"feasible_folds", s.feasible_folds},
        {"residual", s.residual},
        {"stretch_mean", g.stretch.mean},
        {"stretch_max", g.stretch.max},
        {"stretch_before_relax", {{"mean", g.stretch_analytical.mean}, {"max", g.stretch_analytical.max}}},
        {"relaxed", !o.no_relax},
        {"relax_iterations", g.relax_iterations},
        {"regime", regime_name(s.regime)},
        {"explanation", s.explanation},
        {"stress_ratio", s.stress_ratio},
        {"slack_amplitude_m", s.slack_amplitude_m},
        {"critical_stress_pa", drape::critical_stress_pa(p)},
        {"closure", drape::closure_name(s.closure)},
        {"critical_Q", s.critical_Q},
        {"cloth",
         {{"width_m", p.width_m},
          {"height_m", p.height_m},
          {"inset_m", p.inset_m},
          {"support_span_m", p.support_span_m()},
          {"supports", p.supports},
          {"support_drop_m", p.support_drop_m},
          {"thickness_m", p.thickness_m},
          {"young_pa", p.young_pa},
          {"poisson", p.poisson},
          {"weight_n_per_m2", p.weight_n_per_m2},
          {"load_constant", p.load_constant}}},
        {"grid", {grid.nu, grid.nv}},
        {"hem", hem_report(g.mesh.positions, grid)},
        {"look", o.look.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.look)},
        {"output", o.output.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.output)}};
    if (o.verbose) {
        nlohmann::json candidates = nlohmann::json::array();
        for (const auto& c : s.candidates)
            candidates.push_back({{"folds", c.folds},
                                  {"solved", c.solved},
                                  {"feasible", c.feasible},
                                  {"a0_m", c.lowest_amplitude_m},
                                  {"an_m", c.top_amplitude_m},
                                  {"zmax_m", c.zmax_m},
                                  {"fold_length_m", c.fold_length_m},
                                  {"residual", c.residual},
                                  {"why_not", c.why_not}});
        j["candidates"] = candidates;
    }
    return j;
}

void print_text(const drape::ClothParams& p, const drape::FoldSolution& s, const drape::Garment& g,
                const DrapeOptions& o) {
    std::printf("cloth %.3g x %.3g m, supports %.3g m apart; t = %.3g mm, E = %.3g MPa, w = %.4g N/m^2\n", p.width_m,
                p.height_m, p.support_span_m(), p.thickness_m * 1e3, p.young_pa * 1e-6, p.weight_n_per_m2);
    if (p.supports > 2 || p.support_drop_m != 0.0)
        std::printf(
            "%d supports (%d bays of %.3g m cloth on %.3g m), the last %.3g m lower than the first; "
            "folds per bay\n",
            p.supports, p.bays(), p.width_m / p.bays(), p.support_span_m() / p.bays(), p.support_drop_m);
    std::printf("%s\n", s.explanation.c_str());
    std::printf("folds %d, Q %.6g, zmax %.4g m, zig-zag %.4g m, S %.4g, residual %.2g\n", s.folds, s.Q, s.zmax_m,
                s.fold_length_m, s.stress_ratio, s.residual);
    std::printf("amplitudes a_0..a_n (m):");
    for (double a : s.amplitudes_m) std::printf(" %.4g", a);
    std::printf("\nfeasible fold counts:");
    for (int n : s.feasible_folds) std::printf(" %d", n);
    std::printf("%s\n", s.feasible_folds.empty() ? " none" : "");
    if (o.no_relax)
        std::printf("grid stretch: mean %.3g, max %.3g (the model's surface, not relaxed)\n", g.stretch.mean,
                    g.stretch.max);
    else
        std::printf(
            "grid stretch: mean %.3g, max %.3g after relaxation (%d iterations); model's surface: mean %.3g, max "
            "%.3g\n",
            g.stretch.mean, g.stretch.max, g.relax_iterations, g.stretch_analytical.mean, g.stretch_analytical.max);
    if (o.verbose)
        for (const auto& c : s.candidates)
            std::printf("  n=%-3d %-10s a_0 %.4g a_n %.4g zmax %.4g zig-zag %.4g residual %.2g %s\n", c.folds,
                        c.feasible ? "feasible" : (c.solved ? "solved" : "no"), c.lowest_amplitude_m, c.top_amplitude_m,
                        c.zmax_m, c.fold_length_m, c.residual, c.why_not.c_str());
}

int run_drape(const DrapeOptions& o, const Flags& flags) {
    const OutputKind kind = output_kind(o.output);
    const drape::ClothParams params = cloth_params(o, flags);
    // Without --grid, the default grid widened until every support is a vertex.
    const drape::GridSize grid = flags.grid->count()
                                     ? parse_grid(o.grid)
                                     : drape::grid_with_supports_on_vertices(parse_grid(o.grid), params.supports);
    const std::string grid_text = std::to_string(grid.nu) + "x" + std::to_string(grid.nv);
    require(o.frames >= 1 && o.frames <= 100000, "--frames", o.frames, "1..100000");
    const bool frames_kept = kind == OutputKind::pc2 || kind == OutputKind::fca;
    check_drape_work(
        grid.nu, grid.nv, frames_kept ? o.frames : 1,
        "--grid " + grid_text + (frames_kept ? " with --frames " + std::to_string(o.frames) : std::string()), o.force);
    require(std::isfinite(o.fps) && o.fps > 0.0 && o.fps <= 1000.0, "--fps", o.fps, "> 0 and <= 1000");
    require(std::isfinite(o.sway_m) && o.sway_m >= 0.0, "--sway-m", o.sway_m, "a finite number >= 0");
    require_positive("--sway-period-s", o.sway_period_s);
    if (o.max_error_m > 0.0 && !(kind == OutputKind::glb && (flags.frames->count() > 0 || o.sway_m > 0.0)))
        throw InputError("--max-error-m: only for -o x.glb animations (with --frames or --sway-m)");
    if (kind != OutputKind::none) {
        check_writable(o.output);
        if (kind == OutputKind::pc2) check_writable(fs::path(o.output).replace_extension(".obj"));
    }

    const drape::FoldSolution solution = drape::solve_folds(params);
    drape::Garment garment = drape::build_garment(params, solution, grid, !o.no_relax);

    drape::AnimationOptions anim_options;
    anim_options.frames = o.frames;
    anim_options.fps = o.fps;
    anim_options.sway_amplitude_m = o.sway_m;
    anim_options.sway_period_s = o.sway_period_s;
    anim_options.relax = !o.no_relax;
    // A .glb holds the animation when one was asked for (--frames or --sway-m), else the garment.
    const bool glb_animated = kind == OutputKind::glb && (flags.frames->count() > 0 || o.sway_m > 0.0);
    const bool animated = kind == OutputKind::pc2 || kind == OutputKind::fca || o.sway_m > 0.0 || glb_animated;
    gltf::GlbOptions glb_options;
    if (kind == OutputKind::glb && !o.look.empty()) glb_options.look = looks::Library::load_default().find(o.look);
    glb_options.compress = !o.uncompressed;
    glb_options.max_position_error_m = o.max_error_m;
    std::optional<Animation> animation;
    std::optional<gltf::GlbSummary> glb_summary;
    if (animated) {
        ProgressBar bar(o.quiet || o.json);
        animation = drape::animate(params, grid, anim_options, bar.callback());
    }

    if (kind == OutputKind::pc2) {
        write_pc2_animation(o.output, *animation);
    } else if (kind == OutputKind::fca) {  // the codec's default profile and error bound
        codec::EncodeOptions encode_options;
        // The look's name travels with the file, so that a player shows the garment in it.
        if (!o.look.empty()) encode_options.metadata.emplace_back("look", looks::Library::load_default().find(o.look).name);
        codec::write_fca(o.output, codec::encode(*animation, encode_options));
    } else if (glb_animated) {
        glb_summary = gltf::write_glb(o.output, *animation, glb_options);
    } else if (kind != OutputKind::none) {
        Mesh mesh = garment.mesh;
        if (animation) {  // the last frame, sway included
            mesh.positions = animation->frames.back();
            mesh.normals = vertex_normals(mesh.positions, mesh.topology.triangles);
        }
        if (kind == OutputKind::obj)
            write_obj(o.output, mesh);
        else if (kind == OutputKind::glb)
            glb_summary = gltf::write_glb(o.output, mesh, glb_options);
        else
            write_ply(o.output, mesh);
    }

    if (o.json) {
        nlohmann::json j = report(params, solution, garment, o, grid);
        if (animation) j["frames"] = animation->frame_count(), j["fps"] = animation->fps;
        if (glb_summary)
            j["glb"] = {{"bytes", glb_summary->bytes},
                        {"morph_targets", glb_summary->morph_targets},
                        {"compressed", glb_summary->compressed},
                        {"max_position_error_m", glb_summary->max_position_error_m}};
        std::cout << j.dump(2) << "\n";
    } else {
        print_text(params, solution, garment, o);
        if (kind == OutputKind::fca)
            std::printf("wrote %s (%zu frames at %g fps)\n", o.output.c_str(), animation->frame_count(),
                        animation->fps);
        else if (kind == OutputKind::pc2)
            std::printf("wrote %s (%zu frames at %g fps) and %s\n", o.output.c_str(), animation->frame_count(),
                        animation->fps, fs::path(o.output).replace_extension(".obj").c_str());
        else if (glb_summary)
            print_glb_summary(o.output, *glb_summary, false, o.look);
        else if (kind != OutputKind::none)
            std::printf("wrote %s (%dx%d grid)\n", o.output.c_str(), grid.nu, grid.nv);
    }
    return 0;
}
}  // namespace

Command drape_command(CLI::App& app) {
    auto o = std::make_shared<DrapeOptions>();
    auto flags = std::make_shared<Flags>();
    CLI::App* sub =
        app.add_subcommand("drape",
                           "Predict the folds of a cloth hanging from two or more supports (tension-field model, "
                           "docs/drape.md) and write the garment grid or the animation of the folds forming.\n"
                           "Defaults: a cotton shirting panel 0.5 m x 0.7 m, supports 0.1 m in from each side, "
                           "0.3 mm thick, E 5 MPa, 150 g/m^2, Poisson 0.3.");
    sub->add_option("--width-m", o->width_m, "Cloth width L: top edge length (m)")->capture_default_str();
    sub->add_option("--height-m", o->height_m, "Cloth height h (m)")->capture_default_str();
    sub->add_option("--inset-m", o->inset_m,
                    "Support inset d on each side; supports are L - 2d apart (m), 0 <= d < L/2")
        ->capture_default_str();
    sub->add_option("--supports", o->supports,
                    "Supports equally spaced under the top edge, 2..65: supports - 1 bays share the "
                    "inner ones and each folds with its share of the width (--grid NU - 1 a multiple of the bays)")
        ->capture_default_str();
    sub->add_option(
           "--support-drop-m", o->support_drop_m,
           "How much lower the last support hangs than the first (m; negative: higher); the pattern is sheared")
        ->capture_default_str();
    sub->add_option("--closure", o->closure,
                    "How n and zmax are chosen: hem (the top edge and hem keep their length, the most folds "
                    "whose zig-zag fits) or paper (the original paper's 5 % iteration, to reproduce its tables; "
                    "docs/drape.md)")
        ->capture_default_str();
    sub->add_option("--look", o->look,
                    "Fabric look for the mechanics: a name (see `foldcast looks`) or a look "
                    ".toml file; the flags below override its values");
    flags->thickness = sub->add_option("--thickness-mm", o->thickness_mm, "Thickness t (mm)")->capture_default_str();
    flags->young = sub->add_option("--young-mpa", o->young_mpa, "Young's modulus E (MPa)")->capture_default_str();
    flags->gsm = sub->add_option("--gsm", o->gsm, "Fabric weight (g/m^2)")->capture_default_str();
    flags->weight = sub->add_option("--weight-n-mm2", o->weight_n_mm2, "Weight per area w (N/mm^2), instead of --gsm");
    flags->weight->excludes(flags->gsm);
    flags->poisson = sub->add_option("--poisson", o->poisson, "Poisson's ratio nu")->capture_default_str();
    flags->load = sub->add_option("--load-constant", o->load_constant, "Load constant c (default 23.9 pi^2 / 12)")
                      ->capture_default_str();
    flags->grid = sub->add_option("--grid", o->grid,
                                  "Material grid NUxNV (vertices across x down); without it, with --supports N, NU "
                                  "is the nearest above the default that puts every support on a vertex")
                      ->capture_default_str();
    flags->frames =
        sub->add_option("--frames", o->frames,
                        "Animation frames, supports moving in from d = 0 (for -o x.pc2, x.fca, x.glb or --sway-m)")
            ->capture_default_str();
    sub->add_option("--fps", o->fps, "Animation frame rate")->capture_default_str();
    sub->add_option("--sway-m", o->sway_m, "Sway amplitude at the hem on top of the animation (m)")
        ->capture_default_str();
    sub->add_option("--sway-period-s", o->sway_period_s, "Sway period (s)")->capture_default_str();
    sub->add_flag("--no-relax", o->no_relax,
                  "Keep the model's surface as it is (by default the grid is relaxed towards "
                  "isometry so that the cloth keeps its length)");
    sub->add_flag("--uncompressed", o->uncompressed,
                  "x.glb animations: float attributes, without KHR_mesh_quantization / EXT_meshopt_compression");
    sub->add_option("--max-error-m", o->max_error_m,
                    "x.glb animations: the largest position error the quantization may add (m; default: the finest)")
        ->check(finite_in(0.0, 1.0))
        ->excludes("--uncompressed");
    sub->add_flag("--json", o->json, "Print the result as one JSON object");
    sub->add_flag("--verbose", o->verbose, "Also report every fold count tried");
    sub->add_flag("-q,--quiet", o->quiet, "No progress bar");
    sub->add_flag("--force", o->force, "Work even when the memory or time estimate exceeds this machine's");
    sub->add_option(
        "-o,--output", o->output,
        "Write x.obj or x.ply (garment, last frame), x.pc2 (animation + x.obj beside), x.fca (compressed animation) "
        "or x.glb (glTF 2.0: the garment with --look's material; with --frames or --sway-m the animation)");
    return Command{sub, [o, flags] { return run_drape(*o, *flags); }};
}

}  // namespace foldcast::app
