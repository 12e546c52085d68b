#pragma once
// The garment surface spanned by the fold lines (docs/drape.md, "Garment grid").
//
// A vertical fibre at x (c = cos(pi x / l)) runs from the top edge through fold lines
// n, n-1, .., 0, then hangs straight.  Between fold lines it follows a smooth profile in the
// fold coordinate phi in [0, n] (0 = top edge, k = fold line n-k):
//   y = -c a_n Q^phi,   z = c zmax s_top cos(pi phi),   s_top = (-1)^n,
// which passes through every fold line exactly, has dz/dphi = 0 on them (rounded crests,
// no kinks) and whose y is smooth because a_i = a_n Q^(n-i) is an exponential in phi.
// Material depth v maps to phi by the profile's arc length, scaled so that the zig-zag
// uses the fibre length c Z of the model's straight chords (Z the centre fibre's zig-zag,
// <= h); below that the fibre hangs straight down.
#include <Eigen/Core>
#include <vector>

#include "foldcast/drape/drape.hpp"

namespace foldcast::drape::detail {

class FoldSurface {
public:
    FoldSurface(const ClothParams& params, const FoldSolution& solution);

    // Point of the fibre at x (|x| <= l/2) at material depth v (0 <= v <= h).
    Eigen::Vector3d at(double x, double v) const { return at_cos(x, std::cos(pi_over_l_ * x), v); }
    Eigen::Vector3d at_cos(double x, double c, double v) const;
    // z / zmax in [-1, 1]: which way the fold bulges here (0 without folds).
    double fold_sign(double x, double v) const;

    double span_m() const { return span_; }

private:
    // Linear interpolation in the tables indexed by t = v / (c h) in [0, 1].
    void profile(double t, double& amplitude, double& z_profile) const;

    double span_, pi_over_l_;
    double zig_height_;  // Z with folds, 0 without (the fibre hangs straight from the top)
    double zmax_, lowest_amplitude_;
    std::vector<double> amplitude_table_, z_table_;  // a(phi(t)), s_top cos(pi phi(t))
};

// Positions of an nu x nv material grid on the surface (row-major, row 0 = top edge).
// Each material row is spread over its curve on the surface by arc length, so the
// stretch along a row is uniform; the top row is the top edge with u its arc length.
void grid_positions(const FoldSurface& surface, const ClothParams& params, GridSize grid, std::vector<Vec3f>& positions,
                    std::vector<float>* fold_sign = nullptr);

std::vector<Triangle> grid_triangles(GridSize grid);
std::vector<Vec2f> grid_uvs(const ClothParams& params, GridSize grid);
Stretch grid_stretch(const std::vector<Vec3f>& positions, const ClothParams& params, GridSize grid);
void validate_grid(GridSize grid);

// The garment's vertex positions for the whole cloth: the bay grid repeated over
// params.bays() bays (sharing their inner support columns) and sheared by the support
// drop (supports.cpp).  Needs (grid.nu - 1) divisible by the bays (else InputError).
void garment_positions(const ClothParams& params, const FoldSolution& solution, GridSize grid,
                       std::vector<Vec3f>& positions, std::vector<float>* fold_sign = nullptr);
void validate_bay_grid(const ClothParams& params, GridSize grid);
// Row-0 vertex indices of the supports, left to right.
std::vector<int> support_columns(const ClothParams& params, GridSize grid);

}  // namespace foldcast::drape::detail
