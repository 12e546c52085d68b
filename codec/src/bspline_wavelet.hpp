#pragma once
// Cubic endpoint-interpolating B-spline wavelets on [0, 1] (Stollnitz, DeRose & Salesin,
// "Wavelets for Computer Graphics", ch. 7 and appendix): level j has 2^j + 3 scaling
// functions (clamped cubic B-splines on 2^j uniform intervals) and 2^(j-1) semi-orthogonal
// wavelets.  P^j is the B-spline refinement matrix (closed form); Q^j spans the L2
// complement of the coarse space with minimal supports (each column is the null vector of
// (P^j)^T I^j restricted to its support window, I^j the Gram matrix), normalised to unit
// L2 norm.  Analysis solves the banded interleaved [P^j | Q^j] system with a sparse LU
// factored once per level and reused for every trajectory; the dense inverse is never formed.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <memory>
#include <utility>
#include <vector>

namespace foldcast::codec {

constexpr int kCoarsestLevel = 3;  // 11 scaling functions: the smallest level where the
                                   // minimal-support wavelet windows do not overlap
inline std::size_t level_size(int j) { return (std::size_t(1) << j) + 3; }

// The 4 non-zero clamped cubic B-splines of level j at x in [0, 1]: first index and values.
std::pair<std::size_t, std::array<double, 4>> bspline_basis(int level, double x);
// Gram matrix <phi_i, phi_k> of level j (exact, 4-point Gauss-Legendre per interval).
Eigen::SparseMatrix<double> gram_matrix(int level);
// P^j: (2^j+3) x (2^(j-1)+3), j >= kCoarsestLevel + 1 (closed form valid for j >= 3).
Eigen::SparseMatrix<double> refinement_matrix(int level);

// <f, G f> where f is q on rows [first, first + q.size()) of a vector of `rows` and zero
// elsewhere: bit-identical to f.dot(gram * f) over the whole vector, in O(q.size()) work.
double window_energy(const Eigen::SparseMatrix<double>& gram, long rows, long first, const Eigen::VectorXd& q);

class CubicBSplineWavelet {
public:
    explicit CubicBSplineWavelet(int finest_level);  // finest_level >= kCoarsestLevel
    ~CubicBSplineWavelet();
    CubicBSplineWavelet(const CubicBSplineWavelet&) = delete;
    CubicBSplineWavelet& operator=(const CubicBSplineWavelet&) = delete;

    int finest_level() const { return finest_; }
    std::size_t length() const { return level_size(finest_); }

    // Columns are signals of length(): in place, finest B-spline coefficients <->
    // [c^(j0) | d^(j0+1) | ... | d^J] (level j's wavelets at [2^(j-1)+3, 2^j+3)).  The
    // coefficients are scaled by weight() so that every basis function has the same
    // energy in the sample domain: dropping a coefficient c costs about c^2 of squared
    // sample error, which is what makes thresholding |c| < eps meaningful.
    void analyse(Eigen::MatrixXd& signals) const;
    void synthesise(Eigen::MatrixXd& coefficients) const;
    double weight(std::size_t index) const { return weights_[index]; }

    // Unnormalised P^j, Q^j (for tests of their defining identities).
    const Eigen::SparseMatrix<double>& P(int level) const;
    const Eigen::SparseMatrix<double>& Q(int level) const;

    // Conservative range of finest-level samples [first, last] that coefficient `index`
    // influences.
    std::pair<std::size_t, std::size_t> support(std::size_t index) const;

private:
    struct Level;
    int finest_;
    std::vector<std::unique_ptr<Level>> levels_;  // levels_[j - kCoarsestLevel - 1] for j > j0
    std::vector<double> weights_;
    std::vector<std::pair<std::size_t, std::size_t>> supports_;
};

}  // namespace foldcast::codec
