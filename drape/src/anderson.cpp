// Anderson acceleration (anderson.hpp).
#include "anderson.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <type_traits>

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

// One chunk of the step's first pass in one sweep over memory: the residual, the new
// differences, and the 2h dot products (the new difference with each of the h history slots,
// each slot with the residual), each summed exactly as Eigen's dot() sums a vector of this
// length (two packet accumulators over alternate packets, added, then the packet's lanes), so
// the values are the bits the separate pass and dot() calls gave.  Only for chunks whose
// length is a multiple of two packets (every chunk but perhaps the last); H: the history
// length.  Reads each array once instead of once per dot product.
template <int H>
void fused_chunk(Eigen::Index begin, Eigen::Index end, const double* g, const double* current, const double* g_prev,
                 const double* f_prev, double* f, double* new_dg, double* new_df,
                 const std::array<const double*, Anderson::kHistory>& history, double* with_new, double* right) {
    using namespace Eigen::internal;
    using Packet = packet_traits<double>::type;
    constexpr Eigen::Index P = packet_traits<double>::size;
    Packet new0[H], new1[H], right0[H], right1[H];  // the two accumulators of each dot product
    const auto packet = [&](Eigen::Index e, Packet* sum_new, Packet* sum_right, auto first) {
        const Packet ge = ploadu<Packet>(g + e);
        const Packet fe = psub(ge, ploadu<Packet>(current + e));
        const Packet dg = psub(ge, ploadu<Packet>(g_prev + e));
        const Packet df = psub(fe, ploadu<Packet>(f_prev + e));
        pstoreu(f + e, fe), pstoreu(new_dg + e, dg), pstoreu(new_df + e, df);
        for (int a = 0; a < H; ++a) {
            const Packet d = ploadu<Packet>(history[std::size_t(a)] + e);  // new_df's own slot among them
            const Packet n = pmul(df, d), r = pmul(d, fe);
            if constexpr (decltype(first)::value)
                sum_new[a] = n, sum_right[a] = r;
            else
                sum_new[a] = padd(sum_new[a], n), sum_right[a] = padd(sum_right[a], r);
        }
    };
    packet(begin, new0, right0, std::true_type{});
    packet(begin + P, new1, right1, std::true_type{});
    for (Eigen::Index e = begin + 2 * P; e < end; e += 2 * P) {
        packet(e, new0, right0, std::false_type{});
        packet(e + P, new1, right1, std::false_type{});
    }
    for (int a = 0; a < H; ++a) {
        with_new[a] = predux(padd(new0[a], new1[a]));
        right[a] = predux(padd(right0[a], right1[a]));
    }
}

// next = g - sum_a theta_a dg_a over [begin, end), the terms subtracted in slot order, a
// packet at a time (the same operations on each value as one at a time).
template <int H>
void combine_chunk(Eigen::Index begin, Eigen::Index end, const double* g,
                   const std::array<const double*, Anderson::kHistory>& dg, const double* theta, double* next) {
    using namespace Eigen::internal;
    using Packet = packet_traits<double>::type;
    constexpr Eigen::Index P = packet_traits<double>::size;
    Packet t[H];
    for (int a = 0; a < H; ++a) t[a] = pset1<Packet>(theta[a]);
    Eigen::Index e = begin;
    for (; e + P <= end; e += P) {
        Packet v = ploadu<Packet>(g + e);
        for (int a = 0; a < H; ++a) v = psub(v, pmul(t[a], ploadu<Packet>(dg[std::size_t(a)] + e)));
        pstoreu(next + e, v);
    }
    for (; e < end; ++e) {
        double v = g[e];
        for (int a = 0; a < H; ++a) v -= theta[a] * dg[std::size_t(a)][e];
        next[e] = v;
    }
}

// Calls body(std::integral_constant<int, h>{}) for a history length h in 1..kHistory, so that
// the chunk loops are compiled for each length (their per-slot loops unrolled).
template <typename Body>
void with_history_length(int h, Body&& body) {
    static_assert(Anderson::kHistory == 5, "one case per history length");
    switch (h) {
        case 1: return body(std::integral_constant<int, 1>{});
        case 2: return body(std::integral_constant<int, 2>{});
        case 3: return body(std::integral_constant<int, 3>{});
        case 4: return body(std::integral_constant<int, 4>{});
        default: return body(std::integral_constant<int, 5>{});
    }
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
        constexpr Eigen::Index kTwoPackets =
            2 * Eigen::Index(Eigen::internal::packet_traits<double>::size);
        for_chunks(size_, [&](Eigen::Index c, Eigen::Index begin, Eigen::Index end) {
            double* const sums = partial + c * 2 * kHistory;
            if ((end - begin) % kTwoPackets == 0 && h >= 1) {
                with_history_length(h, [&](auto history_length) {
                    fused_chunk<decltype(history_length)::value>(begin, end, g, current, g_prev, f_prev, f, new_dg,
                                                                 new_df, history, sums, sums + kHistory);
                });
                return;
            }
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
            with_history_length(h, [&](auto history_length) {
                combine_chunk<decltype(history_length)::value>(begin, end, g, dg, theta.data(), next);
            });
        });
        return true;
    }
    std::swap(g_prev_, g_), std::swap(f_prev_, f_);
    ++steps_;
    return false;
}

}  // namespace foldcast::drape::detail
