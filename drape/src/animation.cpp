// Folds forming: the supports slide inward from the full width (inset 0) to the target
// inset with a smooth ease-in/ease-out, each frame a fresh solve and grid (built in
// parallel), then relaxed towards isometry in order, warm-started from the previous frame;
// an optional sway swings the cloth about the support line on top.  The result does not
// depend on the thread count.
#include <tbb/parallel_for.h>

#include <Eigen/Core>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

#include "foldcast/core/error.hpp"
#include "foldcast/drape/drape.hpp"
#include "foldcast/drape/relax.hpp"
#include "fold_surface.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast::drape {

namespace {
double smoothstep(double t) { return t * t * (3.0 - 2.0 * t); }

// When an animation frame's relaxation stops: at the bounds (#14: mean stretch
// <= 0.5 %, max <= 3 %) less a margin, not at the stills' 0.4 % / 2.5 %.  A frame is seen for
// a thirtieth of a second and the next frame starts from it; the iterations between the
// stills' rule and these bounds were 16 % of the animation's (docs/benchmarks.md).  The
// margin (0.01 and 0.05 points) is hundreds of times the change that rounding the
// positions to float makes to a stretch (~1e-5).
//
// Each frame smooths its threads for 1 iteration, not the stills' 40: a frame starts from the
// previous relaxed one, and the phase is paid every frame (256x256 x 120 frames: 1.4x the
// time of none, the last frame's 90th-percentile turn between quads 0.25 rad against 0.60;
// 2 or 5 iterations 1.8x / 2.4x for 0.22 / 0.18; docs/benchmarks.md).
//
// In single precision: 0.6x the CPU, 1.4 % more iterations (docs/benchmarks.md).
//
// What made a warm-started frame slow was not its start but the damping and the last few
// edges over the max (the mean was met in a few iterations, the max then fell by a few per
// cent per iteration); docs/benchmarks.md, "Animation relax: half the iterations":
// - the proximal term (every vertex held towards where it is) at a sixteenth of the stills',
//   the fold-line pull at half: the start already carries the previous frame's fold layout;
// - the projections over-relaxed (2: through the rest length), whose fixed point holds the
//   stretched edges nearer their rest length;
// - the edges still beyond the max once the rest is within it brought back by strain limiting
//   in windows around them (strain_windows.hpp) instead of by more iterations.
// At 256x256 x 120 frames: 0.52x the iterations (1906 -> 996), the last frame's turn 0.19 rad
// against 0.26, the crests on the centre fibre a median 5.0 mm from the model's (3.2 before),
// the last frame's within 9.4 mm (3.9).  Then the windows settled into a band instead of to
// the rest lengths (the top row's stretched runs, which the global iterations had carried for
// tens of iterations a frame, settle): 996 -> 682, turn 0.18, crests a median 4.3 mm off
// (docs/benchmarks.md, "Windows that settle into a band").
RelaxSettings frame_settings() {
    RelaxSettings settings;
    settings.target_mean = 0.0049;
    settings.target_max = 0.0295;
    settings.smoothing_iterations = 1;
    settings.single_precision = true;
    settings.anchor_weight = 0.05;
    settings.proximal_share = 0.125;
    settings.window_fix_below_max = 0.1;
    settings.over_relaxation = 2.0;
    settings.report_stretch = false;
    return settings;
}

// How much of the last frame's change of the relaxation's offset from the model (relaxed -
// model) a frame's start carries on: the offset drifts smoothly from frame to frame, but
// the whole change overshoots (it holds the last relaxation's stopping point, not only the
// trend).  Measured in docs/benchmarks.md.
constexpr float kOffsetTrend = 0.5f;

// Relaxes the model's frames in order, each starting from the previous relaxed frame moved
// by the change of the model between the two frames and by half the last change of the
// relaxation's offset (warm start: a few iterations where a cold start takes tens).  One
// factorisation serves every frame.  Sequential by nature;
// each relaxation is parallel inside and deterministic, so the bytes do not depend on the
// thread count.
template <typename Done>
void relax_frames(const ClothParams& params, GridSize grid, std::vector<std::vector<Vec3f>>& frames, Done&& done) {
    const GridRelaxer relaxer(params, grid, detail::support_columns(params, grid),  // build_garment's supports
                              frame_settings());
    // The frame's model moves out of frames[f] and the relaxed frame in; the model two frames
    // back gives its storage to the next start: no per-frame copies or allocations.
    std::vector<Vec3f> model, previous_model, model_before, start;
    for (std::size_t f = 0; f < frames.size(); ++f) {
        model.swap(frames[f]);
        start.resize(model.size());
        if (f == 0)
            start = model;
        else
            tbb::parallel_for(std::size_t(0), model.size(), [&](std::size_t k) {
                start[k] = frames[f - 1][k] + (model[k] - previous_model[k]);
                if (f >= 2)
                    start[k] +=
                        kOffsetTrend * ((frames[f - 1][k] - previous_model[k]) - (frames[f - 2][k] - model_before[k]));
            });
        relaxer.relax(start, model);
        frames[f].swap(start);
        start.swap(model_before);
        model_before.swap(previous_model);
        previous_model.swap(model);
        done(int(f));
    }
}
}  // namespace

double frame_inset_m(const ClothParams& params, const AnimationOptions& options, int frame) {
    if (options.frames <= 1) return params.inset_m;
    return params.inset_m * smoothstep(double(frame) / double(options.frames - 1));
}

Animation animate(const ClothParams& params, GridSize grid, const AnimationOptions& options,
                  const ProgressFn& progress) {
    validate(params);
    detail::validate_grid(grid);
    detail::validate_bay_grid(params, grid);
    if (options.frames < 1 || options.frames > 100000)
        throw InputError("frames = " + std::to_string(options.frames) + ": must be 1..100000");
    if (!std::isfinite(options.fps) || options.fps <= 0.0 || options.fps > 1000.0)
        throw InputError("fps = " + std::to_string(options.fps) + ": must be > 0 and <= 1000");
    if (!std::isfinite(options.sway_amplitude_m) || options.sway_amplitude_m < 0.0)
        throw InputError("sway amplitude = " + std::to_string(options.sway_amplitude_m) +
                         " m: must be a finite number >= 0");
    if (!std::isfinite(options.sway_period_s) || options.sway_period_s <= 0.0)
        throw InputError("sway period = " + std::to_string(options.sway_period_s) + " s: must be a finite number > 0");

    Animation anim;
    anim.fps = options.fps;
    anim.topology.triangles = detail::grid_triangles(grid);
    anim.topology.uvs = detail::grid_uvs(params, grid);
    anim.frames.resize(std::size_t(options.frames));
    // A pendulum-like swing out of the cloth plane: zero on the support line, growing with
    // the square of the depth, lagging a little further down.  Added to the model's frame, so
    // that the relaxation keeps the swinging cloth at its length too (added after it, a 2 cm
    // sway stretched the 256x256 frames' edges by up to 4.5 %).  In float, the sines in
    // Eigen's packets (one libm sine per vertex was 2.5 % of a 256x256 animation's CPU); the
    // frame's phase taken modulo 2 pi in double first, so that float's rounding of it stays
    // ~1e-7 rad.
    const auto add_sway = [&](int f, std::vector<Vec3f>& frame) {
        const double time_s = f / options.fps;
        const float phase_rad = float(std::fmod(2.0 * kPi * time_s / options.sway_period_s, 2.0 * kPi));
        const float inverse_height = float(1.0 / params.height_m);
        const float amplitude_m = float(options.sway_amplitude_m);
        Eigen::ArrayXf depth(Eigen::Index(frame.size()));
        for (std::size_t k = 0; k < frame.size(); ++k)
            depth[Eigen::Index(k)] = std::max(0.0f, -frame[k].y()) * inverse_height;
        const Eigen::ArrayXf swing = amplitude_m * depth.square() * (phase_rad - 0.5f * depth).sin();
        for (std::size_t k = 0; k < frame.size(); ++k) frame[k].z() += swing[Eigen::Index(k)];
    };
    std::atomic<int> done{0};
    // Progress once per frame: from the relaxation when relaxing (the slower pass).
    tbb::parallel_for(0, options.frames, [&](int f) {
        ClothParams frame_params = params;
        frame_params.inset_m = frame_inset_m(params, options, f);
        const FoldSolution solution = solve_folds(frame_params);
        std::vector<Vec3f>& frame = anim.frames[std::size_t(f)];
        detail::garment_positions(frame_params, solution, grid, frame);
        if (options.sway_amplitude_m > 0.0) add_sway(f, frame);
        const int finished = ++done;
        if (progress && !options.relax) progress("frames", double(finished) / options.frames);
    });
    if (options.relax)
        relax_frames(params, grid, anim.frames, [&](int f) {
            if (progress) progress("frames", double(f + 1) / options.frames);
        });
    return anim;
}

}  // namespace foldcast::drape
