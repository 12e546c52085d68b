// Measures of a garment grid's shape (foldcast/drape/relax.hpp): the folds along its centre
// fibre and how much its surface turns between neighbouring quads.  What the tests and the
// benchmarks hold the relaxation to.
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <utility>

#include "foldcast/core/error.hpp"
#include "foldcast/drape/relax.hpp"
#include "fold_surface.hpp"

namespace foldcast::drape {

namespace {

// Below the lowest fold line the fibre hangs straight to the hem at the fold's depth: the
// lowest crest is where the fibre stops folding, the first vertex below the segment's steepest
// flank where the fibre runs nearly straight down (|dz/dy| <= 0.1). Its deepest point is no
// measure of it: a relaxed grid bulges a few tenths of a millimetre anywhere along that
// straight run, which moved a deepest-point crest by centimetres.
int lowest_crest_vertex(const std::vector<double>& y, const std::vector<double>& z, int begin, int end) {
    constexpr double kStraightSlope = 0.1;
    auto slope = [&](int j) {
        const double dy = y[std::size_t(j + 1)] - y[std::size_t(j)];
        return dy == 0.0 ? 0.0 : std::abs((z[std::size_t(j + 1)] - z[std::size_t(j)]) / dy);
    };
    int steepest = begin;
    for (int j = begin; j + 1 < end; ++j)
        if (slope(j) > slope(steepest)) steepest = j;
    for (int j = steepest + 1; j + 1 < end; ++j)
        if (slope(j) <= kStraightSlope) return j;
    int deepest = begin;  // no straight run: the fold's deepest point
    for (int j = begin; j < end; ++j)
        if (std::abs(z[std::size_t(j)]) > std::abs(z[std::size_t(deepest)])) deepest = j;
    return deepest;
}

}  // namespace

CentreFibreFolds centre_fibre_folds(const std::vector<Vec3f>& positions, GridSize grid) {
    detail::validate_grid(grid);
    if (positions.size() != std::size_t(grid.nu) * std::size_t(grid.nv))
        throw InputError("centre fibre: positions must have one entry per grid vertex");
    // The middle column, or the mean of the two middle ones of an even grid.
    const int left = (grid.nu - 1) / 2, right = grid.nu / 2;
    std::vector<double> y(std::size_t(grid.nv)), z(std::size_t(grid.nv));
    for (int j = 0; j < grid.nv; ++j) {
        const Vec3f& a = positions[std::size_t(j * grid.nu + left)];
        const Vec3f& b = positions[std::size_t(j * grid.nu + right)];
        y[std::size_t(j)] = 0.5 * (double(a.y()) + double(b.y()));
        z[std::size_t(j)] = 0.5 * (double(a.z()) + double(b.z()));
    }
    // Sign changes of z, ignoring values within a tenth of a millimetre of the plane.
    constexpr double kPlane_m = 1e-4;
    CentreFibreFolds out;
    int sign = 0, segment_start = 0;
    std::vector<std::pair<int, int>> segments;
    for (int j = 0; j < grid.nv; ++j) {
        const double v = z[std::size_t(j)];
        const int s = v > kPlane_m ? 1 : (v < -kPlane_m ? -1 : 0);
        if (s == 0) continue;
        if (sign != 0 && s != sign) {
            ++out.sign_changes;
            segments.emplace_back(segment_start, j);
            segment_start = j;
        }
        sign = s;
    }
    segments.emplace_back(segment_start, grid.nv);
    for (const auto& [begin, end] : segments) {
        if (segments.size() > 1 && end == grid.nv) {
            out.crest_heights_m.push_back(y[std::size_t(lowest_crest_vertex(y, z, begin, end))]);
            continue;
        }
        int deepest = begin;
        for (int j = begin; j < end; ++j)
            if (std::abs(z[std::size_t(j)]) > std::abs(z[std::size_t(deepest)])) deepest = j;
        // Below the lowest fold line the fibre hangs straight at the fold's depth: that
        // plateau's crest is its top, where the fibre stops folding, not wherever a relaxed
        // grid happens to bulge a fraction of a millimetre further out along it.
        constexpr double kPlateau_m = 5e-4;
        int best = begin;
        while (std::abs(z[std::size_t(best)]) < std::abs(z[std::size_t(deepest)]) - kPlateau_m) ++best;
        double height = y[std::size_t(best)];
        if (best == deepest && best > 0 && best + 1 < grid.nv) {
            // Vertex of the parabola through |z| at best-1, best, best+1, then y interpolated.
            const double zm = std::abs(z[std::size_t(best - 1)]), z0 = std::abs(z[std::size_t(best)]),
                         zp = std::abs(z[std::size_t(best + 1)]);
            const double curvature = zm - 2.0 * z0 + zp;
            if (curvature < 0.0) {
                const double offset = std::clamp(0.5 * (zm - zp) / curvature, -0.5, 0.5);
                const double other = y[std::size_t(offset < 0.0 ? best - 1 : best + 1)];
                height += std::abs(offset) * (other - height);
            }
        }
        out.crest_heights_m.push_back(height);
    }
    return out;
}

Stretch measure_stretch(const std::vector<Vec3f>& positions, const ClothParams& params, GridSize grid) {
    detail::validate_grid(grid);
    if (positions.size() != std::size_t(grid.nu) * std::size_t(grid.nv))
        throw InputError("stretch: positions must have one entry per grid vertex");
    return detail::grid_stretch(positions, params, grid);
}

double turn_p90(const std::vector<Vec3f>& positions, GridSize grid) {
    detail::validate_grid(grid);
    if (positions.size() != std::size_t(grid.nu) * std::size_t(grid.nv))
        throw InputError("turn: positions must have one entry per grid vertex");
    const int qu = grid.nu - 1, qv = grid.nv - 1;
    std::vector<Vec3f> normal(std::size_t(qu) * std::size_t(qv));
    for (int j = 0; j < qv; ++j)
        for (int i = 0; i < qu; ++i) {
            const auto at = [&](int a, int b) {
                return positions[std::size_t(b) * std::size_t(grid.nu) + std::size_t(a)];
            };
            normal[std::size_t(j * qu + i)] =
                (at(i + 1, j + 1) - at(i, j)).cross(at(i, j + 1) - at(i + 1, j)).normalized();
        }
    std::vector<double> turn;
    for (int j = 0; j < qv; ++j)
        for (int i = 0; i < qu; ++i) {
            const Vec3f& n = normal[std::size_t(j * qu + i)];
            const auto add = [&](const Vec3f& m) {
                turn.push_back(std::acos(std::clamp(double(n.dot(m)), -1.0, 1.0)));
            };
            if (i + 1 < qu) add(normal[std::size_t(j * qu + i + 1)]);
            if (j + 1 < qv) add(normal[std::size_t((j + 1) * qu + i)]);
        }
    if (turn.empty()) return 0.0;
    std::nth_element(turn.begin(), turn.begin() + std::ptrdiff_t(turn.size() * 9 / 10), turn.end());
    return turn[turn.size() * 9 / 10];
}

HemShape hem_shape(const std::vector<Vec3f>& positions, GridSize grid) {
    if (grid.nu < 2 || grid.nv < 2 || positions.size() != std::size_t(grid.nu) * std::size_t(grid.nv))
        throw InputError("hem: positions must have one entry per grid vertex of a grid at least 2x2");
    const std::size_t row = std::size_t(grid.nv - 1) * std::size_t(grid.nu);
    const auto at = [&](int i) { return positions[row + std::size_t(i)]; };
    HemShape hem;
    float lo = at(0).x(), hi = lo;
    for (int i = 1; i < grid.nu; ++i) {
        lo = std::min(lo, at(i).x());
        hi = std::max(hi, at(i).x());
    }
    hem.width_m = double(hi) - double(lo);
    const int left = (grid.nu - 1) / 2, right = grid.nu / 2;
    hem.centre_y_m = 0.5 * (double(at(left).y()) + double(at(right).y()));
    hem.corners_y_m = 0.5 * (double(at(0).y()) + double(at(grid.nu - 1).y()));
    return hem;
}

}  // namespace foldcast::drape
