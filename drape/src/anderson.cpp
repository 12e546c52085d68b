// Anderson acceleration (anderson.hpp).
#include "anderson.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>

namespace foldcast::drape::detail {
namespace {

// Entries per chunk: fixed, so the dot products' summation order is too.
constexpr Eigen::Index kChunk = 8192;

template <typename Body>
void for_chunks(Eigen::Index size, Body&& body) {
    const Eigen::Index chunks = (size + kChunk - 1) / kChunk;
    tbb::parallel_for(Eigen::Index(0), chunks,
                      [&](Eigen::Index c) { body(c, c * kChunk, std::min(size, (c + 1) * kChunk)); });
}

}  // namespace

Anderson::Anderson(Eigen::Index size)
    : size_(size),
      f_(std::size_t(size)),
      g_prev_(std::size_t(size)),
      f_prev_(std::size_t(size)),
      g_(std::size_t(size)),
      partial_(std::size_t((size + kChunk - 1) / kChunk) * 2 * kHistory) {
    for (std::vector<double>& d : dg_) d.resize(std::size_t(size));
    for (std::vector<double>& d : df_) d.resize(std::size_t(size));
    slot_dots_.setZero();
}

bool Anderson::step(const double* current, double* next) {
    const double* const g = g_.data();
    double* const f = f_.data();
    if (steps_ == 0) {
        for_chunks(size_, [&](Eigen::Index, Eigen::Index begin, Eigen::Index end) {
            for (Eigen::Index e = begin; e < end; ++e) f[e] = g[e] - current[e];
        });
    } else {
        // The newest differences into a slot (the oldest once the ring is full), and in the
        // same pass their dot products with every slot and each slot's with the residual.
        std::size_t slot;
        if (stored_ == kHistory) {
            slot = std::size_t(oldest_);
            oldest_ = (oldest_ + 1) % kHistory;
        } else {
            if (stored_ == 0) oldest_ = 0;
            slot = slot_of(stored_++);
        }
        const int h = stored_;
        std::array<const double*, kHistory> history{};
        for (int a = 0; a < h; ++a) history[std::size_t(a)] = df_[slot_of(a)].data();
        double* const new_dg = dg_[slot].data();
        double* const new_df = df_[slot].data();
        const double* const g_prev = g_prev_.data();
        const double* const f_prev = f_prev_.data();
        const Eigen::Index chunks = (size_ + kChunk - 1) / kChunk;
        double* const partial = partial_.data();
        for_chunks(size_, [&](Eigen::Index c, Eigen::Index begin, Eigen::Index end) {
            for (Eigen::Index e = begin; e < end; ++e) {
                const double fe = g[e] - current[e];
                f[e] = fe;
                new_dg[e] = g[e] - g_prev[e];
                new_df[e] = fe - f_prev[e];
            }
            // Eigen's dot products: vectorised, and in a fixed order for a given length.
            using Segment = Eigen::Map<const Eigen::VectorXd>;
            const Eigen::Index length = end - begin;
            const Segment df_new(new_df + begin, length), residual(f + begin, length);
            double* const sums = partial + c * 2 * kHistory;
            for (int a = 0; a < h; ++a) {
                const Segment d(history[std::size_t(a)] + begin, length);
                sums[a] = df_new.dot(d), sums[kHistory + a] = d.dot(residual);
            }
        });
        Eigen::Matrix<double, kHistory, 1> with_new = Eigen::Matrix<double, kHistory, 1>::Zero(), right = with_new;
        for (Eigen::Index c = 0; c < chunks; ++c)
            for (int a = 0; a < h; ++a)
                with_new(a) += partial[std::size_t(c * 2 * kHistory + a)],
                    right(a) += partial[std::size_t(c * 2 * kHistory + kHistory + a)];
        for (int a = 0; a < h; ++a)
            slot_dots_(Eigen::Index(slot), Eigen::Index(slot_of(a))) =
                slot_dots_(Eigen::Index(slot_of(a)), Eigen::Index(slot)) = with_new(a);

        // theta minimises |f - sum_a theta_a df_a|; next = g - sum_a theta_a dg_a.
        Eigen::MatrixXd normal(h, h);
        for (int a = 0; a < h; ++a)
            for (int b = 0; b <= a; ++b)
                normal(a, b) = normal(b, a) = slot_dots_(Eigen::Index(slot_of(a)), Eigen::Index(slot_of(b)));
        normal.diagonal() *= 1.0 + 1e-10;
        const Eigen::VectorXd theta = normal.ldlt().solve(right.head(h));
        std::swap(g_prev_, g_), std::swap(f_prev_, f_);  // g and f are overwritten next step
        ++steps_;
        if (!theta.allFinite()) return false;
        std::array<const double*, kHistory> dg{};
        for (int a = 0; a < h; ++a) dg[std::size_t(a)] = dg_[slot_of(a)].data();
        for_chunks(size_, [&](Eigen::Index, Eigen::Index begin, Eigen::Index end) {
            for (Eigen::Index e = begin; e < end; ++e) {
                double v = g[e];
                for (int a = 0; a < h; ++a) v -= theta(a) * dg[std::size_t(a)][e];
                next[e] = v;
            }
        });
        return true;
    }
    std::swap(g_prev_, g_), std::swap(f_prev_, f_);
    ++steps_;
    return false;
}

}  // namespace foldcast::drape::detail
