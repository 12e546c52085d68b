#include "fold_surface.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "foldcast/core/error.hpp"
#include "foldcast/core/math.hpp"
#include "fold_geometry.hpp"

namespace foldcast::drape::detail {

FoldSurface::FoldSurface(const ClothParams& params, const FoldSolution& solution)
    : span_(params.support_span_m()),
      pi_over_l_(kPi / params.support_span_m()),
      zig_height_(solution.folds > 0 ? zig_zag_length_m(solution.amplitudes_m, solution.zmax_m) : 0.0),
      zmax_(solution.folds > 0 ? solution.zmax_m : 0.0),
      lowest_amplitude_(solution.amplitudes_m.empty() ? 0.0 : solution.amplitudes_m.front()) {
    const int n = solution.folds;
    if (n <= 0) return;
    const double top_amplitude = solution.amplitudes_m.back();
    const double log_q = std::log(solution.Q);
    const double s_top = n % 2 == 0 ? 1.0 : -1.0;
    // Arc length G(phi) of the profile (per unit c), by the trapezoid rule on a fine grid.
    const int samples = 256 * n;
    const double dphi = double(n) / samples;
    std::vector<double> arc(static_cast<std::size_t>(samples) + 1, 0.0);
    const auto speed = [&](double phi) {
        return std::hypot(top_amplitude * log_q * std::exp(phi * log_q), kPi * zmax_ * std::sin(kPi * phi));
    };
    double previous = speed(0.0);
    for (int k = 1; k <= samples; ++k) {
        const double current = speed(k * dphi);
        arc[std::size_t(k)] = arc[std::size_t(k - 1)] + 0.5 * (previous + current) * dphi;
        previous = current;
    }
    // Tables over t = G(phi) / G(n), uniform in t.
    const int entries = std::max(2048, 256 * n);
    amplitude_table_.resize(std::size_t(entries) + 1);
    z_table_.resize(std::size_t(entries) + 1);
    std::size_t k = 0;
    for (int m = 0; m <= entries; ++m) {
        const double target = arc.back() * m / entries;
        while (k + 1 < arc.size() - 1 && arc[k + 1] < target) ++k;
        const double span = arc[k + 1] - arc[k];
        const double frac = span > 0.0 ? std::clamp((target - arc[k]) / span, 0.0, 1.0) : 0.0;
        const double phi = (double(k) + frac) * dphi;
        amplitude_table_[std::size_t(m)] = top_amplitude * std::exp(phi * log_q);
        z_table_[std::size_t(m)] = s_top * std::cos(kPi * phi);
    }
}

void FoldSurface::profile(double t, double& amplitude, double& z_profile) const {
    const double pos = std::clamp(t, 0.0, 1.0) * double(amplitude_table_.size() - 1);
    const std::size_t i = std::min(static_cast<std::size_t>(pos), amplitude_table_.size() - 2);
    const double f = pos - double(i);
    amplitude = amplitude_table_[i] + f * (amplitude_table_[i + 1] - amplitude_table_[i]);
    z_profile = z_table_[i] + f * (z_table_[i + 1] - z_table_[i]);
}

Eigen::Vector3d FoldSurface::at_cos(double x, double c, double v) const {
    c = std::max(c, 0.0);
    const double zig = c * zig_height_;
    if (v < zig) {
        double amplitude, z_profile;
        profile(v / zig, amplitude, z_profile);
        return {x, -c * amplitude, c * zmax_ * z_profile};
    }
    // Below the lowest fold line (whose sign is +1) the fibre hangs straight down.
    return {x, -c * lowest_amplitude_ - (v - zig), c * zmax_};
}

double FoldSurface::fold_sign(double x, double v) const {
    if (zmax_ <= 0.0) return 0.0;
    return std::clamp(at(x, v).z() / zmax_, -1.0, 1.0);
}

void validate_grid(GridSize grid) {
    constexpr int kMaxSide = 8192;
    if (grid.nu < 2 || grid.nv < 2 || grid.nu > kMaxSide || grid.nv > kMaxSide)
        throw InputError("grid " + std::to_string(grid.nu) + "x" + std::to_string(grid.nv) + ": each side must be 2.." +
                         std::to_string(kMaxSide) + " vertices");
}

void grid_positions(const FoldSurface& surface, const ClothParams& params, GridSize grid, std::vector<Vec3f>& positions,
                    std::vector<float>* fold_sign) {
    const auto nu = static_cast<std::size_t>(grid.nu);
    const auto nv = static_cast<std::size_t>(grid.nv);
    positions.resize(nu * nv);
    if (fold_sign) fold_sign->resize(nu * nv);
    const double half = 0.5 * surface.span_m();
    const double pi_over_l = kPi / surface.span_m();
    // Fine x samples shared by all rows; the supports get c = 0 exactly.
    const std::size_t samples = std::max<std::size_t>(2 * nu, 256);
    std::vector<double> xs(samples + 1), cs(samples + 1);
    for (std::size_t k = 0; k <= samples; ++k) {
        xs[k] = -half + surface.span_m() * double(k) / double(samples);
        cs[k] = (k == 0 || k == samples) ? 0.0 : std::cos(pi_over_l * xs[k]);
    }
    // Column positions x_i spreading row v uniformly by arc length along its curve.
    const auto columns = [&](double v) {
        std::vector<double> arc(samples + 1, 0.0), x(nu);
        Eigen::Vector3d previous = surface.at_cos(xs[0], cs[0], v);
        for (std::size_t k = 1; k <= samples; ++k) {
            const Eigen::Vector3d p = surface.at_cos(xs[k], cs[k], v);
            arc[k] = arc[k - 1] + (p - previous).norm();
            previous = p;
        }
        std::size_t k = 0;
        for (std::size_t i = 0; i < nu; ++i) {
            const double target = arc.back() * double(i) / double(nu - 1);
            while (k + 1 < samples && arc[k + 1] < target) ++k;
            const double seg = arc[k + 1] - arc[k];
            const double f = seg > 0.0 ? std::clamp((target - arc[k]) / seg, 0.0, 1.0) : 0.0;
            x[i] = xs[k] + f * (xs[k + 1] - xs[k]);
        }
        x.front() = -half;
        x.back() = half;
        return x;
    };
    tbb::parallel_for(std::size_t(0), nv, [&](std::size_t j) {
        const double v = params.height_m * double(j) / double(nv - 1);
        const std::vector<double> x = columns(v);
        for (std::size_t i = 0; i < nu; ++i) {
            const double c = (i == 0 || i == nu - 1) ? 0.0 : std::cos(pi_over_l * x[i]);
            const Eigen::Vector3d p = surface.at_cos(x[i], c, v);
            positions[j * nu + i] = p.cast<float>();
            if (fold_sign) (*fold_sign)[j * nu + i] = static_cast<float>(surface.fold_sign(x[i], v));
        }
    });
}

std::vector<Triangle> grid_triangles(GridSize grid) {
    const auto nu = static_cast<std::uint32_t>(grid.nu);
    const auto nv = static_cast<std::uint32_t>(grid.nv);
    std::vector<Triangle> triangles;
    triangles.reserve(std::size_t(nu - 1) * (nv - 1) * 2);
    // Counter-clockwise seen from +z for the flat cloth: normals face the viewer.
    for (std::uint32_t j = 0; j + 1 < nv; ++j)
        for (std::uint32_t i = 0; i + 1 < nu; ++i) {
            const std::uint32_t k = j * nu + i;
            triangles.push_back({k, k + nu, k + 1});
            triangles.push_back({k + 1, k + nu, k + nu + 1});
        }
    return triangles;
}

std::vector<Vec2f> grid_uvs(const ClothParams& params, GridSize grid) {
    std::vector<Vec2f> uvs(std::size_t(grid.nu) * std::size_t(grid.nv));
    for (int j = 0; j < grid.nv; ++j)
        for (int i = 0; i < grid.nu; ++i)
            uvs[std::size_t(j) * std::size_t(grid.nu) + std::size_t(i)] =
                Vec2f(float(params.width_m * i / (grid.nu - 1)), float(params.height_m * j / (grid.nv - 1)));
    return uvs;
}

Stretch grid_stretch(const std::vector<Vec3f>& positions, const ClothParams& params, GridSize grid) {
    const auto nu = static_cast<std::size_t>(grid.nu);
    const auto nv = static_cast<std::size_t>(grid.nv);
    const double rest_u = params.width_m / double(nu - 1);
    const double rest_v = params.height_m / double(nv - 1);
    double sum = 0.0, max = 0.0;
    std::size_t count = 0;
    const auto edge = [&](std::size_t a, std::size_t b, double rest) {
        const double len = (positions[a].cast<double>() - positions[b].cast<double>()).norm();
        const double s = std::abs(len / rest - 1.0);
        sum += s;
        max = std::max(max, s);
        ++count;
    };
    for (std::size_t j = 0; j < nv; ++j)
        for (std::size_t i = 0; i < nu; ++i) {
            if (i + 1 < nu) edge(j * nu + i, j * nu + i + 1, rest_u);
            if (j + 1 < nv) edge(j * nu + i, (j + 1) * nu + i, rest_v);
        }
    return {count ? sum / double(count) : 0.0, max};
}

}  // namespace foldcast::drape::detail
