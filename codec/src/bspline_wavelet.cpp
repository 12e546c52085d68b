#include "bspline_wavelet.hpp"

#include <Eigen/SVD>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace foldcast::codec {
namespace {
using Sparse = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;

// Clamped knot vector of level j: four zeros, the interior knots k / 2^j, four ones.
double knot(int level, long index) {
    const long intervals = 1L << level;
    return std::clamp(static_cast<double>(index - 3) / static_cast<double>(intervals), 0.0, 1.0);
}

// Window [first, last] of fine rows holding Q^j's column i (m = 2^(j-1) wavelets): the
// minimal supports of Stollnitz et al.: boundary wavelets i = 0..3 start at row i, interior
// ones span the 11 rows [2i-3, 2i+7]; the right half mirrors the left.
std::pair<long, long> wavelet_window(long i, long m, long rows) {
    const bool mirrored = i >= m / 2;
    const long k = mirrored ? m - 1 - i : i;
    const long first = k <= 3 ? k : 2 * k - 3;
    const long last = 2 * k + 7;
    if (!mirrored) return {first, last};
    return {rows - 1 - last, rows - 1 - first};
}

}  // namespace

// <f, G f> for f = q on rows [first, first + q.size()) and zero elsewhere, in O(window) work
// instead of O(rows), with the same result to the last bit as full.dot(gram * full) over
// all rows: the products are the same and are summed in the same order.  G f accumulates
// per row in column order (Eigen's column-major sparse product), and zero entries add
// nothing.  Eigen's dot keeps two packet accumulators filled from the vector's start, so
// the slice starts at a multiple of two packets, and it runs to the end of the vector when
// the window reaches past the last whole pair of packets, where the tail is summed apart.
double window_energy(const Eigen::SparseMatrix<double>& gram, long rows, long first, const Eigen::VectorXd& q) {
    constexpr long lanes = 2 * Eigen::internal::packet_traits<double>::size;
    const long width = static_cast<long>(q.size());
    const long last = first + width - 1;
    const long start = first / lanes * lanes;
    const long whole_pairs_end = rows / lanes * lanes;
    const long end = last < whole_pairs_end ? (last + lanes) / lanes * lanes : rows;
    Eigen::VectorXd f = Eigen::VectorXd::Zero(end - start);
    Eigen::VectorXd gf = Eigen::VectorXd::Zero(end - start);
    f.segment(first - start, width) = q;
    for (long c = first; c <= last; ++c) {
        const double fc = q(c - first);
        for (Eigen::SparseMatrix<double>::InnerIterator e(gram, c); e; ++e)
            if (e.row() >= start && e.row() < end) gf(e.row() - start) += e.value() * fc;
    }
    return f.dot(gf);
}

std::pair<std::size_t, std::array<double, 4>> bspline_basis(int level, double x) {
    const long intervals = 1L << level;
    const long s = std::clamp(static_cast<long>(std::floor(x * static_cast<double>(intervals))), 0L, intervals - 1);
    const long span = s + 3;  // knot index with knot(span) <= x < knot(span + 1)
    // Cox-de Boor triangle (The NURBS Book, algorithm A2.2).
    std::array<double, 4> n{1.0, 0.0, 0.0, 0.0};
    std::array<double, 4> left{}, right{};
    for (int d = 1; d <= 3; ++d) {
        left[static_cast<std::size_t>(d)] = x - knot(level, span + 1 - d);
        right[static_cast<std::size_t>(d)] = knot(level, span + d) - x;
        double saved = 0.0;
        for (int r = 0; r < d; ++r) {
            const double denom = right[static_cast<std::size_t>(r + 1)] + left[static_cast<std::size_t>(d - r)];
            const double temp = denom == 0.0 ? 0.0 : n[static_cast<std::size_t>(r)] / denom;
            n[static_cast<std::size_t>(r)] = saved + right[static_cast<std::size_t>(r + 1)] * temp;
            saved = left[static_cast<std::size_t>(d - r)] * temp;
        }
        n[static_cast<std::size_t>(d)] = saved;
    }
    return {static_cast<std::size_t>(s), n};
}

Sparse gram_matrix(int level) {
    const long intervals = 1L << level;
    const std::size_t n = level_size(level);
    static const double kNodes[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
    static const double kWeights[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
    Eigen::MatrixXd band = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), 4);  // band(i, k) = <phi_i, phi_{i+k}>
    const double h = 1.0 / static_cast<double>(intervals);
    for (long s = 0; s < intervals; ++s)
        for (int q = 0; q < 4; ++q) {
            const double x = (static_cast<double>(s) + 0.5 + 0.5 * kNodes[q]) * h;
            const auto [first, values] = bspline_basis(level, x);
            for (int a = 0; a < 4; ++a)
                for (int b = a; b < 4; ++b)
                    band(static_cast<Eigen::Index>(first) + a, b - a) += 0.5 * h * kWeights[q] *
                                                                         values[static_cast<std::size_t>(a)] *
                                                                         values[static_cast<std::size_t>(b)];
        }
    Triplets t;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t k = 0; k < 4 && i + k < n; ++k) {
            const double v = band(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k));
            t.emplace_back(i, i + k, v);
            if (k > 0) t.emplace_back(i + k, i, v);
        }
    Sparse g(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    g.setFromTriplets(t.begin(), t.end());
    return g;
}

Sparse refinement_matrix(int level) {
    if (level < 3) throw std::logic_error("refinement_matrix: closed form needs level >= 3");
    const long rows = static_cast<long>(level_size(level));
    const long cols = static_cast<long>(level_size(level - 1));
    Triplets t;
    auto column = [&](long c, long first_row, std::initializer_list<double> values) {
        long r = first_row;
        for (double v : values) {
            t.emplace_back(r, c, v);
            t.emplace_back(rows - 1 - r, cols - 1 - c, v);  // mirror image at the right end
            ++r;
        }
    };
    column(0, 0, {1.0, 0.5});
    column(1, 1, {0.5, 0.75, 0.1875});
    column(2, 2, {0.25, 0.6875, 0.5, 0.125});
    for (long c = 3; c < cols / 2; ++c) column(c, 2 * c - 3, {0.125, 0.5, 0.75, 0.5, 0.125});
    if (cols % 2 == 1) {  // the middle column is its own mirror: add it once
        const long c = cols / 2;
        const double v[5] = {0.125, 0.5, 0.75, 0.5, 0.125};
        for (int k = 0; k < 5; ++k) t.emplace_back(2 * c - 3 + k, c, v[k]);
    }
    Sparse p(rows, cols);
    p.setFromTriplets(t.begin(), t.end(), [](double a, double) { return a; });  // mirror duplicates agree
    return p;
}

struct CubicBSplineWavelet::Level {
    Sparse P, Q;
    // [P | Q] with columns interleaved by the row where they are centred: banded.
    Sparse interleaved;
    std::vector<Eigen::Index> column_of;  // interleaved column -> index in [c | d]
    Eigen::SparseLU<Sparse, Eigen::COLAMDOrdering<int>> lu;
};

CubicBSplineWavelet::CubicBSplineWavelet(int finest_level) : finest_(finest_level) {
    if (finest_level < kCoarsestLevel || finest_level > 30)
        throw std::logic_error("CubicBSplineWavelet: level out of range");
    for (int j = kCoarsestLevel + 1; j <= finest_; ++j) {
        auto level = std::make_unique<Level>();
        level->P = refinement_matrix(j);
        const long rows = static_cast<long>(level_size(j));
        const long coarse = static_cast<long>(level_size(j - 1));
        const long m = 1L << (j - 1);
        const Sparse gram = gram_matrix(j);
        const Sparse constraint = Sparse(level->P.transpose()) * gram;  // coarse x rows, banded
        Triplets qt;
        for (long i = 0; i < m; ++i) {
            const auto [first, last] = wavelet_window(i, m, rows);
            const long width = last - first + 1;
            // The constraint rows that touch the window, as a small dense matrix.
            std::vector<std::pair<long, Eigen::VectorXd>> touching;
            for (long c = first; c <= last; ++c)
                for (Sparse::InnerIterator e(constraint, c); e; ++e) {
                    auto it =
                        std::find_if(touching.begin(), touching.end(), [&](auto& t) { return t.first == e.row(); });
                    if (it == touching.end()) {
                        touching.push_back({static_cast<long>(e.row()), Eigen::VectorXd::Zero(width)});
                        it = touching.end() - 1;
                    }
                    it->second(c - first) = e.value();
                }
            Eigen::MatrixXd a(static_cast<Eigen::Index>(touching.size()), width);
            for (std::size_t k = 0; k < touching.size(); ++k)
                a.row(static_cast<Eigen::Index>(k)) = touching[k].second.transpose();
            Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullV);
            const auto& sv = svd.singularValues();
            const Eigen::Index rank_needed = width - 1;
            const bool has_null = sv.size() < width || sv(width - 1) < 1e-9 * sv(0);
            if (!has_null || sv.size() < rank_needed || sv(rank_needed - 1) < 1e-9 * sv(0))
                throw std::logic_error("wavelet window " + std::to_string(i) + " at level " + std::to_string(j) +
                                       " does not have a one-dimensional null space");
            Eigen::VectorXd q = svd.matrixV().col(width - 1);
            // Unit L2 norm, and a fixed sign (largest entry positive) for determinism.
            const double norm2 = window_energy(gram, rows, first, q);
            Eigen::Index arg = 0;
            q.cwiseAbs().maxCoeff(&arg);
            q *= (q(arg) < 0 ? -1.0 : 1.0) / std::sqrt(norm2);
            for (long r = 0; r < width; ++r)
                if (q(r) != 0.0) qt.emplace_back(first + r, i, q(r));
        }
        level->Q = Sparse(rows, m);
        level->Q.setFromTriplets(qt.begin(), qt.end());

        // Interleave: P column k is centred near row 2k-1, Q column i near row 2i+2.
        std::vector<std::pair<double, Eigen::Index>> order;
        for (long k = 0; k < coarse; ++k) order.push_back({2.0 * double(k) - 1.0, k});
        for (long i = 0; i < m; ++i) order.push_back({2.0 * double(i) + 2.0 + 0.5, coarse + i});
        std::stable_sort(order.begin(), order.end(), [](auto& x, auto& y) { return x.first < y.first; });
        Triplets it;
        level->column_of.resize(order.size());
        for (std::size_t c = 0; c < order.size(); ++c) {
            const Eigen::Index src = order[c].second;
            level->column_of[c] = src;
            const Sparse& block = src < coarse ? level->P : level->Q;
            const Eigen::Index col = src < coarse ? src : src - coarse;
            for (Sparse::InnerIterator e(block, col); e; ++e)
                it.emplace_back(e.row(), static_cast<Eigen::Index>(c), e.value());
        }
        level->interleaved = Sparse(rows, rows);
        level->interleaved.setFromTriplets(it.begin(), it.end());
        level->interleaved.makeCompressed();
        level->lu.compute(level->interleaved);
        if (level->lu.info() != Eigen::Success)
            throw std::logic_error("[P|Q] is singular at level " + std::to_string(j));
        levels_.push_back(std::move(level));
    }

    // Weights: scaling functions of the coarsest level get sqrt(2^J <phi,phi>), unit-norm
    // wavelets sqrt(2^J), since |samples|^2 ~ 2^J ||f||^2 for B-spline coefficients.
    const double scale = std::ldexp(1.0, finest_);
    const Sparse g0 = gram_matrix(kCoarsestLevel);
    weights_.resize(length());
    for (std::size_t k = 0; k < level_size(kCoarsestLevel); ++k)
        weights_[k] = std::sqrt(scale * g0.coeff(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k)));
    for (std::size_t k = level_size(kCoarsestLevel); k < length(); ++k) weights_[k] = std::sqrt(scale);

    // Supports: a range of level-j coefficients reaches fine rows [2lo-3, 2hi+1] at j+1.
    supports_.resize(length());
    auto lift = [&](long lo, long hi, int from_level) {
        for (int j = from_level + 1; j <= finest_; ++j) {
            lo = std::max(0L, 2 * lo - 3);
            hi = std::min(static_cast<long>(level_size(j)) - 1, 2 * hi + 1);
        }
        return std::pair<std::size_t, std::size_t>(static_cast<std::size_t>(lo), static_cast<std::size_t>(hi));
    };
    for (std::size_t k = 0; k < level_size(kCoarsestLevel); ++k)
        supports_[k] = lift(static_cast<long>(k), static_cast<long>(k), kCoarsestLevel);
    for (int j = kCoarsestLevel + 1; j <= finest_; ++j) {
        const long m = 1L << (j - 1);
        for (long i = 0; i < m; ++i) {
            const auto [first, last] = wavelet_window(i, m, static_cast<long>(level_size(j)));
            supports_[static_cast<std::size_t>(m + 3 + i)] = lift(first, last, j);
        }
    }
}

CubicBSplineWavelet::~CubicBSplineWavelet() = default;

const Eigen::SparseMatrix<double>& CubicBSplineWavelet::P(int level) const {
    return levels_.at(static_cast<std::size_t>(level - kCoarsestLevel - 1))->P;
}
const Eigen::SparseMatrix<double>& CubicBSplineWavelet::Q(int level) const {
    return levels_.at(static_cast<std::size_t>(level - kCoarsestLevel - 1))->Q;
}

std::pair<std::size_t, std::size_t> CubicBSplineWavelet::support(std::size_t index) const {
    return supports_.at(index);
}

void CubicBSplineWavelet::analyse(Eigen::MatrixXd& x) const {
    if (static_cast<std::size_t>(x.rows()) != length()) throw std::logic_error("analyse: wrong signal length");
    for (int j = finest_; j > kCoarsestLevel; --j) {
        const Level& level = *levels_[static_cast<std::size_t>(j - kCoarsestLevel - 1)];
        const Eigen::Index n = static_cast<Eigen::Index>(level_size(j));
        const Eigen::MatrixXd solved = level.lu.solve(x.topRows(n));
        for (Eigen::Index c = 0; c < n; ++c) x.row(level.column_of[static_cast<std::size_t>(c)]) = solved.row(c);
    }
    for (std::size_t k = 0; k < length(); ++k) x.row(static_cast<Eigen::Index>(k)) *= weights_[k];
}

void CubicBSplineWavelet::synthesise(Eigen::MatrixXd& x) const {
    if (static_cast<std::size_t>(x.rows()) != length()) throw std::logic_error("synthesise: wrong length");
    for (std::size_t k = 0; k < length(); ++k) x.row(static_cast<Eigen::Index>(k)) /= weights_[k];
    for (int j = kCoarsestLevel + 1; j <= finest_; ++j) {
        const Level& level = *levels_[static_cast<std::size_t>(j - kCoarsestLevel - 1)];
        const Eigen::Index coarse = static_cast<Eigen::Index>(level_size(j - 1));
        const Eigen::Index m = Eigen::Index(1) << (j - 1);
        const Eigen::MatrixXd fine = level.P * x.topRows(coarse) + level.Q * x.middleRows(coarse, m);
        x.topRows(coarse + m) = fine;
    }
}

}  // namespace foldcast::codec
