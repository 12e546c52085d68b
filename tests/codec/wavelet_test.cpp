#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cstring>
#include <random>

#include "bspline_wavelet.hpp"

namespace foldcast::codec {
namespace {

Eigen::MatrixXd random_signals(std::size_t rows, int cols, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> d(0.0, 1.0);
    Eigen::MatrixXd x(static_cast<Eigen::Index>(rows), cols);
    for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = d(rng);
    return x;
}

TEST(BSplineBasis, PartitionOfUnityAndEndpointInterpolation) {
    for (double x : {0.0, 0.1, 0.37, 0.5, 0.99, 1.0}) {
        const auto [first, values] = bspline_basis(4, x);
        EXPECT_NEAR(values[0] + values[1] + values[2] + values[3], 1.0, 1e-12);
        (void)first;
    }
    EXPECT_NEAR(bspline_basis(4, 0.0).second[0], 1.0, 1e-12);
    EXPECT_NEAR(bspline_basis(4, 1.0).second[3], 1.0, 1e-12);
}

// Refinement relation: phi^(j-1)_k(x) = sum_i P^j(i, k) phi^j_i(x) everywhere.
TEST(BSplineWavelet, RefinementMatrixReproducesCoarseBasis) {
    for (int j = 4; j <= 6; ++j) {
        const Eigen::MatrixXd P(refinement_matrix(j));
        for (int s = 0; s <= 200; ++s) {
            const double x = s / 200.0;
            Eigen::VectorXd coarse = Eigen::VectorXd::Zero(P.cols()), fine = Eigen::VectorXd::Zero(P.rows());
            const auto [cf, cv] = bspline_basis(j - 1, x);
            const auto [ff, fv] = bspline_basis(j, x);
            for (int k = 0; k < 4; ++k) {
                coarse(static_cast<Eigen::Index>(cf) + k) = cv[static_cast<std::size_t>(k)];
                fine(static_cast<Eigen::Index>(ff) + k) = fv[static_cast<std::size_t>(k)];
            }
            EXPECT_LT((P.transpose() * fine - coarse).cwiseAbs().maxCoeff(), 1e-12) << "level " << j << " x " << x;
        }
    }
}

// Q spans wavelets orthogonal to the coarse space: (P^j)^T I^j Q^j = 0, unit L2 norm,
// and [P | Q] is square and invertible.
TEST(BSplineWavelet, WaveletsAreOrthogonalToCoarseSpaceAndNormalised) {
    const CubicBSplineWavelet w(7);
    for (int j = 4; j <= 7; ++j) {
        const Eigen::MatrixXd P(w.P(j)), Q(w.Q(j)), I(gram_matrix(j));
        EXPECT_EQ(P.cols() + Q.cols(), P.rows());
        EXPECT_LT((P.transpose() * I * Q).cwiseAbs().maxCoeff(), 1e-10) << "level " << j;
        EXPECT_LT(((Q.transpose() * I * Q).diagonal().array() - 1.0).abs().maxCoeff(), 1e-10);
        Eigen::MatrixXd PQ(P.rows(), P.rows());
        PQ << P, Q;
        EXPECT_GT(Eigen::FullPivLU<Eigen::MatrixXd>(PQ).rank(), P.rows() - 1);
        // Interior wavelets have the 11-coefficient minimal support.
        const Eigen::Index mid = Q.cols() / 2 - 1;
        EXPECT_EQ((Q.col(mid).array() != 0.0).count(), 11) << "level " << j;
    }
}

TEST(BSplineWavelet, ExactRoundTripWithoutThresholding) {
    for (int level : {3, 4, 5, 8, 10}) {
        const CubicBSplineWavelet w(level);
        const Eigen::MatrixXd x = random_signals(w.length(), 7, static_cast<unsigned>(level));
        Eigen::MatrixXd y = x;
        w.analyse(y);
        EXPECT_GT((y - x).cwiseAbs().maxCoeff(), 1e-3);  // it did transform
        w.synthesise(y);
        EXPECT_LT((y - x).cwiseAbs().maxCoeff(), 1e-10) << "level " << level;
        // And the other way: analysis(synthesis(c)) = c.
        Eigen::MatrixXd c = x;
        w.synthesise(c);
        w.analyse(c);
        EXPECT_LT((c - x).cwiseAbs().maxCoeff(), 1e-9) << "level " << level;
    }
}

TEST(BSplineWavelet, SmoothSignalsConcentrateInCoarseCoefficients) {
    const CubicBSplineWavelet w(8);
    Eigen::MatrixXd x(static_cast<Eigen::Index>(w.length()), 1);
    for (Eigen::Index i = 0; i < x.rows(); ++i) x(i, 0) = std::sin(3.0 * double(i) / double(x.rows()));
    w.analyse(x);
    const double coarse = x.topRows(11).norm(), detail = x.bottomRows(x.rows() - 11).norm();
    EXPECT_LT(detail, 1e-3 * coarse);
}

TEST(BSplineWavelet, SupportsCoverTheSignalAndNest) {
    const CubicBSplineWavelet w(6);
    EXPECT_EQ(w.support(0).first, 0u);
    EXPECT_EQ(w.support(10).second, w.length() - 1);
    // A finest-level wavelet's support is narrower than a coarse one's.
    const auto fine = w.support(w.length() - 40), coarse = w.support(12);
    EXPECT_LT(fine.second - fine.first, coarse.second - coarse.first);
}

}  // namespace
}  // namespace foldcast::codec

namespace foldcast::codec {
namespace {

// The windowed energy replaces f.dot(gram * f) over the whole vector (O(rows) per wavelet,
// O(T^2) per animation); the wavelets, and so the codec's bytes, depend on it being the
// same double to the last bit, for windows at the start, the middle and every end phase.
TEST(BSplineWavelet, WindowEnergyIsBitIdenticalToTheWholeVectorProduct) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> d(-1.0, 1.0);
    for (int level = 4; level <= 9; ++level) {
        const Eigen::SparseMatrix<double> gram = gram_matrix(level);
        const long rows = static_cast<long>(level_size(level));
        for (long width : {4L, 5L, 11L})
            for (long first = 0; first + width <= rows; ++first) {
                Eigen::VectorXd q(width);
                for (Eigen::Index k = 0; k < q.size(); ++k) q(k) = d(rng);
                Eigen::VectorXd full = Eigen::VectorXd::Zero(rows);
                full.segment(first, width) = q;
                const double whole = full.dot(gram * full);
                const double windowed = window_energy(gram, rows, first, q);
                ASSERT_EQ(std::memcmp(&whole, &windowed, sizeof whole), 0)
                    << "level " << level << " first " << first << " width " << width << ": " << whole << " vs "
                    << windowed;
            }
    }
}

}  // namespace
}  // namespace foldcast::codec
