// The relaxation's Anderson step (drape/relax/anderson.hpp) against a plain implementation of the
// same arithmetic: the residual and differences in separate passes, each dot product over each
// chunk of 8192 entries, the chunks summed in order: in double by Eigen's dot(), in float a
// value at a time in the step's order (four lanes, float sums over blocks of 16 entries added
// to double ones).  The step fuses those
// passes and sums the dot products itself, in dot()'s order: the bits must be the same, every
// step, with the history filling, wrapping round the ring and forgotten.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstring>
#include <deque>
#include <type_traits>
#include <vector>

#include "anderson.hpp"

namespace foldcast::drape::detail {
namespace {

template <typename T>
class PlainAnderson {
public:
    using Vector = Eigen::Matrix<T, Eigen::Dynamic, 1>;
    explicit PlainAnderson(Eigen::Index size) : size_(size) {}
    void forget() { dg_.clear(), df_.clear(); }

    // Returns false (next untouched) where Anderson::step does.
    bool step(const Vector& current, const Vector& g, Vector& next) {
        const Vector f = g - current;
        if (!started_) {
            started_ = true;
            g_prev_ = g, f_prev_ = f;
            return false;
        }
        if (int(df_.size()) == Anderson<T>::kHistory) dg_.pop_front(), df_.pop_front();
        dg_.push_back(g - g_prev_), df_.push_back(f - f_prev_);
        g_prev_ = g, f_prev_ = f;
        const int h = int(df_.size());
        const auto dot = [&](const Vector& a, const Vector& b) {
            double sum = 0.0;
            for (Eigen::Index begin = 0; begin < size_; begin += kChunk) {
                const Eigen::Index end = std::min(size_, begin + kChunk);
                if constexpr (std::is_same_v<T, double>) {
                    sum += a.segment(begin, end - begin).dot(b.segment(begin, end - begin));
                    continue;
                }
                double lane[4] = {};
                for (Eigen::Index block = begin; block < end; block += 16) {
                    float block_sum[4] = {};
                    for (Eigen::Index e = block; e < std::min(end, block + 16); ++e)
                        block_sum[(e - begin) % 4] += a[e] * b[e];
                    for (int l = 0; l < 4; ++l) lane[l] += double(block_sum[l]);
                }
                sum += (lane[0] + lane[2]) + (lane[1] + lane[3]);
            }
            return sum;
        };
        // The normal matrix's entries are computed once, when the newer of the two arrives
        // (new . older, as the step does), and kept.
        std::vector<double> row(static_cast<std::size_t>(h));
        for (int a = 0; a < h; ++a) row[std::size_t(a)] = dot(df_.back(), df_[std::size_t(a)]);
        dots_.push_back(row);
        if (int(dots_.size()) > Anderson<T>::kHistory) dots_.pop_front();
        Eigen::MatrixXd normal(h, h);
        Eigen::VectorXd right(h);
        for (int a = 0; a < h; ++a) {
            right(a) = dot(df_[std::size_t(a)], f);
            for (int b = 0; b <= a; ++b) {
                // dots_[a] holds slot a's dot products with the slots before it, oldest first.
                const std::vector<double>& newer = dots_[std::size_t(a)];
                normal(a, b) = normal(b, a) = newer[newer.size() - std::size_t(a - b) - 1];
            }
        }
        normal.diagonal() *= 1.0 + 1e-10;
        const Eigen::VectorXd theta = normal.ldlt().solve(right);
        if (!theta.allFinite()) return false;
        next = g;
        for (Eigen::Index e = 0; e < size_; ++e) {
            T v = g[e];
            for (int a = 0; a < h; ++a) v -= T(theta(a)) * dg_[std::size_t(a)][e];
            next[e] = v;
        }
        return true;
    }

    void reset_dots() { dots_.clear(); }

private:
    static constexpr Eigen::Index kChunk = 8192;
    Eigen::Index size_;
    bool started_ = false;
    Vector g_prev_, f_prev_;
    std::deque<Vector> dg_, df_;
    std::deque<std::vector<double>> dots_;
};

// A smooth nonlinear contraction, so that the history is neither degenerate nor trivial.
template <typename Vector>
Vector map(const Vector& x) {
    using T = typename Vector::Scalar;
    Vector g(x.size());
    for (Eigen::Index e = 0; e < x.size(); ++e)
        g[e] = T(0.8 * x[e] + 0.1 * std::sin(3.0 * x[(e + 7) % x.size()]) + 0.01 * std::cos(0.001 * double(e)));
    return g;
}

template <typename T>
void same_bits_as_plain(Eigen::Index size) {
    using Vector = typename PlainAnderson<T>::Vector;
    Anderson<T> fused(size);
    PlainAnderson<T> plain(size);
    fused.restart();
    Vector x = Vector::LinSpaced(size, T(-1), T(1)), next_fused(size), next_plain(size);
    for (int step = 0; step < 14; ++step) {
        if (step == 9) fused.forget(), plain.forget(), plain.reset_dots();  // as after a rejected step
        const Vector g = map(x);
        std::copy(g.data(), g.data() + size, fused.g());
        const bool accelerated = fused.step(x.data(), next_fused.data());
        ASSERT_EQ(accelerated, plain.step(x, g, next_plain)) << "step " << step;
        if (!accelerated) {
            x = g;
            continue;
        }
        ASSERT_EQ(std::memcmp(next_fused.data(), next_plain.data(), sizeof(T) * std::size_t(size)), 0)
            << "step " << step << ", size " << size;
        x = next_fused;
    }
}

TEST(Anderson, SameBitsAsThePlainPassesWhereEveryChunkIsFused) {
    same_bits_as_plain<double>(3 * 8192);
    same_bits_as_plain<float>(3 * 8192);
}
TEST(Anderson, SameBitsAsThePlainPassesWithARaggedLastChunk) {
    same_bits_as_plain<double>(2 * 8192 + 4103);
    same_bits_as_plain<float>(2 * 8192 + 4103);
}

}  // namespace
}  // namespace foldcast::drape::detail
