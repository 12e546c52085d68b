#pragma once
// Relaxation of a garment grid towards isometry (docs/drape.md, "Relaxation"): the
// analytical fold surface stretches the cloth; a local/global projection (projective
// dynamics, the global step solved by DCTs) brings every warp and weft edge back to its
// rest length while the support vertices stay pinned and every vertex is pulled softly
// towards the model's surface, so the fold layout survives.
//
// Its room, drape/relax/, in the order an iteration uses it: relax.cpp (the local step and
// the iteration), grid_solver.* (the global step: the grid's Laplacian solved by dct.*, the
// pins by a capacitance matrix), anderson.* (acceleration of the fixed-point map),
// thread_directions.* (the smoothing phase's blended edge directions), strain_windows.*
// (animation frames' strain limiting around the last long edges).
#include <memory>
#include <vector>

#include "foldcast/drape/drape.hpp"

namespace foldcast::drape {

struct RelaxSettings {
    double target_mean = 0.004;  // stop once mean |len/rest - 1| <= this ...
    double target_max = 0.025;   // ... and max <= this (docs/drape.md has the measured values)
    int max_iterations = 300;
    // Pull of a centre-fibre crest towards the model's height and depth, relative to an
    // edge's pull towards its rest length, for a 64-column grid (scaled as 1/nu).
    double anchor_weight = 0.1;
    // Thread smoothing (docs/drape.md): for the first smoothing_iterations the edges are
    // projected onto their directions blended with their neighbours' along the thread (weight
    // `smoothing`), so that threads which must lengthen bend instead of kinking at every
    // vertex; then plain iterations until the stretch bounds.  0 iterations: none.
    double smoothing = 0.5;
    int smoothing_iterations = 40;
    // The iterations' per-vertex arrays in float instead of double (sums, dot products and the
    // DCTs' arithmetic stay double): about 0.6x the CPU per iteration at 256x256, where the
    // arrays do not fit in the caches.  The result is as close to isometric, but not the same
    // cloth: the relaxation amplifies rounding into where the cloth crumples (a still's vertices
    // moved by millimetres), so stills keep double and animation frames, warm-started from
    // the previous frame, use float.
    bool single_precision = false;
    // The proximal term (every vertex pulled towards where it is: the matrix's diagonal)
    // relative to anchor_weight (1: the stills').  Lower, each iteration moves the cloth
    // further; the fold-line pull stays anchor_weight (docs/drape.md, "Animation").  0 < x <= 1.
    double proximal_share = 1.0;
    // > 0: once the mean is within target_mean and the max within this, the edges still
    // beyond target_max are brought back by strain limiting in windows around them
    // (strain_windows.hpp) instead of by more global iterations; 0: never.
    double window_fix_below_max = 0.0;
    // The local step's projections carried past the rest length by this factor (1: plain
    // projection; 2: reflection through it).  Over-relaxed, the iterations' fixed point holds
    // the stretched edges nearer their rest length, so the max falls below target_max sooner
    // (docs/drape.md, "Animation").  1..2.
    double over_relaxation = 1.0;
    // false: RelaxReport's before and after are left 0 (animation frames, whose reports
    // nobody reads: the two passes over the grid were 3.5 % of the animation's CPU).
    bool report_stretch = true;
};

struct RelaxReport {
    Stretch before, after;
    int iterations = 0;
    int window_fixes = 0;  // strain limiting in windows (RelaxSettings::window_fix_below_max)
};

// Prefactored for one grid, its rest lengths (from params' width and height) and its pinned
// vertices; relax() may be called for many frames of that grid (the animation does).
class GridRelaxer {
public:
    GridRelaxer(const ClothParams& params, GridSize grid, std::vector<int> pinned, RelaxSettings settings = {});
    ~GridRelaxer();
    GridRelaxer(GridRelaxer&&) noexcept;
    GridRelaxer& operator=(GridRelaxer&&) noexcept;

    // positions: the start (the analytical grid, or the previous frame moved by the change
    // of the model); targets: the model's surface for this frame.  Pinned vertices are set
    // to their targets exactly.  Deterministic whatever the thread count.
    RelaxReport relax(std::vector<Vec3f>& positions, const std::vector<Vec3f>& targets) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// What a grid's centre fibre (the middle column, or the mean of the two middle ones) shows
// of its folds: how often the out-of-plane displacement z changes sign going down, and the
// height y of each crest (the vertex of largest |z| between two sign changes, refined by a
// parabola; for a plateau within 0.5 mm of that depth, its top), top first.  The lowest crest,
// below which the fibre hangs straight to the hem, is where the fibre stops folding: the first
// vertex below that segment's steepest flank with |dz/dy| <= 0.1.  The same analysis runs on
// Blender's cloth (bench/).
struct CentreFibreFolds {
    int sign_changes = 0;
    std::vector<double> crest_heights_m;  // y of each crest, from the top edge down
};
CentreFibreFolds centre_fibre_folds(const std::vector<Vec3f>& positions, GridSize grid);

// How the hem (the grid's last row) hangs: its extent across (max x - min x), the height y of
// its centre vertex (the mean of the two middle ones) and the mean height of its two corners.
// The same measures run on Blender's cloth (bench/).
struct HemShape {
    double width_m = 0.0;
    double centre_y_m = 0.0;
    double corners_y_m = 0.0;
};
HemShape hem_shape(const std::vector<Vec3f>& positions, GridSize grid);

// How far a grid is from its cut: mean and max |length / rest - 1| over its warp and weft edges,
// the rest lengths from params' width and height.
Stretch measure_stretch(const std::vector<Vec3f>& positions, const ClothParams& params, GridSize grid);

// How much the surface turns between neighbouring grid quads: the 90th percentile, over every
// pair of quads sharing a warp or weft edge, of the angle between their normals (from their
// diagonals), in radians.  Crumpling shows up as a turn at every vertex.
double turn_p90(const std::vector<Vec3f>& positions, GridSize grid);

}  // namespace foldcast::drape
