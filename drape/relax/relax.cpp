// Relaxation towards isometry by local/global projection (projective dynamics, Bouaziz et
// al. 2014, without inertia): minimise
//   sum_edges |x_i - x_j - p_e|^2 + anchor sum_vertices |x_k - t_k|^2
// over the free vertices, alternating the local step (p_e = the edge's current direction at
// its rest length; in the first RelaxSettings::smoothing_iterations that direction blended
// along the thread, thread_directions.hpp) with the global step, a linear solve whose matrix (graph Laplacian +
// anchor) depends only on the grid and the pinned set: diagonal in the grid's DCT basis, it is
// solved by two DCTs and a small system for the pins (grid_solver.hpp), set up once and
// reused for every iteration and every frame.  Animation frames (animation.cpp) also
// over-relax the local step's projections (RelaxSettings::over_relaxation) and bring the last
// edges over the max back by strain limiting in windows (strain_windows.hpp).
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <type_traits>

#include "foldcast/core/error.hpp"
#include "foldcast/drape/relax.hpp"
#include "thread_directions.hpp"
#include "anderson.hpp"
#include "fold_surface.hpp"
#include "grid_solver.hpp"
#include "strain_windows.hpp"

namespace foldcast::drape {

struct GridRelaxer::Impl {
    GridSize grid;
    double rest_u = 0.0, rest_v = 0.0;
    RelaxSettings settings;
    double anchor = 0.0;               // the matrix's anchor term, scaled so that it does not grow with nu
    std::vector<char> is_pinned;       // per vertex
    std::vector<int> pinned_vertices;  // in vertex order, each once
    std::unique_ptr<detail::GridSolver> solver;
    detail::StrainWindows windows;

    // relax()'s arrays (tens of megabytes at 256x256), kept for the next call: allocating them
    // afresh for every animation frame cost more in page faults than a few iterations.  A call
    // takes them (or makes its own while another call holds them) and gives them back.
    template <typename T>
    struct Workspace;
    mutable std::mutex spare_lock;
    mutable std::unique_ptr<Workspace<double>> spare_double;
    mutable std::unique_ptr<Workspace<float>> spare_float;
    template <typename T>
    std::unique_ptr<Workspace<T>>& spare() const {
        if constexpr (std::is_same_v<T, double>)
            return spare_double;
        else
            return spare_float;
    }

    template <typename T>
    RelaxReport relax(std::vector<Vec3f>& positions, const std::vector<Vec3f>& targets) const;
    // One relax() call's iterations, in their steps (below).
    template <typename T>
    struct Run;
};

// T: the per-vertex arrays' type (RelaxSettings::single_precision).  An iteration is a few
// sweeps over them, too large for the caches at 256x256, so float halves the memory moved.
// Float's rounding of a position (~3e-8 m) is a thousandth of the stretch bounds' scale on a
// 4 mm edge; sums over the grid (stretch, energy, the Anderson step's dot products) and the
// DCTs are in double.
template <typename T>
struct GridRelaxer::Impl::Workspace {
    detail::ThreadDirections<T> directions;    // the smoothing phase's edge directions
    std::vector<T> right_len, down_len;        // each edge's length (to the right, below)
    std::vector<T> right_factor, down_factor;  // rest / length of the same edges (0 where length 0)
    std::vector<T> target_y, target_z;         // the targets' height and depth
    std::vector<T> pull;                       // per vertex: its fold-line pull (0: none)
    std::vector<double> row_sum, row_max, row_energy;
    std::array<std::vector<T>, 3> global_rhs;  // per coordinate, every vertex (pins ignored)
    std::vector<T> spectrum;                   // the global step's DCT work array, per coordinate
    // Positions, every vertex's x, then every y, then every z: what the global step returns
    // per coordinate and what the Anderson step combines, so neither needs a copy.
    std::vector<T> current, next;
    detail::Anderson<T> anderson;
    detail::StrainWindows::Scratch windows;

    Workspace(std::size_t n, int rows)
        : right_len(n, T(0)),
          down_len(n, T(0)),
          right_factor(n, T(0)),
          down_factor(n, T(0)),
          target_y(n),
          target_z(n),
          pull(n),
          row_sum(std::size_t(rows)),
          row_max(std::size_t(rows)),
          row_energy(std::size_t(rows)),
          spectrum(3 * n),
          current(3 * n),
          next(3 * n),
          anderson(Eigen::Index(3 * n)) {
        for (std::vector<T>& b : global_rhs) b.assign(n, T(0));
    }
};

GridRelaxer::GridRelaxer(const ClothParams& params, GridSize grid, std::vector<int> pinned, RelaxSettings settings)
    : impl_(std::make_unique<Impl>()) {
    detail::validate_grid(grid);
    Impl& m = *impl_;
    m.grid = grid;
    m.rest_u = params.width_m / (grid.nu - 1);
    m.rest_v = params.height_m / (grid.nv - 1);
    m.settings = settings;
    if (!(settings.proximal_share > 0.0 && settings.proximal_share <= 1.0))
        throw InputError("relaxation: proximal_share = " + std::to_string(settings.proximal_share) +
                         ": must be in (0, 1]");
    if (!(settings.over_relaxation >= 1.0 && settings.over_relaxation <= 2.0))
        throw InputError("relaxation: over_relaxation = " + std::to_string(settings.over_relaxation) +
                         ": must be in [1, 2]");
    // Fold-line vertices per fold line grow with nu while the edge energy of the sheet
    // does not: per-vertex weights scale as 1/nu (set for 64 columns).
    m.anchor = settings.anchor_weight * settings.proximal_share * 63.0 / (grid.nu - 1);
    const int n = grid.nu * grid.nv;
    m.is_pinned.assign(std::size_t(n), 0);
    for (int p : pinned) {
        if (p < 0 || p >= n) throw InputError("pinned vertex " + std::to_string(p) + " is not in the grid");
        m.is_pinned[std::size_t(p)] = 1;
    }
    for (int k = 0; k < n; ++k)
        if (m.is_pinned[std::size_t(k)]) m.pinned_vertices.push_back(k);
    if (m.pinned_vertices.size() == std::size_t(n))
        throw std::runtime_error("relaxation: every vertex of the grid is pinned, nothing to relax");
    // The matrix: the graph Laplacian of the warp/weft edges plus the anchor on the diagonal.
    m.solver = std::make_unique<detail::GridSolver>(grid, m.anchor, m.pinned_vertices);
    m.windows = {grid, m.rest_u, m.rest_v, &m.is_pinned};
}

GridRelaxer::~GridRelaxer() = default;
GridRelaxer::GridRelaxer(GridRelaxer&&) noexcept = default;
GridRelaxer& GridRelaxer::operator=(GridRelaxer&&) noexcept = default;

namespace {

// Vertices where the model's fold lines cross each column: local extrema of |z| going down
// the column (the first vertex of a plateau, where the fibre hangs straight below the
// lowest fold line).  These carry the soft targets; the rest of the cloth is free.
std::vector<double> fold_line_vertices(const std::vector<Vec3f>& model, GridSize grid, double rest_v) {
    std::vector<double> crest(model.size(), 0.0);
    double deepest = 0.0;
    for (const Vec3f& p : model) deepest = std::max(deepest, std::abs(double(p.z())));
    if (deepest <= 0.0) return crest;
    const double floor = 1e-3 * deepest;  // ignore the flat ends of the fold lines near the supports
    // A target on one vertex of a fine column would pull a spike out of the cloth: each
    // crest's pull is spread over the rows within kSpread_m of it (tapering), and scaled
    // with the row spacing so that the pull per length of fibre does not depend on nv.
    constexpr double kSpread_m = 0.01;
    const int reach = std::max(1, int(std::lround(kSpread_m / rest_v)));
    const double per_row = std::min(1.0, rest_v * 63.0 / 0.7);
    // Column by column (each writes only its own column): in parallel.
    tbb::parallel_for(0, grid.nu, [&](int i) {
        for (int j = 0; j < grid.nv; ++j) {
            const auto z = [&](int row) { return std::abs(double(model[std::size_t(row * grid.nu + i)].z())); };
            const double here = z(j);
            if (here <= floor) continue;
            const bool above = j == 0 || here > z(j - 1);
            const bool below = j + 1 == grid.nv || here >= z(j + 1);
            if (!above || !below) continue;
            // Full weight on the centre fibre, fading towards the supports where the
            // model's fold lines converge and cannot all be kept.
            const double w = std::pow(here / deepest, 8);
            for (int d = -reach; d <= reach; ++d) {
                const int row = j + d;
                if (row < 0 || row >= grid.nv) continue;
                double& c = crest[std::size_t(row * grid.nu + i)];
                c = std::max(c, w * per_row * double(reach + 1 - std::abs(d)) / (reach + 1));
            }
        }
    });
    return crest;
}

// Sums over a row in lanes of the arrays' type T, two SIMD packets wide (entry e in lane
// e % kLanes), so that the loops vectorise instead of waiting on one running sum per edge; the
// lanes are added in order in double.  A row's sums have a few hundred terms, where float's
// rounding (~1e-5 of the sum) is far below what the stopping rule and the energy test tell
// apart.
template <typename T>
using Packet = typename Eigen::internal::packet_traits<T>::type;
template <typename T>
constexpr std::size_t kPacket = Eigen::internal::packet_traits<T>::size;
template <typename T>
constexpr std::size_t kLanes = 2 * kPacket<T>;

// Runs term(lanes, e) for every entry e < count: the whole packets, then the rest a lane at
// a time; returns the lanes, two packets of accumulators per quantity.
template <typename T, int N, typename PacketTerm, typename ScalarTerm>
std::array<std::array<T, kLanes<T>>, N> lane_sums(std::size_t count, PacketTerm&& packet_term,
                                                  ScalarTerm&& scalar_term) {
    using namespace Eigen::internal;
    Packet<T> low[N], high[N];
    for (int q = 0; q < N; ++q) low[q] = high[q] = pset1<Packet<T>>(T(0));
    std::size_t e = 0;
    for (; e + kLanes<T> <= count; e += kLanes<T>) packet_term(low, e), packet_term(high, e + kPacket<T>);
    std::array<std::array<T, kLanes<T>>, N> lanes;
    for (int q = 0; q < N; ++q)
        pstoreu(lanes[std::size_t(q)].data(), low[q]), pstoreu(lanes[std::size_t(q)].data() + kPacket<T>, high[q]);
    for (std::size_t l = 0; e < count; ++e, ++l) scalar_term(lanes, l, e);
    return lanes;
}

// factor[e] = rest / len[e], 0 where len[e] is 0, a packet at a time (a loop with the test
// keeps the division behind a branch: scalar).  Over-relaxed (omega > 1): the projection
// carried past the rest length, len + omega (rest - len), i.e. omega rest / len - (omega - 1).
template <typename T>
void rest_over(const T* len, std::size_t count, T rest, T omega, T* factor) {
    using namespace Eigen::internal;
    using P = Packet<T>;
    const P r = pset1<P>(rest * omega), zero = pset1<P>(T(0)), one = pset1<P>(T(1));
    const P past = pset1<P>(omega - T(1));
    std::size_t e = 0;
    const bool over = omega != T(1);
    for (; e + kPacket<T> <= count; e += kPacket<T>) {
        const P l = ploadu<P>(len + e), positive = pcmp_lt(zero, l);
        P f = pdiv(pand(positive, r), pselect(positive, l, one));
        if (over) f = psub(f, pand(positive, past));
        pstoreu(factor + e, f);
    }
    for (; e < count; ++e) {
        factor[e] = (len[e] > T(0) ? rest * omega : T(0)) / (len[e] > T(0) ? len[e] : T(1));
        if (over && len[e] > T(0)) factor[e] -= omega - T(1);
    }
}

struct Sums {
    double sum = 0.0, max = 0.0, energy = 0.0;  // stretch |len / rest - 1|, its max, (len - rest)^2
};

template <typename T>
Sums edge_sums(const T* len, std::size_t count, T rest) {
    using namespace Eigen::internal;
    using P = Packet<T>;
    const T inverse = T(1) / rest;
    const P r = pset1<P>(rest), inv = pset1<P>(inverse);
    const auto lanes = lane_sums<T, 3>(
        count,
        [&](auto& acc, std::size_t e) {
            const P d = psub(ploadu<P>(len + e), r), stretch = pabs(pmul(d, inv));
            acc[0] = padd(acc[0], stretch), acc[1] = pmax(acc[1], stretch), acc[2] = padd(acc[2], pmul(d, d));
        },
        [&](auto& acc, std::size_t l, std::size_t e) {
            const T d = len[e] - rest, stretch = std::abs(d * inverse);
            acc[0][l] += stretch, acc[1][l] = std::max(acc[1][l], stretch), acc[2][l] += d * d;
        });
    Sums out;
    for (std::size_t l = 0; l < kLanes<T>; ++l) {
        out.sum += double(lanes[0][l]);
        out.max = std::max(out.max, double(lanes[1][l]));
        out.energy += double(lanes[2][l]);
    }
    return out;
}

// sum pull ((y - target_y)^2 + (z - target_z)^2) over a row (pull 0: an exact 0 term).
template <typename T>
double pull_energy(const T* y, const T* z, const T* ty, const T* tz, const T* pull, std::size_t count) {
    using namespace Eigen::internal;
    using P = Packet<T>;
    const auto lanes = lane_sums<T, 1>(
        count,
        [&](auto& acc, std::size_t e) {
            const P dy = psub(ploadu<P>(y + e), ploadu<P>(ty + e));
            const P dz = psub(ploadu<P>(z + e), ploadu<P>(tz + e));
            acc[0] = padd(acc[0], pmul(ploadu<P>(pull + e), padd(pmul(dy, dy), pmul(dz, dz))));
        },
        [&](auto& acc, std::size_t l, std::size_t e) {
            const T dy = y[e] - ty[e], dz = z[e] - tz[e];
            acc[0][l] += pull[e] * (dy * dy + dz * dz);
        });
    double out = 0.0;
    for (const T v : lanes[0]) out += double(v);
    return out;
}

}  // namespace

// One relax() call: the workspace it holds, where the pins are held, the fold-line pulls and
// the iteration count, and the steps of the local/global iteration.
template <typename T>
struct GridRelaxer::Impl::Run {
    struct Local {
        double energy, mean, max;
    };
    static constexpr int kSoftenEvery = 30;
    static constexpr int kMaxWindowFixes = 3;
    static constexpr double kWindowAim = 0.98, kWindowSettle = 0.8;

    const Impl& m;
    Workspace<T>& w;
    const GridSize grid;
    const std::size_t n;
    const std::vector<double>& crest;
    const double anchor;
    const int nu, nv;
    const double rest_u, rest_v;
    const T anchor_t;
    double anchor_scale = 1.0;
    int iteration = 0;  // the local step reads it: in the smoothing phase or not
    // Where the pinned vertices are held: fixed for the whole relaxation.
    std::array<Eigen::VectorXd, 3> pinned_positions;

    Run(const Impl& impl, Workspace<T>& workspace, const std::vector<double>& crest_weights)
        : m(impl),
          w(workspace),
          grid(impl.grid),
          n(std::size_t(impl.grid.nu) * std::size_t(impl.grid.nv)),
          crest(crest_weights),
          anchor(impl.anchor),
          nu(impl.grid.nu),
          nv(impl.grid.nv),
          rest_u(impl.rest_u),
          rest_v(impl.rest_v),
          anchor_t(T(impl.anchor)) {}

    // Per-vertex set-up and the result below, a row at a time: run on one thread, an
    // animation frame's passes over the grid outside the iterations left the other core idle.
    template <typename Body>
    void each_row(Body&& body) const {
        tbb::parallel_for(0, grid.nv, [&](int j) {
            const std::size_t row = std::size_t(j) * std::size_t(grid.nu);
            for (std::size_t k = row; k < row + std::size_t(grid.nu); ++k) body(k);
        });
    }

    void start(const std::vector<Vec3f>& positions, const std::vector<Vec3f>& targets) {
        each_row([&](std::size_t k) {
            const Vec3f& start = m.is_pinned[k] ? targets[k] : positions[k];
            for (std::size_t c = 0; c < 3; ++c) w.current[c * n + k] = T(start(Eigen::Index(c)));
            w.target_y[k] = T(targets[k].y()), w.target_z[k] = T(targets[k].z());
        });
        for (std::size_t c = 0; c < 3; ++c) {
            pinned_positions[c].resize(Eigen::Index(m.pinned_vertices.size()));
            for (std::size_t i = 0; i < m.pinned_vertices.size(); ++i)
                pinned_positions[c][Eigen::Index(i)] = double(w.current[c * n + std::size_t(m.pinned_vertices[i])]);
        }
        set_pull();
    }

    // Each vertex's pull towards its fold-line target (crest weight x anchor_scale), 0 where
    // it has none: set again whenever anchor_scale changes.
    void set_pull() {
        each_row([&](std::size_t k) {
            w.pull[k] =
                !m.is_pinned[k] && crest[k] > 0.0 ? T(crest[k] / m.settings.proximal_share * anchor_scale) : T(0);
        });
    }

    // One coordinate of one row of the global step's right-hand side:
    //   anchor (x_k + pull (t_k - x_k)) + sum over the edges (x_k - x_o) rest / len
    // (left, right, up, down, the same operations in the same order as a vertex at a time;
    // a zero pull or factor adds an exact zero).  Up and Down: whether the row has rows
    // above and below.  Branch-free inside the row, so it vectorises.
    template <typename Up, typename Down>
    void rhs_row(Up, Down, const T* __restrict x, const T* __restrict target, std::size_t row,
                 T* __restrict out) const {
        const T* __restrict const pull = w.pull.data();
        const T* __restrict const rf = w.right_factor.data();
        const T* __restrict const df = w.down_factor.data();
        constexpr bool kUp = Up::value, kDown = Down::value;
        const std::size_t stride = std::size_t(nu);
        const auto vertex = [&](std::size_t k, bool left, bool right) {
            T b = x[k];
            if (target) b += pull[k] * (target[k] - x[k]);
            b *= anchor_t;
            if (left) b += (x[k] - x[k - 1]) * rf[k - 1];
            if (right) b += (x[k] - x[k + 1]) * rf[k];
            if (kUp) b += (x[k] - x[k - stride]) * df[k - stride];
            if (kDown) b += (x[k] - x[k + stride]) * df[k];
            out[k] = b;
        };
        vertex(row, false, nu > 1);
        const std::size_t end = row + stride - 1;
        // The interior of the row, branch-free so that it vectorises: with the fold-line pull
        // (y and z) or without it (x).
        const auto interior = [&](auto with_target) {
            for (std::size_t k = row + 1; k < end; ++k) {
                T b = x[k];
                if constexpr (decltype(with_target)::value) b += pull[k] * (target[k] - x[k]);
                b *= anchor_t;
                b += (x[k] - x[k - 1]) * rf[k - 1];
                b += (x[k] - x[k + 1]) * rf[k];
                if (kUp) b += (x[k] - x[k - stride]) * df[k - stride];
                if (kDown) b += (x[k] - x[k + stride]) * df[k];
                out[k] = b;
            }
        };
        if (target)
            interior(std::true_type{});
        else
            interior(std::false_type{});
        if (nu > 1) vertex(end, true, false);
    }

    // Row j's edge lengths and rest / length factors (each edge's length computed once per
    // local step, the edge to the right of and the one below each vertex, instead of once
    // from each end and again for the stretch: |x_k - x_o| and |x_o - x_k| are the same bits,
    // so the result is too), then the row's stretch and energy.
    void row_lengths_and_energy(int j, const T* px, const T* py, const T* pz, T factor_u, T factor_v, T omega) {
        const std::size_t row = std::size_t(j) * std::size_t(nu);
        // |x_o - x_k| as Eigen's norm() sums it, (dx^2 + dy^2) + dz^2, for the edges from
        // `first` to the vertex `step` further on; rest / |x_o - x_k| beside it (no
        // division by 0, so that the loop vectorises).
        const auto lengths = [&](std::size_t first, std::size_t count, std::size_t step, T rest, T* __restrict len_out,
                                 T* __restrict factor_out) {
            const T* __restrict x = px + first;
            const T* __restrict y = py + first;
            const T* __restrict z = pz + first;
            len_out += first, factor_out += first;
            for (std::size_t e = 0; e < count; ++e) {
                const T dx = x[e + step] - x[e], dy = y[e + step] - y[e], dz = z[e + step] - z[e];
                len_out[e] = dx * dx + dy * dy + dz * dz;
            }
            // Eigen's packet square root (std::sqrt's errno check keeps the loop scalar).
            Eigen::Map<Eigen::Array<T, Eigen::Dynamic, 1>> squared(len_out, Eigen::Index(count));
            squared = squared.sqrt();
            rest_over(len_out, count, rest, omega, factor_out);
        };
        lengths(row, std::size_t(nu) - 1, 1, factor_u, w.right_len.data(), w.right_factor.data());
        if (j + 1 < nv)
            lengths(row, std::size_t(nu), std::size_t(nu), factor_v, w.down_len.data(), w.down_factor.data());
        // The row's stretch and energy from the lengths just computed (each edge once: to
        // the right and below), then the fold-line terms.
        const Sums right = edge_sums(w.right_len.data() + row, std::size_t(nu) - 1, T(rest_u));
        const Sums down = j + 1 < nv ? edge_sums(w.down_len.data() + row, std::size_t(nu), T(rest_v)) : Sums{};
        const double pulled = pull_energy(py + row, pz + row, w.target_y.data() + row, w.target_z.data() + row,
                                          w.pull.data() + row, std::size_t(nu));
        w.row_sum[std::size_t(j)] = right.sum + down.sum;
        w.row_max[std::size_t(j)] = std::max(right.max, down.max);
        w.row_energy[std::size_t(j)] = (right.energy + down.energy) + anchor * pulled;
    }

    // Row j's right-hand side, a coordinate at a time (x has no fold-line pull).  Pinned
    // vertices get one too, set to 0 by local().
    void row_right_hand_side(int j, const T* px, const T* py, const T* pz) {
        const std::size_t row = std::size_t(j) * std::size_t(nu);
        const auto rows = [&](auto up, auto down) {
            rhs_row(up, down, px, nullptr, row, w.global_rhs[0].data());
            rhs_row(up, down, py, w.target_y.data(), row, w.global_rhs[1].data());
            rhs_row(up, down, pz, w.target_z.data(), row, w.global_rhs[2].data());
        };
        using Yes = std::true_type;
        using No = std::false_type;
        if (j > 0 && j + 1 < nv)
            rows(Yes{}, Yes{});
        else if (j > 0)
            rows(Yes{}, No{});
        else if (j + 1 < nv)
            rows(No{}, Yes{});
        else
            rows(No{}, No{});
    }

    // The smoothing phase's edge terms: each edge at its rest length along its blended
    // direction d, +d for the edge arriving at a vertex, -d for the one leaving it.
    void add_thread_directions(const T* px, const T* py, const T* pz) {
        detail::thread_directions(px, py, pz, grid, m.settings.smoothing, w.directions);
        const detail::ThreadDirections<T>& d = w.directions;
        tbb::parallel_for(0, nv, [&](int j) {
            for (int i = 0; i < nu; ++i) {
                const std::size_t k = std::size_t(j) * std::size_t(nu) + std::size_t(i);
                for (std::size_t c = 0; c < 3; ++c) {
                    double b = 0.0;
                    if (i > 0) b += rest_u * double(d.right[c][k - 1]);
                    if (i + 1 < nu) b -= rest_u * double(d.right[c][k]);
                    if (j > 0) b += rest_v * double(d.down[c][k - std::size_t(nu)]);
                    if (j + 1 < nv) b -= rest_v * double(d.down[c][k]);
                    w.global_rhs[c][k] = T(double(w.global_rhs[c][k]) + b);
                }
            }
        });
    }

    // Local step at x: the right-hand side of the global step, the energy
    //   sum_edges (len - rest)^2 + anchor sum_fold-line vertices |x - target|^2
    // and the stretch.  Every vertex has the anchor term in the matrix: a fold-line vertex
    // is pulled to its target, any other to where it is (a proximal term: the same fixed
    // points, and the matrix stays the same for every frame).  Gathered per row, summed in
    // row order: the result does not depend on the thread count.
    Local local(const T* positions_now) {
        const T* const px = positions_now;
        const T* const py = positions_now + n;
        const T* const pz = positions_now + 2 * n;
        const bool smoothing = iteration < m.settings.smoothing_iterations && m.settings.smoothing > 0.0;
        // In the smoothing phase the edge terms come from the blended directions below, so
        // the rows' right-hand sides get the anchor terms only (rest 0 gives factors 0).
        const T factor_u = smoothing ? T(0) : T(rest_u), factor_v = smoothing ? T(0) : T(rest_v);
        const T omega = smoothing ? T(1) : T(m.settings.over_relaxation);
        tbb::parallel_for(0, nv, [&](int j) { row_lengths_and_energy(j, px, py, pz, factor_u, factor_v, omega); });
        tbb::parallel_for(0, nv, [&](int j) { row_right_hand_side(j, px, py, pz); });
        if (smoothing) add_thread_directions(px, py, pz);
        // The pins' right-hand sides, which the solve ignores, as +0: then it need not copy
        // the rest to zero them.
        for (const int p : m.pinned_vertices)
            for (std::vector<T>& b : w.global_rhs) b[std::size_t(p)] = T(0);
        Local out{0.0, 0.0, 0.0};
        for (int j = 0; j < grid.nv; ++j)
            out.energy += w.row_energy[std::size_t(j)], out.mean += w.row_sum[std::size_t(j)],
                out.max = std::max(out.max, w.row_max[std::size_t(j)]);
        const double edges = double(grid.nu - 1) * grid.nv + double(grid.nv - 1) * grid.nu;
        out.mean /= edges;
        return out;
    }

    // The global step, g = G(current), a coordinate at a time, the pins exactly where they
    // are held (the solve meets them to rounding).
    void global_step(T* const g) {
        tbb::parallel_for(0, 3, [&](int c) {
            T* const solved = g + std::size_t(c) * n;
            m.solver->solve(w.global_rhs[std::size_t(c)].data(), pinned_positions[std::size_t(c)], solved,
                            w.spectrum.data() + std::size_t(c) * n);
            for (std::size_t i = 0; i < m.pinned_vertices.size(); ++i)
                solved[m.pinned_vertices[i]] = T(pinned_positions[std::size_t(c)][Eigen::Index(i)]);
        });
    }

    // A few edges left beyond the max: strain limiting in windows around them.  Aimed a
    // little inside the bound (the global step nudges them back out), each window's edges
    // settled within 0.8 of that (docs/benchmarks.md, "Windows that settle into a band").
    // Three tries at most per relaxation; a window that cannot settle (a pinned edge's
    // neighbours) is left to the global iterations.  True when it ran.
    bool window_fix(RelaxReport& report, const Local& state) {
        if (!(m.settings.window_fix_below_max > 0.0 && report.window_fixes < kMaxWindowFixes &&
              iteration >= m.settings.smoothing_iterations && state.mean <= m.settings.target_mean &&
              state.max > m.settings.target_max && state.max <= m.settings.window_fix_below_max))
            return false;
        ++report.window_fixes;
        m.windows.limit(w.current.data(), w.current.data() + n, w.current.data() + 2 * n,
                        kWindowAim * m.settings.target_max, kWindowSettle * kWindowAim * m.settings.target_max,
                        w.windows);
        return true;
    }

    // Anderson acceleration of the local/global fixed-point map (anderson.hpp), with the
    // plain step whenever the accelerated one would raise the energy.
    void iterate(RelaxReport& report) {
        detail::Anderson<T>& anderson = w.anderson;
        anderson.restart();
        Local state = local(w.current.data());
        double accepted_energy = state.energy;
        while (!(state.mean <= m.settings.target_mean && state.max <= m.settings.target_max) &&
               iteration < m.settings.max_iterations) {
            // Not there yet after every kSoftenEvery iterations: the targets ask for more than
            // the cloth can give, so soften them.  After the smoothing phase: plain projections.
            const bool soften = iteration > 0 && iteration % kSoftenEvery == 0;
            const bool smoothing_over = iteration > 0 && iteration == m.settings.smoothing_iterations;
            if (soften || smoothing_over) anderson.forget();  // a new fixed-point map: the history goes
            // The last local step already projected plainly (it ran with the phase's last
            // iteration counted): only a softened pull changes what it computed.
            if (soften) {
                anchor_scale *= 0.5, set_pull();
                state = local(w.current.data());
                accepted_energy = state.energy;
            }
            ++iteration;
            global_step(anderson.g());
            const bool accelerated = anderson.step(w.current.data(), w.next.data());
            state = local(accelerated ? w.next.data() : anderson.last_g());
            bool plain = !accelerated;
            if (accelerated && !(state.energy <= accepted_energy)) {  // fall back to the plain step
                state = local(anderson.last_g());
                anderson.forget();
                plain = true;
            }
            accepted_energy = state.energy;
            if (plain)
                std::copy(anderson.last_g(), anderson.last_g() + 3 * n, w.current.begin());
            else
                w.current.swap(w.next);
            if (window_fix(report, state)) {
                anderson.forget();
                state = local(w.current.data());
                accepted_energy = state.energy;
            }
        }
    }

    void store(std::vector<Vec3f>& positions) const {
        each_row([&](std::size_t k) {
            positions[k] = Vec3f(float(w.current[k]), float(w.current[n + k]), float(w.current[2 * n + k]));
        });
    }
};

template <typename T>
RelaxReport GridRelaxer::Impl::relax(std::vector<Vec3f>& positions, const std::vector<Vec3f>& targets) const {
    const Impl& m = *this;
    const GridSize grid = m.grid;
    const std::size_t n = std::size_t(grid.nu) * std::size_t(grid.nv);
    if (positions.size() != n || targets.size() != n)
        throw InputError("relaxation: positions and targets must have one entry per grid vertex");
    const ClothParams rest_params = [&] {
        ClothParams p;
        p.width_m = m.rest_u * (grid.nu - 1);
        p.height_m = m.rest_v * (grid.nv - 1);
        return p;
    }();
    RelaxReport report;
    if (m.settings.report_stretch) report.before = detail::grid_stretch(targets, rest_params, grid);
    const std::vector<double> crest = fold_line_vertices(targets, grid, m.rest_v);

    std::unique_ptr<Workspace<T>> workspace;
    {
        const std::lock_guard<std::mutex> hold(m.spare_lock);
        workspace = std::move(m.spare<T>());
    }
    if (!workspace) workspace = std::make_unique<Workspace<T>>(n, grid.nv);
    Run<T> run(m, *workspace, crest);
    run.start(positions, targets);
    run.iterate(report);
    run.store(positions);
    report.iterations = run.iteration;
    if (m.settings.report_stretch) report.after = detail::grid_stretch(positions, rest_params, grid);
    const std::lock_guard<std::mutex> hold(m.spare_lock);
    m.spare<T>() = std::move(workspace);
    return report;
}

RelaxReport GridRelaxer::relax(std::vector<Vec3f>& positions, const std::vector<Vec3f>& targets) const {
    return impl_->settings.single_precision ? impl_->relax<float>(positions, targets)
                                            : impl_->relax<double>(positions, targets);
}

}  // namespace foldcast::drape
