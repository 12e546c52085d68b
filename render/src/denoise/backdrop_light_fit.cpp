#include "backdrop_light_fit.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "foldcast/core/colour.hpp"

namespace foldcast::render {
namespace {

// The window and its Gaussian weights: at 320x180 radius 10 and 12 (sigma half of it) did
// alike and 8 worse; a box window was as good by the score but left faint streaks along the
// rows and columns (docs/benchmarks.md).
constexpr int kBackdropRadius = 10;
constexpr float kBackdropSigma = 5.0f;
// How far the guide's residual may go beyond its noise before the fit gives way to the
// a-trous result (exp(-residual / (kBackdropMisfit noise))): 8 / 32 / 128 at 320x180, 26.1 / 25.9 /
// 26.2 (docs/benchmarks.md); a hard cut was no better than the blend.
constexpr float kBackdropMisfit = 32.0f;
constexpr float kBackdropRidge = 1e-6f;  // on the slopes, relative to the weights' sum

// The regressors are 1, u, v (the offset in units of the radius) and z (the depth relative to
// the backdrop's mean).  The sums of their products and of the light's and the guide's with
// them are separable: a row pass convolves each per-pixel field with g(d) d^k, and a column
// pass the rows' results.
enum Field { kOne, kZ, kZZ, kR, kG, kB, kZR, kZG, kZB, kGuide, kZGuide, kGuideGuide, kFields };
struct Sum {
    Field field;
    int row_power, column_power;  // of u and v
};
// X^T W X (upper triangle over 1, u, v, z), X^T W y per channel, X^T W guide and the guide's
// weighted square.
constexpr std::array<Sum, 27> kSums = {{
    {kOne, 0, 0}, {kOne, 1, 0},   {kOne, 0, 1},   {kZ, 0, 0},     {kOne, 2, 0},    {kOne, 1, 1},        {kZ, 1, 0},
    {kOne, 0, 2}, {kZ, 0, 1},     {kZZ, 0, 0},    {kR, 0, 0},     {kR, 1, 0},      {kR, 0, 1},          {kZR, 0, 0},
    {kG, 0, 0},   {kG, 1, 0},     {kG, 0, 1},     {kZG, 0, 0},    {kB, 0, 0},      {kB, 1, 0},          {kB, 0, 1},
    {kZB, 0, 0},  {kGuide, 0, 0}, {kGuide, 1, 0}, {kGuide, 0, 1}, {kZGuide, 0, 0}, {kGuideGuide, 0, 0},
}};
constexpr int kLightSums = 10, kGuideSums = 22, kGuideSquare = 26;

// The row passes the column pass needs: (field, power of u), each once.
struct RowPass {
    Field field;
    int power;
};
constexpr int row_pass_count() {
    int n = 0;
    for (std::size_t a = 0; a < kSums.size(); ++a) {
        bool seen = false;
        for (std::size_t b = 0; b < a; ++b)
            seen = seen || (kSums[b].field == kSums[a].field && kSums[b].row_power == kSums[a].row_power);
        n += seen ? 0 : 1;
    }
    return n;
}
constexpr int kRowPasses = row_pass_count();
constexpr std::array<RowPass, kRowPasses> row_passes() {
    std::array<RowPass, kRowPasses> passes{};
    int n = 0;
    for (const Sum& s : kSums) {
        bool seen = false;
        for (int b = 0; b < n; ++b) seen = seen || (passes[b].field == s.field && passes[b].power == s.row_power);
        if (!seen) passes[n++] = RowPass{s.field, s.row_power};
    }
    return passes;
}
constexpr std::array<RowPass, kRowPasses> kRowPass = row_passes();
constexpr int row_pass_of(const Sum& s) {
    for (int p = 0; p < kRowPasses; ++p)
        if (kRowPass[p].field == s.field && kRowPass[p].power == s.row_power) return p;
    return -1;
}

// g(d) (d / kBackdropRadius)^k for k = 0, 1, 2 and d = 0 .. kBackdropRadius: even in d for k = 0 and 2, odd
// for k = 1, so each pass adds a tap pair's sum or difference times one weight.
struct Kernels {
    float k[3][kBackdropRadius + 1];
    Kernels() {
        for (int d = 0; d <= kBackdropRadius; ++d) {
            const float u = float(d) / kBackdropRadius,
                        g = std::exp(-float(d * d) / (2.0f * kBackdropSigma * kBackdropSigma));
            k[0][d] = g, k[1][d] = g * u, k[2][d] = g * u * u;
        }
    }
};

// sum over d of g(d) u^power f(x + d) for a row or column of taps: f(x + d) is at[d] (at[-d]
// the tap on the other side, zero beyond the image).
template <class Tap>
void convolve(const Kernels& kernels, int power, int n, float* dst, Tap&& at) {
    const float* const k = kernels.k[power];
    {
        const float* const centre = at(0);
        for (int x = 0; x < n; ++x) dst[x] = power == 0 ? k[0] * centre[x] : 0.0f;
    }
    for (int d = 1; d <= kBackdropRadius; ++d) {
        const float* const plus = at(d);
        const float* const minus = at(-d);
        const float kd = k[d];
        if (power == 1)
            for (int x = 0; x < n; ++x) dst[x] += kd * (plus[x] - minus[x]);
        else
            for (int x = 0; x < n; ++x) dst[x] += kd * (plus[x] + minus[x]);
    }
}

// The 4x4 normal matrix's Cholesky factor L (lower, row by row: l[0] = L00, l[1..2] = L10
// L11, l[3..5] = L20 L21 L22, l[6..9] = L30 .. L33); false where it is not positive definite.
bool cholesky4(const float (&m)[10], float (&l)[10]) {
    // m: the upper triangle row by row, (0,0) (0,1) (0,2) (0,3) (1,1) (1,2) (1,3) (2,2) (2,3) (3,3).
    const float a00 = m[0], a10 = m[1], a20 = m[2], a30 = m[3], a11 = m[4], a21 = m[5], a31 = m[6], a22 = m[7],
                a32 = m[8], a33 = m[9];
    const float d0 = a00;
    if (!(d0 > 0.0f)) return false;
    const float l00 = std::sqrt(d0), l10 = a10 / l00, l20 = a20 / l00, l30 = a30 / l00;
    const float d1 = a11 - l10 * l10;
    if (!(d1 > 0.0f)) return false;
    const float l11 = std::sqrt(d1), l21 = (a21 - l20 * l10) / l11, l31 = (a31 - l30 * l10) / l11;
    const float d2 = a22 - l20 * l20 - l21 * l21;
    if (!(d2 > 0.0f)) return false;
    const float l22 = std::sqrt(d2), l32 = (a32 - l30 * l20 - l31 * l21) / l22;
    const float d3 = a33 - l30 * l30 - l31 * l31 - l32 * l32;
    if (!(d3 > 0.0f)) return false;
    const float l33 = std::sqrt(d3);
    const float out[10] = {l00, l10, l11, l20, l21, l22, l30, l31, l32, l33};
    for (int i = 0; i < 10; ++i) l[i] = out[i];
    return true;
}

// L^-1 b by forward substitution.
void forward4(const float (&l)[10], const float (&b)[4], float (&y)[4]) {
    y[0] = b[0] / l[0];
    y[1] = (b[1] - l[1] * y[0]) / l[2];
    y[2] = (b[2] - l[3] * y[0] - l[4] * y[1]) / l[5];
    y[3] = (b[3] - l[6] * y[0] - l[7] * y[1] - l[8] * y[2]) / l[9];
}

}  // namespace

void regress_backdrop(const BackdropRegressionInput& in, std::vector<V3>& out) {
    const int w = in.width, h = in.height;
    const std::size_t count = std::size_t(w) * h;
    const std::vector<std::int32_t>& backdrop = *in.backdrop;
    const std::vector<float>& depth = *in.depth;
    const std::vector<float>& guide = *in.guide;
    double depth_sum = 0.0;
    std::size_t backdrop_count = 0;
    for (std::size_t i = 0; i < count; ++i)
        if (backdrop[i]) depth_sum += depth[i], ++backdrop_count;
    if (backdrop_count == 0) return;
    const float inv_mean_depth = float(double(backdrop_count) / depth_sum);
    // The row passes' results, plane by plane, so that the column pass runs along contiguous
    // floats.  Every float is written before it is read.
    static const Kernels kernels;
    const std::unique_ptr<float[]> rows(new float[std::size_t(kRowPasses) * count]);
    const auto row_plane = [&](int p) { return rows.get() + std::size_t(p) * count; };
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& r) {
        // The row's fields (zero off the backdrop and for kBackdropRadius pixels beyond each end),
        // field by field.
        const std::size_t stride = std::size_t(w) + 2 * kBackdropRadius;
        std::vector<float> field(std::size_t(kFields) * stride, 0.0f);
        for (int y = r.begin(); y < r.end(); ++y) {
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                const float z = depth[i] * inv_mean_depth - 1.0f, g = guide[i];
                const V3& l = (*in.light)[i];
                const float values[kFields] = {1.0f,      z,         z * z,     l.x(), l.y(), l.z(),
                                               z * l.x(), z * l.y(), z * l.z(), g,     z * g, g * g};
                for (int f = 0; f < kFields; ++f)
                    field[std::size_t(f) * stride + kBackdropRadius + x] = backdrop[i] ? values[f] : 0.0f;
            }
            for (int p = 0; p < kRowPasses; ++p) {
                const float* const src = field.data() + std::size_t(kRowPass[p].field) * stride + kBackdropRadius;
                convolve(kernels, kRowPass[p].power, w, row_plane(p) + std::size_t(y) * w,
                         [&](int d) { return src + d; });
            }
        }
    });
    const std::vector<float> zeros(w, 0.0f);  // the rows beyond the image
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> sums(kSums.size() * std::size_t(w));
        for (int y = r.begin(); y < r.end(); ++y) {
            for (std::size_t s = 0; s < kSums.size(); ++s) {
                const float* const src = row_plane(row_pass_of(kSums[s]));
                convolve(kernels, kSums[s].column_power, w, sums.data() + s * w,
                         [&](int d) { return y + d >= 0 && y + d < h ? src + std::size_t(y + d) * w : zeros.data(); });
            }
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                if (!backdrop[i]) continue;
                const auto s = [&](int k) { return sums[std::size_t(k) * w + x]; };
                const float ridge = kBackdropRidge * s(0);
                const float m[10] = {s(0), s(1), s(2),         s(3), s(4) + ridge,
                                     s(5), s(6), s(7) + ridge, s(8), s(9) + ridge};
                float l[10];
                if (!cholesky4(m, l)) continue;
                // With y = L^-1 X^T W y and q = L^-1 (1, 0, 0, z), the fit's value at the pixel
                // (beta_0 + z beta_z = (1, 0, 0, z) M^-1 X^T W y) is q . y, and the guide's
                // beta^T X^T W g is |L^-1 X^T W g|^2: forward substitution alone.
                const float z = depth[i] * inv_mean_depth - 1.0f;
                float q[4];
                forward4(l, {1.0f, 0.0f, 0.0f, z}, q);
                V3 value;
                for (int c = 0; c < 3; ++c) {
                    const int k = kLightSums + 4 * c;
                    float yc[4];
                    forward4(l, {s(k), s(k + 1), s(k + 2), s(k + 3)}, yc);
                    value[c] = q[0] * yc[0] + q[1] * yc[1] + q[2] * yc[2] + q[3] * yc[3];
                }
                if (!value.allFinite() || value.minCoeff() < 0.0f) continue;
                // The guide's weighted residual variance under the same model,
                // (g^T W g - beta^T X^T W g) / sum W: large where the light is not linear here.
                float yg[4];
                forward4(l, {s(kGuideSums), s(kGuideSums + 1), s(kGuideSums + 2), s(kGuideSums + 3)}, yg);
                const float explained = yg[0] * yg[0] + yg[1] * yg[1] + yg[2] * yg[2] + yg[3] * yg[3];
                const float residual = std::max(0.0f, s(kGuideSquare) - explained) / s(0);
                const float alpha = std::exp(-residual / (kBackdropMisfit * (*in.variance)[i] + 1e-20f));
                out[i] = alpha * value + (1.0f - alpha) * out[i];
            }
        }
    });
}

}  // namespace foldcast::render
