#pragma once
// The 2-D DCT-II and DCT-III of an nu x nv grid (row-major, rows of nu), with FFTW's
// REDFT10 / REDFT01 scaling, computed by Makhoul's algorithm: each 1-D DCT of length N is one
// real FFT of length N of the reordered input (even samples forwards, odd ones backwards) and
// a twiddle.  Why not FFTW's own r2r plans: with FFTW_ESTIMATE (the only planner mode that
// gives the same plan, hence the same bytes, on every machine) FFTW builds REDFT10 from scalar
// codelets, about 4x slower than its SIMD real FFTs of the same size.
//
// Each 1-D transform (a row, then a column) is independent of the others and runs on its own
// aligned scratch, so the rows and columns are spread over TBB and the result does not depend
// on the thread count.  The spectrum is kept transposed, so that both passes of each transform
// read and write contiguous lines.
#include <memory>

#include "foldcast/drape/drape.hpp"

namespace foldcast::drape::detail {

class GridDct {
public:
    explicit GridDct(GridSize grid);
    ~GridDct();
    GridDct(const GridDct&) = delete;
    GridDct& operator=(const GridDct&) = delete;

    // out = REDFT10 in both directions (X_k = 2 sum_n x_n cos(pi k (2n + 1) / 2N) per
    // dimension), laid out transposed: mode (p, q) (p along a row, q along a column) at
    // out[p * nv + q].  in: nu * nv values, row-major; out: nu * nv values, not in's memory.
    // T: double or float (the arithmetic is double either way; float halves the memory the
    // passes move).
    template <typename T>
    void forward(const T* in, T* out) const;
    // out = REDFT01 in both directions (y_n = X_0 + 2 sum_k>0 X_k cos(pi k (2n + 1) / 2N)),
    // the inverse of forward up to the factor 4 nu nv, of in (laid out as forward's out)
    // multiplied entry by entry by scale (laid out alike) when scale is given.  in is
    // overwritten (the first pass works in place); out: row-major, not in's memory.
    template <typename T>
    void inverse(T* in, T* out, const T* scale = nullptr) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace foldcast::drape::detail
