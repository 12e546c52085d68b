// Anderson acceleration (anderson.hpp).
#include "anderson.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <type_traits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace foldcast::drape::detail {
namespace {

// Entries per chunk: fixed, so the dot products' summation order is too.
constexpr Eigen::Index kChunk = 8192;
constexpr int kHistory = Anderson<double>::kHistory;  // the same for every T

template <typename Body>
void for_chunks(Eigen::Index size, Body&& body) {
    const Eigen::Index chunks = (size + kChunk - 1) / kChunk;
    tbb::parallel_for(Eigen::Index(0), chunks,
                      [&](Eigen::Index c) { body(c, c * kChunk, std::min(size, (c + 1) * kChunk)); });
}

// In double (Anderson<double>):
//
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
                 const std::array<const double*, kHistory>& history, double* with_new, double* right) {
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
void combine_chunk(Eigen::Index begin, Eigen::Index end, const double* g, const std::array<const double*, kHistory>& dg,
                   const double* theta, double* next) {
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

// In float (Anderson<float>):
//
// A dot product's summation order, fixed so that the bits do not depend on the threads: entry
// e of a chunk goes to lane e % 4; each lane sums its products in float over a block of 16
// entries, then adds that to its double total; the lanes are added as (0 + 2) + (1 + 3).  The
// products and the short sums in float keep the pass as cheap as the floats' memory (the
// conversions to double for every product made it compute-bound); the double totals keep the
// long sums' rounding from growing with the length.
constexpr Eigen::Index kDotBlock = 16;

// The order above one entry at a time: a short last chunk's dot products.
double block_dot(const float* a, const float* b, Eigen::Index length) {
    double lane[4] = {};
    for (Eigen::Index start = 0; start < length; start += kDotBlock) {
        float sum[4] = {};
        for (Eigen::Index e = start; e < std::min(length, start + kDotBlock); ++e) sum[e % 4] += a[e] * b[e];
        for (int l = 0; l < 4; ++l) lane[l] += double(sum[l]);
    }
    return (lane[0] + lane[2]) + (lane[1] + lane[3]);
}

// Four floats at a time (SSE2, or the same operations a lane at a time).
#if defined(__SSE2__)
using Float4 = __m128;
Float4 zero4() { return _mm_setzero_ps(); }
Float4 load4(const float* p) { return _mm_loadu_ps(p); }
void store4(float* p, Float4 v) { _mm_storeu_ps(p, v); }
Float4 sub4(Float4 a, Float4 b) { return _mm_sub_ps(a, b); }
Float4 mul4(Float4 a, Float4 b) { return _mm_mul_ps(a, b); }
Float4 add4(Float4 a, Float4 b) { return _mm_add_ps(a, b); }
// Four double lanes, added to as float lanes.
struct Lanes {
    __m128d low = _mm_setzero_pd(), high = _mm_setzero_pd();
    void add(Float4 v) {
        low = _mm_add_pd(low, _mm_cvtps_pd(v)), high = _mm_add_pd(high, _mm_cvtps_pd(_mm_movehl_ps(v, v)));
    }
    double total() const {
        const __m128d pair = _mm_add_pd(low, high);
        return _mm_cvtsd_f64(_mm_add_sd(pair, _mm_unpackhi_pd(pair, pair)));
    }
};
#else
struct Float4 {
    float v[4];
};
Float4 zero4() { return {{0.0f, 0.0f, 0.0f, 0.0f}}; }
Float4 load4(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
void store4(float* p, Float4 a) { std::copy(a.v, a.v + 4, p); }
Float4 sub4(Float4 a, Float4 b) { return {{a.v[0] - b.v[0], a.v[1] - b.v[1], a.v[2] - b.v[2], a.v[3] - b.v[3]}}; }
Float4 mul4(Float4 a, Float4 b) { return {{a.v[0] * b.v[0], a.v[1] * b.v[1], a.v[2] * b.v[2], a.v[3] * b.v[3]}}; }
Float4 add4(Float4 a, Float4 b) { return {{a.v[0] + b.v[0], a.v[1] + b.v[1], a.v[2] + b.v[2], a.v[3] + b.v[3]}}; }
struct Lanes {
    double v[4] = {};
    void add(Float4 a) {
        for (int l = 0; l < 4; ++l) v[l] += double(a.v[l]);
    }
    double total() const { return (v[0] + v[2]) + (v[1] + v[3]); }
};
#endif

// One chunk of the step's first pass in one sweep over memory: the residual, the new
// differences, and the 2h dot products (the new difference with each of the h history slots,
// each slot with the residual) in block_dot's order.  Only for chunks whose length is a
// multiple of kDotBlock (every chunk but perhaps the last); H: the history length.  Reads each
// array once instead of once per dot product.
template <int H>
void fused_chunk(Eigen::Index begin, Eigen::Index end, const float* g, const float* current, const float* g_prev,
                 const float* f_prev, float* f, float* new_dg, float* new_df,
                 const std::array<const float*, kHistory>& history, double* with_new, double* right) {
    std::array<Lanes, H> total_new{}, total_right{};
    for (Eigen::Index start = begin; start < end; start += kDotBlock) {
        Float4 sum_new[H], sum_right[H];
        for (std::size_t a = 0; a < std::size_t(H); ++a) sum_new[a] = sum_right[a] = zero4();
        for (Eigen::Index e = start; e < start + kDotBlock; e += 4) {
            const Float4 ge = load4(g + e);
            const Float4 residual = sub4(ge, load4(current + e));
            const Float4 difference = sub4(residual, load4(f_prev + e));
            store4(f + e, residual), store4(new_dg + e, sub4(ge, load4(g_prev + e))), store4(new_df + e, difference);
            for (std::size_t a = 0; a < std::size_t(H); ++a) {
                const Float4 d = load4(history[a] + e);  // new_df's own slot among them
                sum_new[a] = add4(sum_new[a], mul4(difference, d));
                sum_right[a] = add4(sum_right[a], mul4(d, residual));
            }
        }
        for (std::size_t a = 0; a < std::size_t(H); ++a) total_new[a].add(sum_new[a]), total_right[a].add(sum_right[a]);
    }
    for (std::size_t a = 0; a < std::size_t(H); ++a)
        with_new[a] = total_new[a].total(), right[a] = total_right[a].total();
}

// next = g - sum_a theta_a dg_a over [begin, end), the terms subtracted in slot order, in
// float (next is stored in float: double arithmetic would only round later), a packet at a
// time (the same operations on each value as one at a time).
template <int H>
void combine_chunk(Eigen::Index begin, Eigen::Index end, const float* g, const std::array<const float*, kHistory>& dg,
                   const double* theta, float* next) {
    float t[H];
    for (int a = 0; a < H; ++a) t[a] = float(theta[a]);
    for (Eigen::Index e = begin; e < end; ++e) {
        float v = g[e];
        for (int a = 0; a < H; ++a) v -= t[a] * dg[std::size_t(a)][e];
        next[e] = v;
    }
}

// The chunk lengths the fused pass takes (the others go one value at a time).
constexpr Eigen::Index fused_multiple(double) { return 2 * Eigen::Index(Eigen::internal::packet_traits<double>::size); }
constexpr Eigen::Index fused_multiple(float) { return kDotBlock; }

// A dot product over a short last chunk, in the fused pass's order: Eigen's dot() (double), or
// block_dot (float).
double chunk_dot(const double* a, const double* b, Eigen::Index length) {
    using Segment = Eigen::Map<const Eigen::VectorXd>;
    return Segment(a, length).dot(Segment(b, length));
}
double chunk_dot(const float* a, const float* b, Eigen::Index length) { return block_dot(a, b, length); }

// Calls body(std::integral_constant<int, h>{}) for a history length h in 1..kHistory, so that
// the chunk loops are compiled for each length (their per-slot loops unrolled).
template <typename Body>
void with_history_length(int h, Body&& body) {
    static_assert(kHistory == 5, "one case per history length");
    switch (h) {
        case 1: return body(std::integral_constant<int, 1>{});
        case 2: return body(std::integral_constant<int, 2>{});
        case 3: return body(std::integral_constant<int, 3>{});
        case 4: return body(std::integral_constant<int, 4>{});
        default: return body(std::integral_constant<int, 5>{});
    }
}

}  // namespace

template <typename T>
Anderson<T>::Anderson(Eigen::Index size)
    : size_(size),
      f_(std::size_t(size)),
      g_prev_(std::size_t(size)),
      f_prev_(std::size_t(size)),
      g_(std::size_t(size)),
      partial_(std::size_t((size + kChunk - 1) / kChunk) * 2 * kHistory) {
    for (std::vector<T>& d : dg_) d.resize(std::size_t(size));
    for (std::vector<T>& d : df_) d.resize(std::size_t(size));
    slot_dots_.setZero();
}

template <typename T>
bool Anderson<T>::step(const T* current, T* next) {
    const T* const g = g_.data();
    T* const f = f_.data();
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
        std::array<const T*, kHistory> history{};
        for (int a = 0; a < h; ++a) history[std::size_t(a)] = df_[slot_of(a)].data();
        T* const new_dg = dg_[slot].data();
        T* const new_df = df_[slot].data();
        const T* const g_prev = g_prev_.data();
        const T* const f_prev = f_prev_.data();
        const Eigen::Index chunks = (size_ + kChunk - 1) / kChunk;
        double* const partial = partial_.data();
        for_chunks(size_, [&](Eigen::Index c, Eigen::Index begin, Eigen::Index end) {
            double* const sums = partial + c * 2 * kHistory;
            if ((end - begin) % fused_multiple(T{}) == 0 && h >= 1) {
                with_history_length(h, [&](auto history_length) {
                    fused_chunk<decltype(history_length)::value>(begin, end, g, current, g_prev, f_prev, f, new_dg,
                                                                 new_df, history, sums, sums + kHistory);
                });
                return;
            }
            for (Eigen::Index e = begin; e < end; ++e) {
                const T fe = g[e] - current[e];
                f[e] = fe;
                new_dg[e] = g[e] - g_prev[e];
                new_df[e] = fe - f_prev[e];
            }
            for (int a = 0; a < h; ++a) {
                const T* const d = history[std::size_t(a)] + begin;
                sums[a] = chunk_dot(new_df + begin, d, end - begin);
                sums[kHistory + a] = chunk_dot(d, f + begin, end - begin);
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
        std::array<const T*, kHistory> dg{};
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

template class Anderson<double>;
template class Anderson<float>;

}  // namespace foldcast::drape::detail
