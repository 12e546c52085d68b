// Makhoul's DCT (dct.hpp).  For a line x_0..x_{N-1} let v_n = x_{2n} and v_{N-1-n} = x_{2n+1}
// (even samples forwards, odd ones backwards) and V = FFT(v).  Then with w_k = exp(-i pi k / 2N)
//   REDFT10:  X_k = 2 Re(w_k V_k),  X_{N-k} = -2 Im(w_k V_k)          (0 < k < N - k)
// and, V being Hermitian, the real FFT's half spectrum is all that is needed.  The inverse
// runs the same steps backwards: V_k = conj(w_k) (X_k - i X_{N-k}) / 2, v = the inverse real
// FFT of V, and REDFT01(X) = 2 v put back in the original order.
#include "dct.hpp"

#include <fftw3.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <new>
#include <stdexcept>
#include <vector>

namespace foldcast::drape::detail {
namespace {

// FFTW's planner is not thread-safe; executing a plan on other arrays is.
std::mutex& planner_lock() {
    static std::mutex lock;
    return lock;
}

template <typename T>
struct FftwArray {
    T* data = nullptr;
    explicit FftwArray(std::size_t n) : data(static_cast<T*>(fftw_malloc(sizeof(T) * std::max<std::size_t>(n, 1)))) {
        if (!data) throw std::bad_alloc();
    }
    ~FftwArray() { fftw_free(data); }
    FftwArray(const FftwArray&) = delete;
    FftwArray& operator=(const FftwArray&) = delete;
};

// The work arrays of one block of lines, kept per thread between calls (fftw_malloc'd, so
// aligned as the plans' arrays were: a plan may then run on them).
struct BlockScratch {
    std::size_t size = 0, spectrum_size = 0;
    std::unique_ptr<FftwArray<double>> v;
    std::unique_ptr<FftwArray<fftw_complex>> spectrum;
};

BlockScratch& block_scratch(std::size_t size, std::size_t spectrum_size) {
    thread_local BlockScratch scratch;
    if (scratch.size < size) scratch.v = std::make_unique<FftwArray<double>>(size), scratch.size = size;
    if (scratch.spectrum_size < spectrum_size)
        scratch.spectrum = std::make_unique<FftwArray<fftw_complex>>(spectrum_size),
        scratch.spectrum_size = spectrum_size;
    return scratch;
}

// kBlock lines of one length at a time (FFTW vectorises across the lines of a batch, which a
// single line of 256 cannot use well): the real FFT's plans for a full block and for the
// last, shorter one, and the twiddles w_k.  Blocks are fixed by the grid, not by the threads.
constexpr int kBlock = 8;

struct Lines {
    int n = 0, half = 0;                                   // length, and the real FFT's half spectrum n/2 + 1
    fftw_plan r2c[kBlock + 1] = {}, c2r[kBlock + 1] = {};  // by the number of lines
    std::vector<double> cos_k, sin_k;                      // cos and sin of pi k / 2N

    Lines(int length, int lines)
        : n(length), half(length / 2 + 1), cos_k(std::size_t(length)), sin_k(std::size_t(length)) {
        for (int k = 0; k < n; ++k) {
            const double angle = M_PI * k / (2.0 * n);
            cos_k[std::size_t(k)] = std::cos(angle), sin_k[std::size_t(k)] = std::sin(angle);
        }
        FftwArray<double> v{std::size_t(n) * kBlock};
        FftwArray<fftw_complex> spectrum{std::size_t(half) * kBlock};
        const std::lock_guard<std::mutex> hold(planner_lock());
        for (const int count : {std::min(kBlock, lines), lines % kBlock}) {
            if (count == 0 || r2c[count]) continue;
            r2c[count] = fftw_plan_many_dft_r2c(1, &n, count, v.data, nullptr, 1, n, spectrum.data, nullptr, 1, half,
                                                FFTW_ESTIMATE);
            c2r[count] = fftw_plan_many_dft_c2r(1, &n, count, spectrum.data, nullptr, 1, half, v.data, nullptr, 1, n,
                                                FFTW_ESTIMATE);
            if (!r2c[count] || !c2r[count])
                throw std::runtime_error("DCT: FFTW could not plan real FFTs of length " + std::to_string(n));
        }
    }
    ~Lines() {
        const std::lock_guard<std::mutex> hold(planner_lock());
        for (int c = 0; c <= kBlock; ++c) {
            if (r2c[c]) fftw_destroy_plan(r2c[c]);
            if (c2r[c]) fftw_destroy_plan(c2r[c]);
        }
    }
    Lines(const Lines&) = delete;
    Lines& operator=(const Lines&) = delete;

    // Where a block's lines are: sample s of line c at base[c * line + s * sample] (a block of
    // rows: sample 1, line n; a block of columns: sample nu, line 1).  Each loop goes over the
    // block's lines innermost when the lines are interleaved, so a block of columns is read
    // and written a cache line (8 neighbours of a row) at a time instead of being copied into
    // contiguous lines and back (a column strides by a row's length, often a power of two,
    // which maps it onto a few cache sets).  The values and the operations on them are the
    // same either way.
    struct Layout {
        std::ptrdiff_t sample, line;
    };

    template <typename Body>
    static void each(int count, int samples, Layout layout, Body&& body) {
        if (layout.sample == 1) {
            for (int c = 0; c < count; ++c)
                for (int m = 0; m < samples; ++m) body(c, m);
        } else {
            for (int m = 0; m < samples; ++m)
                for (int c = 0; c < count; ++c) body(c, m);
        }
    }

    // One contiguous line each (a block of rows): the same operations as the general loops
    // below, in loops the compiler vectorises.  T: the grid's values, double or float (the
    // FFTs run in double on the block's scratch either way).
    template <typename T>
    void reorder_line(const T* __restrict x, double* __restrict v) const {
        for (int m = 0; 2 * m < n; ++m) v[m] = x[2 * m];
        for (int m = 0; 2 * m + 1 < n; ++m) v[n - 1 - m] = x[2 * m + 1];
    }
    template <typename T>
    void twiddle_line(const double* __restrict spectrum, T* __restrict x) const {
        const double* __restrict co = cos_k.data();
        const double* __restrict sn = sin_k.data();
        x[0] = T(2.0 * spectrum[0]);
        for (int k = 1; 2 * k < n; ++k) {
            const double re = spectrum[2 * k], im = spectrum[2 * k + 1];
            x[k] = T(2.0 * (co[k] * re + sn[k] * im));
            x[n - k] = T(-2.0 * (co[k] * im - sn[k] * re));
        }
        if (n % 2 == 0 && n > 0) {
            const int k = n / 2;
            x[k] = T(2.0 * (co[k] * spectrum[2 * k] + sn[k] * spectrum[2 * k + 1]));
        }
    }
    template <typename T>
    void untwiddle_line(const T* __restrict x, const T* __restrict scale, double* __restrict spectrum) const {
        const double* __restrict co = cos_k.data();
        const double* __restrict sn = sin_k.data();
        spectrum[0] = 0.5 * (scale ? double(x[0]) * double(scale[0]) : double(x[0])), spectrum[1] = 0.0;
        if (scale) {
            for (int k = 1; 2 * k <= n; ++k) {
                const double a = double(x[k]) * double(scale[k]), b = double(x[n - k]) * double(scale[n - k]);
                spectrum[2 * k] = 0.5 * (co[k] * a + sn[k] * b);
                spectrum[2 * k + 1] = 0.5 * (sn[k] * a - co[k] * b);
            }
        } else {
            for (int k = 1; 2 * k <= n; ++k) {
                const double a = double(x[k]), b = double(x[n - k]);
                spectrum[2 * k] = 0.5 * (co[k] * a + sn[k] * b);
                spectrum[2 * k + 1] = 0.5 * (sn[k] * a - co[k] * b);
            }
        }
    }
    template <typename T>
    void unorder_line(const double* __restrict v, T* __restrict x) const {
        for (int m = 0; 2 * m < n; ++m) x[2 * m] = T(2.0 * v[m]);
        for (int m = 0; 2 * m + 1 < n; ++m) x[2 * m + 1] = T(2.0 * v[n - 1 - m]);
    }

    // REDFT10 of `count` lines from `in` to `out` (in == out allowed).
    template <typename T>
    void forward(int count, const T* in, Layout from, T* out, Layout to) const {
        BlockScratch& s = block_scratch(std::size_t(n) * kBlock, std::size_t(half) * kBlock);
        double* const v = s.v->data;
        if (from.sample == 1 && to.sample == 1) {
            for (int c = 0; c < count; ++c) reorder_line(in + c * from.line, v + std::ptrdiff_t(c) * n);
            fftw_execute_dft_r2c(r2c[count], v, s.spectrum->data);
            for (int c = 0; c < count; ++c)
                twiddle_line(&s.spectrum->data[std::ptrdiff_t(c) * half][0], out + c * to.line);
            return;
        }
        each(count, (n + 1) / 2, from, [&](int c, int m) {
            v[std::ptrdiff_t(c) * n + m] = in[c * from.line + 2 * m * from.sample];
        });
        each(count, n / 2, from, [&](int c, int m) {
            v[std::ptrdiff_t(c) * n + n - 1 - m] = in[c * from.line + (2 * m + 1) * from.sample];
        });
        fftw_execute_dft_r2c(r2c[count], v, s.spectrum->data);
        const auto put = [&](int c, int k, double value) { out[c * to.line + k * to.sample] = T(value); };
        each(count, n / 2 + 1, to, [&](int c, int k) {
            const fftw_complex* spectrum = s.spectrum->data + std::ptrdiff_t(c) * half;
            if (k == 0) {
                put(c, 0, 2.0 * spectrum[0][0]);
                return;
            }
            // w_k V_k, w_k = cos - i sin
            const double co = cos_k[std::size_t(k)], sn = sin_k[std::size_t(k)];
            put(c, k, 2.0 * (co * spectrum[k][0] + sn * spectrum[k][1]));
            if (2 * k < n) put(c, n - k, -2.0 * (co * spectrum[k][1] - sn * spectrum[k][0]));
        });
    }

    // REDFT01 of `count` lines from `in` to `out` (in == out allowed), each input value
    // multiplied by scale's entry at the same place first when scale is given (scale laid out
    // as in).
    template <typename T>
    void inverse(int count, const T* in, Layout from, T* out, Layout to, const T* scale) const {
        BlockScratch& s = block_scratch(std::size_t(n) * kBlock, std::size_t(half) * kBlock);
        if (from.sample == 1 && to.sample == 1) {
            for (int c = 0; c < count; ++c)
                untwiddle_line(in + c * from.line, scale ? scale + c * from.line : nullptr,
                               &s.spectrum->data[std::ptrdiff_t(c) * half][0]);
            fftw_execute_dft_c2r(c2r[count], s.spectrum->data, s.v->data);
            for (int c = 0; c < count; ++c) unorder_line(s.v->data + std::ptrdiff_t(c) * n, out + c * to.line);
            return;
        }
        const auto get = [&](int c, int k) {
            const std::ptrdiff_t at = c * from.line + k * from.sample;
            return scale ? double(in[at]) * double(scale[at]) : double(in[at]);
        };
        each(count, n / 2 + 1, from, [&](int c, int k) {
            fftw_complex* spectrum = s.spectrum->data + std::ptrdiff_t(c) * half;
            if (k == 0) {
                spectrum[0][0] = 0.5 * get(c, 0), spectrum[0][1] = 0.0;
                return;
            }
            // conj(w_k) (X_k - i X_{N-k}) / 2; at k = N/2 both are X_{N/2}
            const double a = get(c, k), b = get(c, n - k);
            const double co = cos_k[std::size_t(k)], sn = sin_k[std::size_t(k)];
            spectrum[k][0] = 0.5 * (co * a + sn * b);
            spectrum[k][1] = 0.5 * (sn * a - co * b);
        });
        fftw_execute_dft_c2r(c2r[count], s.spectrum->data, s.v->data);
        const double* const v = s.v->data;
        each(count, (n + 1) / 2, to,
             [&](int c, int m) { out[c * to.line + 2 * m * to.sample] = T(2.0 * v[std::ptrdiff_t(c) * n + m]); });
        each(count, n / 2, to, [&](int c, int m) {
            out[c * to.line + (2 * m + 1) * to.sample] = T(2.0 * v[std::ptrdiff_t(c) * n + n - 1 - m]);
        });
    }
};

}  // namespace

struct GridDct::Impl {
    GridSize grid;
    std::unique_ptr<Lines> rows, columns;  // lengths nu and nv

    // Every row, then every column, kBlock lines at a time, each block read and written in
    // place (Lines::Layout).  transform(lines, count, in, from, out, to, scale) runs one
    // block; scale is given to the row pass only (the first, which reads rows contiguously).
    template <typename T, typename Transform>
    void separable(const T* in, T* out, const T* scale, Transform&& transform) const {
        const int nu = grid.nu, nv = grid.nv;
        tbb::parallel_for(0, (nv + kBlock - 1) / kBlock, [&](int block) {
            const std::ptrdiff_t start = std::ptrdiff_t(block) * kBlock * nu;
            const Lines::Layout row_block{1, nu};
            transform(*rows, std::min(kBlock, nv - block * kBlock), in + start, row_block, out + start, row_block,
                      scale ? scale + start : nullptr);
        });
        tbb::parallel_for(0, (nu + kBlock - 1) / kBlock, [&](int block) {
            const int first = block * kBlock;
            const Lines::Layout column_block{nu, 1};
            transform(*columns, std::min(kBlock, nu - first), out + first, column_block, out + first, column_block,
                      nullptr);
        });
    }
};

GridDct::GridDct(GridSize grid) : impl_(std::make_unique<Impl>()) {
    impl_->grid = grid;
    impl_->rows = std::make_unique<Lines>(grid.nu, grid.nv);
    impl_->columns = std::make_unique<Lines>(grid.nv, grid.nu);
}

GridDct::~GridDct() = default;

template <typename T>
void GridDct::forward(const T* in, T* out) const {
    impl_->separable(in, out, static_cast<const T*>(nullptr),
                     [](const Lines& lines, int count, const T* a, Lines::Layout from, T* b, Lines::Layout to,
                        const T*) { lines.forward(count, a, from, b, to); });
}

template <typename T>
void GridDct::inverse(const T* in, T* out, const T* scale) const {
    impl_->separable(in, out, scale,
                     [](const Lines& lines, int count, const T* a, Lines::Layout from, T* b, Lines::Layout to,
                        const T* by) { lines.inverse(count, a, from, b, to, by); });
}

template void GridDct::forward(const double*, double*) const;
template void GridDct::forward(const float*, float*) const;
template void GridDct::inverse(const double*, double*, const double*) const;
template void GridDct::inverse(const float*, float*, const float*) const;

}  // namespace foldcast::drape::detail
