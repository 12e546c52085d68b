#pragma once
// drape: tension-field wrinkle model of a cloth hanging from supports (docs/drape.md), the
// garment grid built on its fold lines, and the animation of folds forming.
//
// Frame: origin midway between the supports, x to the right (supports at x = +/- l/2),
// y up (the cloth hangs towards -y from y = 0), z out of the cloth plane towards the viewer.
#include <string>
#include <vector>

#include "foldcast/core/mesh.hpp"
#include "foldcast/core/progress.hpp"
#include "foldcast/looks/looks.hpp"

namespace foldcast::drape {

// How the fold count and the fold depth are closed (docs/drape.md, "The closure"):
// hem: the top edge and the hem keep their length, the most folds whose zig-zag fits;
// paper: the original paper's iteration (a_0 = 1.01 h, zmax stepped up, n from the centre
// fibre, until the top edge is within 5 % of L), to reproduce its published tables.
enum class Closure { hem, paper };
const char* closure_name(Closure closure);
// "hem" or "paper"; false for any other name.
bool closure_from_name(const std::string& name, Closure& closure);

struct ClothParams {
    double width_m = 0.5;   // L: top edge length
    double height_m = 0.7;  // h
    double inset_m = 0.1;   // d: supports are l = L - 2d apart
    double thickness_m = 0.3e-3;
    double young_pa = 5e6;
    double poisson = 0.3;
    double weight_n_per_m2 = 1.47;                          // w
    double load_constant = looks::default_load_constant();  // c
    // More supports (docs/drape.md): `supports` equally spaced under the top edge, the
    // outer two at the corners moved in by inset_m, so supports - 1 bays share their inner
    // supports and each folds by the model with its share of the width.  The last support
    // hangs support_drop_m lower than the first (negative: higher); the pattern is sheared.
    int supports = 2;
    double support_drop_m = 0.0;
    Closure closure = Closure::hem;

    double support_span_m() const { return width_m - 2.0 * inset_m; }
    int bays() const { return supports - 1; }
};

// One bay as a two-support cloth: width L/bays, inset d/bays, level.  The fold solve and
// the stress ratio are those of a bay.
ClothParams bay_params(const ClothParams& params);

ClothParams cloth_from_look(const looks::Mechanics& mechanics, double width_m, double height_m, double inset_m);

// Throws InputError naming the parameter and the allowed range: sizes, thickness, modulus,
// weight and load constant finite and > 0, 0 <= inset < width/2, 0 <= poisson < 0.5,
// 2 <= supports <= 65, |support drop| <= support span.
void validate(const ClothParams& params);

// sigma_cr = c E t^2 / (l^2 (1 - nu^2)), in Pa, l the span of one bay.
double critical_stress_pa(const ClothParams& params);
// S = sigma_cr t / (w h); S >= 1: the cloth is too stiff to wrinkle.
double stress_ratio(const ClothParams& params);
// The root Q > 1 of (1-S) Q^2 - (2+S) Q + 1 = 0, or 0 when S >= 1 (no such root).
double amplitude_ratio(double stress_ratio);
// Length of the curve (x, A cos(pi x/l)) over [-l/2, l/2]: (2l/pi) sqrt(1+k^2) E(k^2/(1+k^2))
// with k = pi A / l (complete elliptic integral of the second kind).
double top_edge_length_m(double span_m, double amplitude_m);
// The A >= 0 with top_edge_length_m(span_m, A) = length_m (needs length_m >= span_m).
double top_edge_amplitude_m(double span_m, double length_m);

// One candidate number of folds and its solve of the length equations.
struct FoldCandidate {
    int folds = 0;
    bool solved = false;              // the top edge and hem length equations have a solution (zmax > 0, a_0 > 0)
    bool feasible = false;            // solved with a zig-zag that fits the centre fibre (fold_length_m <= h)
    double top_amplitude_m = 0.0;     // a_n
    double lowest_amplitude_m = 0.0;  // a_0 = a_n Q^n
    double zmax_m = 0.0;
    double fold_length_m = 0.0;  // Z: length of the centre fibre's zig-zag through the n folds
    double residual = 0.0;       // max relative residual of the length equations
    std::string why_not;         // when not feasible
};

struct FoldSolution {
    int folds = 0;   // n (per bay); 0 = no wrinkles (smooth sag) or no slack
    double Q = 1.0;  // amplitude ratio a_{i-1}/a_i
    double zmax_m = 0.0;
    // Z, the centre fibre's zig-zag length; the rest h - Z hangs straight below the lowest
    // fold line.  Z > h only when even one fold is longer than the cloth: the hem cuts it.
    double fold_length_m = 0.0;
    std::vector<double> amplitudes_m;  // a_0 (lowest fold line) .. a_n (top edge sag)
    std::vector<int> feasible_folds;
    std::vector<FoldCandidate> candidates;  // every n tried, for verbose output
    double residual = 0.0;                  // max relative residual of the chosen solution
    double stress_ratio = 0.0;              // S = sigma_cr t / (w h); S >= 1: no wrinkles
    double slack_amplitude_m = 0.0;         // A = sqrt(a_n^2 + zmax^2), fixed by the top edge length
    Closure closure = Closure::hem;         // which closure chose n and zmax
    // Q of the critical-stress equation; the paper closure reports Q = (a_0/a_n)^(1/n) as the
    // paper does, which differs from it once n is rounded to an integer.
    double critical_Q = 1.0;
    int closure_steps = 0;  // paper closure: steps of zmax until the top edge was within 5 %
    enum class Regime { wrinkled, no_wrinkles, no_feasible_folds } regime = Regime::wrinkled;
    std::string explanation;  // one sentence for users, always set
};

// Pure function: no I/O.  Throws InputError for invalid params (see validate).
FoldSolution solve_folds(const ClothParams& params);

// A sampled fold line i (0 = lowest) of one bay: points (x, -y_i(x), z_i(x)) in metres, and
// its sign (+1 crest towards the viewer, -1 valley).  With more supports every bay's lines
// are listed (bay 0 first), sheared by the support drop.
struct FoldLine {
    int index = 0;
    int sign = 1;
    int bay = 0;
    std::vector<Eigen::Vector3d> points;
};
std::vector<FoldLine> fold_lines(const ClothParams& params, const FoldSolution& solution, int samples = 129);

struct GridSize {
    int nu = 64;  // vertices across
    int nv = 64;  // vertices down
};

// The grid with at least grid.nu columns that puts every one of `supports` supports on a
// vertex ((nu - 1) a multiple of the bays): what a user who gives supports but no grid gets.
inline GridSize grid_with_supports_on_vertices(GridSize grid, int supports) {
    const int bays = supports > 1 ? supports - 1 : 1;
    grid.nu = 1 + (grid.nu - 1 + bays - 1) / bays * bays;
    return grid;
}

struct Stretch {
    double mean = 0.0;  // mean |len/rest - 1| over grid edges
    double max = 0.0;
};

struct Garment {
    Mesh mesh;                          // positions, triangles, UVs in metres, normals
    std::vector<float> fold_sign;       // per vertex in [-1,1]: which way the local fold bulges
    std::vector<int> support_vertices;  // fixed points: every support, inner ones too (row 0)
    Stretch stretch;                    // of the grid returned (relaxed unless relax = false)
    Stretch stretch_analytical;         // of the model's surface before relaxation
    int relax_iterations = 0;
};

// Needs (grid.nu - 1) divisible by the bays, so that every support is a grid vertex.
// relax: bring the analytical grid towards isometry (foldcast/drape/relax.hpp), every support pinned;
// false keeps the model's surface as it is.
Garment build_garment(const ClothParams& params, const FoldSolution& solution, GridSize grid, bool relax = true);

struct AnimationOptions {
    int frames = 60;
    double fps = 30.0;
    double sway_amplitude_m = 0.0;  // optional sway at the hem, added to the model's frames before relaxing; 0 = none
    double sway_period_s = 2.0;
    bool relax = true;  // each frame relaxed towards isometry, warm-started from the last
};

// Inset of the supports in frame `frame`: 0 in the first frame, params.inset_m in the last,
// eased in and out (smoothstep) in between.
double frame_inset_m(const ClothParams& params, const AnimationOptions& options, int frame);

// Frames in which the supports move inward from d = 0 to params.inset_m (folds forming),
// plus optional sway.  Deterministic.
Animation animate(const ClothParams& params, GridSize grid, const AnimationOptions& options,
                  const ProgressFn& progress = {});

}  // namespace foldcast::drape
