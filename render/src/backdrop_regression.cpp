#include "backdrop_regression.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Cholesky>
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
constexpr int kRadius = 10;
constexpr float kSigma = 5.0f;
constexpr int kTaps = 2 * kRadius + 1;
// How far the guide's residual may go beyond its noise before the fit gives way to the
// a-trous result (exp(-residual / (kMisfit noise))): 8 / 32 / 128 at 320x180, 26.1 / 25.9 /
// 26.2 (docs/benchmarks.md); a hard cut at 16 was worse than the blend.
constexpr float kMisfit = 32.0f;
constexpr float kRidge = 1e-6f;  // on the slopes, relative to the weights' sum

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

// g(d) (d / kRadius)^k for k = 0, 1, 2.
struct Kernels {
    float k[3][kTaps];
    Kernels() {
        for (int d = -kRadius; d <= kRadius; ++d) {
            const float u = float(d) / kRadius, g = std::exp(-float(d * d) / (2.0f * kSigma * kSigma));
            k[0][d + kRadius] = g, k[1][d + kRadius] = g * u, k[2][d + kRadius] = g * u * u;
        }
    }
};

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
        // The row's fields (zero off the backdrop), field by field.
        std::vector<float> field(std::size_t(kFields) * w);
        for (int y = r.begin(); y < r.end(); ++y) {
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                const float z = depth[i] * inv_mean_depth - 1.0f, g = guide[i];
                const V3& l = (*in.light)[i];
                const float values[kFields] = {1.0f,      z,         z * z,     l.x(), l.y(), l.z(),
                                               z * l.x(), z * l.y(), z * l.z(), g,     z * g, g * g};
                for (int f = 0; f < kFields; ++f) field[std::size_t(f) * w + x] = backdrop[i] ? values[f] : 0.0f;
            }
            for (int p = 0; p < kRowPasses; ++p) {
                const float* const src = field.data() + std::size_t(kRowPass[p].field) * w;
                float* const dst = row_plane(p) + std::size_t(y) * w;
                const float* const k = kernels.k[kRowPass[p].power];
                // Tap by tap, each pixel's sum in the kernel's order from +0.
                std::fill(dst, dst + w, 0.0f);
                for (int d = -kRadius; d <= kRadius; ++d) {
                    const int x0 = std::max(0, -d), x1 = std::min(w, w - d);
                    const float kd = k[d + kRadius];
                    for (int x = x0; x < x1; ++x) dst[x] += kd * src[x + d];
                }
            }
        }
    });
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& r) {
        std::vector<float> sums(kSums.size() * std::size_t(w));
        for (int y = r.begin(); y < r.end(); ++y) {
            std::fill(sums.begin(), sums.end(), 0.0f);
            for (std::size_t s = 0; s < kSums.size(); ++s) {
                float* const dst = sums.data() + s * w;
                const float* const k = kernels.k[kSums[s].column_power];
                const float* const src = row_plane(row_pass_of(kSums[s]));
                for (int d = std::max(-kRadius, -y); d <= std::min(kRadius, h - 1 - y); ++d) {
                    const float kd = k[d + kRadius];
                    const float* const row = src + std::size_t(y + d) * w;
                    for (int x = 0; x < w; ++x) dst[x] += kd * row[x];
                }
            }
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * w + x;
                if (!backdrop[i]) continue;
                const auto s = [&](int k) { return sums[std::size_t(k) * w + x]; };
                Eigen::Matrix4f m;
                m << s(0), s(1), s(2), s(3), s(1), s(4), s(5), s(6), s(2), s(5), s(7), s(8), s(3), s(6), s(8), s(9);
                for (int a = 1; a < 4; ++a) m(a, a) += kRidge * s(0);
                const Eigen::LLT<Eigen::Matrix4f> fit(m);
                if (fit.info() != Eigen::Success) continue;
                // Columns: X^T W y for red, green, blue and the guide.
                Eigen::Matrix4f rhs;
                for (int c = 0; c < 3; ++c)
                    for (int a = 0; a < 4; ++a) rhs(a, c) = s(kLightSums + 4 * c + a);
                for (int a = 0; a < 4; ++a) rhs(a, 3) = s(kGuideSums + a);
                const Eigen::Matrix4f beta = fit.solve(rhs);
                const float z = depth[i] * inv_mean_depth - 1.0f;
                V3 value;
                for (int c = 0; c < 3; ++c) value[c] = beta(0, c) + beta(3, c) * z;
                if (!value.allFinite() || value.minCoeff() < 0.0f) continue;
                // The guide's weighted residual variance under the same model,
                // (g^T W g - beta^T X^T W g) / sum W: large where the light is not linear here.
                const float residual = std::max(0.0f, s(kGuideSquare) - beta.col(3).dot(rhs.col(3))) / s(0);
                const float alpha = std::exp(-residual / (kMisfit * (*in.variance)[i] + 1e-20f));
                out[i] = alpha * value + (1.0f - alpha) * out[i];
            }
        }
    });
}

}  // namespace foldcast::render
