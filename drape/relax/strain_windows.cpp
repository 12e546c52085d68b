#include "strain_windows.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace foldcast::drape::detail {

namespace {
// Measured on the 256x256 x 120-frame animation (docs/benchmarks.md, "Strain windows" and
// "Windows that settle into a band"): 6 vertices either side of an edge and 30 sweeps per
// round, up to 5 rounds (each round's windows around the edges the last one left over).
// With a band the windows' runs along the top row settle where projecting to the rest
// length did not; more sweeps, rounds or a wider radius saved no further iterations.
constexpr int kRadius = 6, kSweeps = 30, kRounds = 5;
}  // namespace

// Named, not anonymous: StrainWindows::limit's lambdas hold GridEdges, and a type from an
// anonymous namespace in them is a -Wsubobject-linkage error once the unity build joins files.
namespace strain_window_steps {

// The grid's edges and where their ends are: an edge is 2 k + 0 (k to its right neighbour)
// or 2 k + 1 (k to the vertex below).
template <typename T>
struct GridEdges {
    T *x, *y, *z;
    int nu, nv;
    double rest_u, rest_v;
    std::size_t far_end(std::size_t edge) const { return edge / 2 + (edge % 2 ? std::size_t(nu) : 1); }
    double rest(std::size_t edge) const { return edge % 2 ? rest_v : rest_u; }
    double strain(std::size_t edge) const {
        const std::size_t a = edge / 2, b = far_end(edge);
        const double dx = double(x[b]) - double(x[a]), dy = double(y[b]) - double(y[a]),
                     dz = double(z[b]) - double(z[a]);
        return std::abs(std::sqrt(dx * dx + dy * dy + dz * dz) / rest(edge) - 1.0);
    }
};

// The edges beyond the bound.  The whole grid's edges, a row at a time: squared lengths
// against the squared limits in T, branch-free so that it vectorises (a scan is as long as a
// global iteration's local step, and most rows have no edge beyond), then the rows that do,
// edge by edge.
template <typename T>
std::vector<std::size_t> edges_beyond(const GridEdges<T>& g, double bound) {
    const int nu = g.nu, nv = g.nv;
    const T *const x = g.x, *const y = g.y, *const z = g.z;
    std::vector<std::size_t> over;
    const auto beyond = [&](const T* x0, const T* y0, const T* z0, std::size_t step, std::size_t count, double rest) {
        const T shortest = T(rest * (1.0 - bound) * rest * (1.0 - bound));
        const T longest = T(rest * (1.0 + bound) * rest * (1.0 + bound));
        int any = 0;
        for (std::size_t e = 0; e < count; ++e) {
            const T dx = x0[e + step] - x0[e], dy = y0[e + step] - y0[e], dz = z0[e + step] - z0[e];
            const T squared = dx * dx + dy * dy + dz * dz;
            any |= int(squared > longest) | int(squared < shortest);
        }
        return any != 0;
    };
    for (int j = 0; j < nv; ++j) {
        const std::size_t row = std::size_t(j) * std::size_t(nu);
        const bool across = beyond(x + row, y + row, z + row, 1, std::size_t(nu) - 1, g.rest_u);
        const bool down = j + 1 < nv && beyond(x + row, y + row, z + row, std::size_t(nu), std::size_t(nu), g.rest_v);
        if (!across && !down) continue;
        for (std::size_t k = row; k < row + std::size_t(nu); ++k) {
            if (across && k + 1 < row + std::size_t(nu) && g.strain(2 * k) > bound) over.push_back(2 * k);
            if (down && g.strain(2 * k + 1) > bound) over.push_back(2 * k + 1);
        }
    }
    return over;
}

// The movable vertices within kRadius of each edge over the bound (`marked`, sorted);
// returns whether an edge lies between two pins, which no window can move.
template <typename T>
bool mark_movable(const GridEdges<T>& g, const std::vector<std::size_t>& over, const std::vector<char>& pinned,
                  std::vector<char>& movable, std::vector<std::size_t>& marked) {
    const int nu = g.nu, nv = g.nv;
    bool between_pins = false;
    for (const std::size_t edge : over) {
        if (pinned[edge / 2] && pinned[g.far_end(edge)]) {
            between_pins = true;
            continue;
        }
        const int i = int(edge / 2 % std::size_t(nu)), j = int(edge / 2 / std::size_t(nu));
        const int right = edge % 2 ? 0 : 1, down = edge % 2 ? 1 : 0;
        for (int b = std::max(0, j - kRadius); b <= std::min(nv - 1, j + down + kRadius); ++b)
            for (int a = std::max(0, i - kRadius); a <= std::min(nu - 1, i + right + kRadius); ++a) {
                const std::size_t v = std::size_t(b) * std::size_t(nu) + std::size_t(a);
                if (!movable[v] && !pinned[v]) movable[v] = 1, marked.push_back(v);
            }
    }
    std::sort(marked.begin(), marked.end());
    return between_pins;
}

// Windows that share no movable vertex share no edge that moves either end of both: they
// settle independently, in parallel, each in its own row-major order, so the result is the
// same on any number of threads.  Numbered from their first vertex; returns each window's
// edges: every edge with a movable end, once, with the window of that end (in row-major
// order: marked is sorted, and an edge is listed from its first vertex when movable).
std::vector<std::vector<std::size_t>> connected_windows(int nu, int nv, const std::vector<std::size_t>& marked,
                                                        const std::vector<char>& movable, std::vector<int>& window_of) {
    int count = 0;
    std::vector<std::size_t> stack;
    for (const std::size_t seed : marked) {
        if (window_of[seed] >= 0) continue;
        window_of[seed] = count;
        stack.push_back(seed);
        while (!stack.empty()) {
            const std::size_t v = stack.back();
            stack.pop_back();
            const int i = int(v % std::size_t(nu)), j = int(v / std::size_t(nu));
            const auto reach = [&](bool inside, std::size_t o) {
                if (inside && movable[o] && window_of[o] < 0) window_of[o] = count, stack.push_back(o);
            };
            reach(i > 0, v - 1), reach(i + 1 < nu, v + 1);
            reach(j > 0, v - std::size_t(nu)), reach(j + 1 < nv, v + std::size_t(nu));
        }
        ++count;
    }
    std::vector<std::vector<std::size_t>> windows(static_cast<std::size_t>(count));
    for (const std::size_t v : marked) {
        std::vector<std::size_t>& edges = windows[std::size_t(window_of[v])];
        const int i = int(v % std::size_t(nu)), j = int(v / std::size_t(nu));
        if (i > 0 && !movable[v - 1]) edges.push_back(2 * (v - 1));
        if (j > 0 && !movable[v - std::size_t(nu)]) edges.push_back(2 * (v - std::size_t(nu)) + 1);
        if (i + 1 < nu) edges.push_back(2 * v);
        if (j + 1 < nv) edges.push_back(2 * v + 1);
    }
    return windows;
}

// kSweeps sweeps over one window's edges (sorted here), each edge outside its band
// projected to the nearest length within it.
template <typename T>
void settle_window(const GridEdges<T>& g, std::vector<std::size_t>& edges, const std::vector<char>& movable,
                   const T (&shortest_of)[2], const T (&longest_of)[2]) {
    T *const x = g.x, *const y = g.y, *const z = g.z;
    std::sort(edges.begin(), edges.end());
    for (int sweep = 0; sweep < kSweeps; ++sweep)
        for (const std::size_t edge : edges) {
            // In T: a sweep is a chain of dependent square roots, and float's rounding
            // of an edge (~1e-5 of it) is far inside the margin the caller aims within.
            const std::size_t a = edge / 2, b = g.far_end(edge);
            const T dx = x[b] - x[a], dy = y[b] - y[a], dz = z[b] - z[a];
            const T squared = dx * dx + dy * dy + dz * dz;
            if (!(squared > T(0))) continue;
            const T length = std::sqrt(squared);
            const T shortest = shortest_of[edge % 2], longest = longest_of[edge % 2];
            if (length >= shortest && length <= longest) continue;
            // Each movable end takes its share of the change to the nearest length
            // within the band.
            const T c = T(1) - (length > longest ? longest : shortest) / length;
            const T share_a = movable[a] ? (movable[b] ? T(0.5) : T(1)) : T(0);
            const T share_b = movable[b] ? (movable[a] ? T(0.5) : T(1)) : T(0);
            x[a] += share_a * c * dx, y[a] += share_a * c * dy, z[a] += share_a * c * dz;
            x[b] -= share_b * c * dx, y[b] -= share_b * c * dy, z[b] -= share_b * c * dz;
        }
}

}  // namespace strain_window_steps

template <typename T>
bool StrainWindows::limit(T* x, T* y, T* z, double bound, double settle, Scratch& scratch) const {
    const strain_window_steps::GridEdges<T> g{x, y, z, grid.nu, grid.nv, rest_u, rest_v};
    const std::size_t n = std::size_t(grid.nu) * std::size_t(grid.nv);
    const std::vector<char>& pinned = *is_pinned;
    // The band each window's edges settle into, by direction (edge % 2: 0 along a row, 1 down
    // a column); settle 0 leaves only the rest length itself.
    const T shortest_of[2] = {T(rest_u) * T(1.0 - settle), T(rest_v) * T(1.0 - settle)};
    const T longest_of[2] = {T(rest_u) * T(1.0 + settle), T(rest_v) * T(1.0 + settle)};

    std::vector<std::size_t> over = strain_window_steps::edges_beyond(g, bound);
    // Left all 0 / -1 by the last call: only the marked vertices are set, and reset below.
    std::vector<char>& movable = scratch.movable;
    std::vector<int>& window_of = scratch.window_of;
    if (movable.size() != n) movable.assign(n, 0), window_of.assign(n, -1);
    std::vector<std::size_t> marked;
    const auto reset = [&] {
        for (const std::size_t v : marked) movable[v] = 0, window_of[v] = -1;
        marked.clear();
    };
    bool between_pins = false;  // an edge beyond the bound that no window can move
    for (int round = 0; !over.empty(); ++round) {
        reset();
        if (round == kRounds) return false;
        if (strain_window_steps::mark_movable(g, over, pinned, movable, marked)) between_pins = true;
        std::vector<std::vector<std::size_t>> windows =
            strain_window_steps::connected_windows(grid.nu, grid.nv, marked, movable, window_of);
        std::vector<std::vector<std::size_t>> left(windows.size());  // each window's edges still over
        tbb::parallel_for(std::size_t(0), windows.size(), [&](std::size_t w) {
            strain_window_steps::settle_window(g, windows[w], movable, shortest_of, longest_of);
            // Only the windows' edges moved: the rest stayed within the bound.
            for (const std::size_t edge : windows[w])
                if (g.strain(edge) > bound) left[w].push_back(edge);
        });
        over.clear();
        for (const std::vector<std::size_t>& edges : left) over.insert(over.end(), edges.begin(), edges.end());
    }
    reset();
    return !between_pins;
}

template bool StrainWindows::limit<float>(float*, float*, float*, double, double, Scratch&) const;
template bool StrainWindows::limit<double>(double*, double*, double*, double, double, Scratch&) const;

}  // namespace foldcast::drape::detail
