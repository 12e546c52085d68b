// Makhoul's DCT (dct.hpp).  For a line x_0..x_{N-1} let v_n = x_{2n} and v_{N-1-n} = x_{2n+1}
// (even samples forwards, odd ones backwards) and V = FFT(v).  Then with w_k = exp(-i pi k / 2N)
//   REDFT10:  X_k = 2 Re(w_k V_k),  X_{N-k} = -2 Im(w_k V_k)          (0 < k < N - k)
// and, V being Hermitian, the real FFT's half spectrum is all that is needed.  The inverse
// runs the same steps backwards: V_k = conj(w_k) (X_k - i X_{N-k}) / 2, v = the inverse real
// FFT of V, and REDFT01(X) = 2 v put back in the original order.
#include "dct.hpp"

#include "foldcast/core/math.hpp"

#include <fftw3.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <new>
#include <stdexcept>
#include <vector>

namespace foldcast::drape::detail {
// Named, not anonymous: GridDct::Impl holds its types (an anonymous namespace's in a
// class of the detail namespace would be a linkage error once the unity build joins files).
namespace fftw_lines {

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
            const double angle = kPi * k / (2.0 * n);
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

    // One contiguous line each: loops the compiler vectorises.  T: the grid's values, double
    // or float (the FFTs run in double on the block's scratch either way).
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

    // REDFT10 of `count` contiguous lines (line c at in + c n) into out laid out alike; out
    // may be in, or the block's scratch v (read before the twiddles write it).
    template <typename In, typename Out>
    void forward(int count, const In* in, Out* out, BlockScratch& s) const {
        double* const v = s.v->data;
        for (int c = 0; c < count; ++c) reorder_line(in + std::ptrdiff_t(c) * n, v + std::ptrdiff_t(c) * n);
        fftw_execute_dft_r2c(r2c[count], v, s.spectrum->data);
        for (int c = 0; c < count; ++c)
            twiddle_line(&s.spectrum->data[std::ptrdiff_t(c) * half][0], out + std::ptrdiff_t(c) * n);
    }

    // REDFT01 of `count` contiguous lines from in to out laid out alike (out may be in; in
    // may be the block's scratch v), each input value multiplied by scale's entry at the same
    // place first when scale is given.
    template <typename In, typename Out>
    void inverse(int count, const In* in, Out* out, const In* scale, BlockScratch& s) const {
        for (int c = 0; c < count; ++c)
            untwiddle_line(in + std::ptrdiff_t(c) * n, scale ? scale + std::ptrdiff_t(c) * n : nullptr,
                           &s.spectrum->data[std::ptrdiff_t(c) * half][0]);
        fftw_execute_dft_c2r(c2r[count], s.spectrum->data, s.v->data);
        for (int c = 0; c < count; ++c) unorder_line(s.v->data + std::ptrdiff_t(c) * n, out + std::ptrdiff_t(c) * n);
    }
};

}  // namespace fftw_lines

struct GridDct::Impl {
    GridSize grid;
    std::unique_ptr<fftw_lines::Lines> rows, columns;  // lengths nu and nv

    // This thread's block scratch, large enough for either length.
    fftw_lines::BlockScratch& scratch() const {
        const std::size_t most = std::size_t(std::max(grid.nu, grid.nv)) + 2;
        return fftw_lines::block_scratch(most * fftw_lines::kBlock, (most / 2 + 1) * fftw_lines::kBlock);
    }
    static int blocks(int lines) { return (lines + fftw_lines::kBlock - 1) / fftw_lines::kBlock; }

    // Every line is transformed where it lies contiguously: the rows' results go out
    // transposed (a block of rows is a few neighbours in every row of the output), so that
    // the columns are contiguous lines for the second pass, and the inverse gathers them back
    // the same way.  Strided access is then one plain copy per transform, not the
    // reordering and twiddles of every column.
    template <typename T>
    void forward(const T* in, T* out) const {
        const int nu = grid.nu, nv = grid.nv;
        tbb::parallel_for(0, blocks(nv), [&](int block) {
            const int first = block * fftw_lines::kBlock, count = std::min(fftw_lines::kBlock, nv - first);
            fftw_lines::BlockScratch& s = scratch();
            double* const v = s.v->data;
            rows->forward(count, in + std::ptrdiff_t(first) * nu, v, s);
            for (int p = 0; p < nu; ++p) {
                T* const to = out + std::ptrdiff_t(p) * nv + first;
                for (int c = 0; c < count; ++c) to[c] = T(v[std::ptrdiff_t(c) * nu + p]);
            }
        });
        tbb::parallel_for(0, blocks(nu), [&](int block) {
            const int first = block * fftw_lines::kBlock;
            T* const lines = out + std::ptrdiff_t(first) * nv;
            columns->forward(std::min(fftw_lines::kBlock, nu - first), lines, lines, scratch());
        });
    }

    template <typename T>
    void inverse(T* in, T* out, const T* scale) const {
        const int nu = grid.nu, nv = grid.nv;
        tbb::parallel_for(0, blocks(nu), [&](int block) {
            const int first = block * fftw_lines::kBlock;
            T* const lines = in + std::ptrdiff_t(first) * nv;
            columns->inverse(std::min(fftw_lines::kBlock, nu - first), lines, lines,
                             scale ? scale + std::ptrdiff_t(first) * nv : nullptr, scratch());
        });
        tbb::parallel_for(0, blocks(nv), [&](int block) {
            const int first = block * fftw_lines::kBlock, count = std::min(fftw_lines::kBlock, nv - first);
            fftw_lines::BlockScratch& s = scratch();
            double* const v = s.v->data;
            for (int p = 0; p < nu; ++p) {
                const T* const from = in + std::ptrdiff_t(p) * nv + first;
                for (int c = 0; c < count; ++c) v[std::ptrdiff_t(c) * nu + p] = double(from[c]);
            }
            rows->inverse(count, v, out + std::ptrdiff_t(first) * nu, static_cast<const double*>(nullptr), s);
        });
    }
};

GridDct::GridDct(GridSize grid) : impl_(std::make_unique<Impl>()) {
    impl_->grid = grid;
    impl_->rows = std::make_unique<fftw_lines::Lines>(grid.nu, grid.nv);
    impl_->columns = std::make_unique<fftw_lines::Lines>(grid.nv, grid.nu);
}

GridDct::~GridDct() = default;

template <typename T>
void GridDct::forward(const T* in, T* out) const {
    impl_->forward(in, out);
}

template <typename T>
void GridDct::inverse(T* in, T* out, const T* scale) const {
    impl_->inverse(in, out, scale);
}

template void GridDct::forward(const double*, double*) const;
template void GridDct::forward(const float*, float*) const;
template void GridDct::inverse(double*, double*, const double*) const;
template void GridDct::inverse(float*, float*, const float*) const;

}  // namespace foldcast::drape::detail
