// Folds forming: the supports slide inward from the full width (inset 0) to the target
// inset with a smooth ease-in/ease-out, each frame a fresh solve and grid; an optional sway
// swings the cloth about the support line on top.  Frames are independent, so they are
// built in parallel and the result does not depend on the thread count.
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <string>

#include "foldcast/core/error.hpp"
#include "foldcast/drape.hpp"
#include "fold_surface.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast::drape {

namespace {
double smoothstep(double t) { return t * t * (3.0 - 2.0 * t); }
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
        throw InputError("sway period = " + std::to_string(options.sway_period_s) +
                         " s: must be a finite number > 0");

    Animation anim;
    anim.fps = options.fps;
    anim.topology.triangles = detail::grid_triangles(grid);
    anim.topology.uvs = detail::grid_uvs(params, grid);
    anim.frames.resize(std::size_t(options.frames));
    std::atomic<int> done{0};
    tbb::parallel_for(0, options.frames, [&](int f) {
        ClothParams frame_params = params;
        frame_params.inset_m = frame_inset_m(params, options, f);
        const FoldSolution solution = solve_folds(frame_params);
        std::vector<Vec3f>& positions = anim.frames[std::size_t(f)];
        detail::garment_positions(frame_params, solution, grid, positions);
        if (options.sway_amplitude_m > 0.0) {
            // A pendulum-like swing out of the cloth plane: zero on the support line,
            // growing with the square of the depth, lagging a little further down.
            const double time_s = f / options.fps;
            const double h = params.height_m;
            for (Vec3f& p : positions) {
                const double depth = std::max(0.0, -double(p.y())) / h;
                const double phase = 2.0 * kPi * time_s / options.sway_period_s - 0.5 * depth;
                p.z() += float(options.sway_amplitude_m * depth * depth * std::sin(phase));
            }
        }
        const int finished = ++done;
        if (progress) progress("frames", double(finished) / options.frames);
    });
    return anim;
}

}  // namespace foldcast::drape
