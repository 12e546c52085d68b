#include "denoise.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

#include "foldcast/core/colour.hpp"

namespace foldcast::render {
namespace {

constexpr int kPasses = 5;  // steps 1-16
constexpr int kCrossPasses = 3;  // of them cross-filtered when there are two halves
static_assert(kCrossPasses < kPasses, "the halves are merged before the last passes");
constexpr float kSigmaLuminance = 4.0f;  // in standard deviations of the pixel's noise
constexpr float kSigmaDepth = 1.0f;      // in local depth steps per pixel of distance
constexpr float kMaxExponent = 20.0f;    // taps weighted below exp(-20) are skipped
// The normal weight is cos^(2^k): cos^128, and cos^4 in the last pass between two cloth
// pixels whose albedos agree within kSameAlbedo (the weave not resolved there: their
// shading normals differ by the bump averaged over a few samples and by the fold's curvature,
// which in the shadowed troughs turns faster than cos^128 allows from one pixel to the next).
constexpr int kNormalSquarings = 7;
constexpr int kRelaxedNormalSquarings = 2;
constexpr float kSameAlbedo = 0.005f;
// A pixel that is partly a thin wire or the rod's or the cloth's edge and partly backdrop
// (its share of samples on the garment and supports between 0 and 1) is not its neighbours'
// mixture: taps whose share differs by more than the dead zone (a 16-sample share's noise
// is about 0.1) are refused, exp(-kMixScale (|difference| - kMixDeadZone)).  Measured in
// docs/benchmarks.md ("The denoiser's mixture weight").
constexpr float kMixScale = 16.0f;
constexpr float kMixDeadZone = 0.2f;

// The guide the passes compare taps by, one array per quantity: a tap reads only what its
// test needs (depth and share first; the normal, cloth flag and albedo after).
struct Guide {
    std::vector<V3> n;                      // unit normal, or zero for the sky
    std::vector<std::uint8_t> sky;          // n is zero
    std::vector<float> depth;
    std::vector<float> inv_depth_tolerance;  // 1 / (kSigmaDepth * how much depth changes per pixel here)
    std::vector<std::uint8_t> covered;      // alpha > 0
    std::vector<std::uint8_t> cloth;        // most of its samples hit the garment
    std::vector<float> turning;             // share of its samples that hit the garment or its supports
    std::vector<V3> albedo;                 // first-hit albedo
    explicit Guide(std::size_t count)
        : n(count), sky(count), depth(count), inv_depth_tolerance(count), covered(count), cloth(count),
          turning(count), albedo(count) {}
};

constexpr float kKernel[3] = {0.25f, 0.5f, 0.25f};

// One buffer the passes filter: demodulated light, the variance of its luminance, and per
// pass its luminance and the colour weight's scale.
struct Buffer {
    std::vector<V3> light, next;
    std::vector<float> variance, next_variance, lum, sigma;
    explicit Buffer(std::size_t count)
        : light(count), next(count), variance(count), next_variance(count), lum(count), sigma(count) {}
    void swap() {
        std::swap(light, next);
        std::swap(variance, next_variance);
    }
};

class Filter {
public:
    Filter(int w, int h, const Guide& guide, int threads)
        : w_(w), h_(h), g_(guide), arena_(threads > 0 ? threads : tbb::task_arena::automatic) {}

    // The colour weight's scale from the variance blurred over 3x3 pixels (SVGF): a pixel
    // whose few samples happened to agree would otherwise refuse every neighbour and stay a
    // dark or bright speck.  Also the luminance the weight compares.
    void prepare(Buffer& b) {
        rows([&](int y) {
            for (int x = 0; x < w_; ++x) {
                float sum = 0.0f, sum_w = 0.0f;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int qx = x + dx, qy = y + dy;
                        if (qx < 0 || qx >= w_ || qy < 0 || qy >= h_) continue;
                        const std::size_t j = index(qx, qy);
                        if (!g_.covered[j]) continue;
                        const float k = kKernel[dx + 1] * kKernel[dy + 1];
                        sum += k * b.variance[j];
                        sum_w += k;
                    }
                const float v = sum_w > 0.0f ? sum / sum_w : 0.0f;
                const std::size_t i = index(x, y);
                b.sigma[i] = kSigmaLuminance * std::sqrt(std::max(0.0f, v)) + 1e-4f;
                b.lum[i] = luminance(b.light[i]);
            }
        });
    }

    // One a-trous pass at `stride`.  With two buffers each is averaged with colour weights
    // from the other (cross-filtering): whether a tap is taken does not depend on the noise
    // it carries, so a pixel's own noise cannot make it refuse its neighbours.  With one
    // buffer (b == nullptr) it is guided by itself.  `relaxed`: cloth pixels of one albedo
    // take the relaxed normal weight.
    void pass(int stride, Buffer& a, Buffer* b, bool relaxed = false) {
        if (b)
            rows([&](int y) { pass_row<true>(y, stride, a, *b, *b, relaxed); });
        else
            rows([&](int y) { pass_row<false>(y, stride, a, a, a, relaxed); });
        a.swap();
        if (b) b->swap();
    }

private:
    // Row y of a pass.  kCross: buffer a is guided by g (== b), b by a; else a by itself (g
    // and b are a, b unused).  Every tap's weight is the same expression as the one-loop
    // version this replaced, term for term, so the bytes do not depend on the split: the
    // template drops the second buffer's work where there is none, and the mixture term is
    // only added where it is not zero (its share difference beyond the dead zone).
    template <bool kCross>
    void pass_row(int y, int stride, Buffer& a, Buffer& b, const Buffer& g, bool relaxed) {
        float inv_distance[3][3];
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                inv_distance[dy + 1][dx + 1] =
                    1.0f / std::max(1.0f, static_cast<float>(stride) * std::sqrt(static_cast<float>(dx * dx + dy * dy)));
        const V3* const normal = g_.n.data();
        const std::uint8_t* const sky = g_.sky.data();
        const float* const depth = g_.depth.data();
        const std::uint8_t* const covered = g_.covered.data();
        const std::uint8_t* const cloth = g_.cloth.data();
        const float* const turning = g_.turning.data();
        const V3* const albedo = g_.albedo.data();
        const float* const g_lum = g.lum.data();
        const float* const a_lum = a.lum.data();
        const V3* const a_light = a.light.data();
        const float* const a_variance = a.variance.data();
        const V3* const b_light = b.light.data();
        const float* const b_variance = b.variance.data();
        for (int x = 0; x < w_; ++x) {
            const std::size_t i = index(x, y);
            if (!covered[i]) {
                a.next[i] = a_light[i];
                a.next_variance[i] = a_variance[i];
                if (kCross) b.next[i] = b_light[i], b.next_variance[i] = b_variance[i];
                continue;
            }
            const float inv_sigma_g = 1.0f / g.sigma[i], inv_sigma_a = 1.0f / a.sigma[i];
            const float inv_depth = g_.inv_depth_tolerance[i];
            const float depth_i = depth[i], turning_i = turning[i];
            const float lum_g = g_lum[i], lum_a = a_lum[i];
            const bool sky_i = sky[i] != 0;
            const V3& n_i = normal[i];
            const bool relaxed_i = relaxed && cloth[i];
            V3 sum_a = V3::Zero(), sum_b = V3::Zero();
            float wa_sum = 0.0f, va_sum = 0.0f, wb_sum = 0.0f, vb_sum = 0.0f;
            for (int dy = -1; dy <= 1; ++dy) {
                const int qy = y + dy * stride;
                if (qy < 0 || qy >= h_) continue;
                for (int dx = -1; dx <= 1; ++dx) {
                    const int qx = x + dx * stride;
                    if (qx < 0 || qx >= w_) continue;
                    const std::size_t j = index(qx, qy);
                    if (!covered[j]) continue;
                    float e_depth = std::abs(depth[j] - depth_i) * inv_depth * inv_distance[dy + 1][dx + 1];
                    const float mix = std::abs(turning[j] - turning_i);
                    if (mix > kMixDeadZone) e_depth += kMixScale * (mix - kMixDeadZone);
                    const float e_a = e_depth + std::abs(g_lum[j] - lum_g) * inv_sigma_g;
                    const float e_b = kCross ? e_depth + std::abs(a_lum[j] - lum_a) * inv_sigma_a : kMaxExponent + 1.0f;
                    // Beyond this the tap's weight (< 1e-9) is lost in the centre's (>= 1/4).
                    if (e_a > kMaxExponent && e_b > kMaxExponent) continue;
                    // The normal weight: 1 between two sky pixels, 0 between sky and surface.
                    float nw = 1.0f;
                    if (sky_i || sky[j]) {
                        if (sky_i != (sky[j] != 0)) continue;
                    } else {
                        const bool same_cloth =
                            relaxed_i && cloth[j] && (albedo[i] - albedo[j]).cwiseAbs().maxCoeff() < kSameAlbedo;
                        const int squarings = same_cloth ? kRelaxedNormalSquarings : kNormalSquarings;
                        nw = std::max(0.0f, n_i.dot(normal[j]));
                        for (int s = 0; s < squarings; ++s) nw *= nw;
                        if (nw == 0.0f) continue;
                    }
                    const float k = kKernel[dx + 1] * kKernel[dy + 1] * nw;
                    if (e_a <= kMaxExponent) {
                        const float wt = k * std::exp(-e_a);
                        sum_a += wt * a_light[j];
                        wa_sum += wt;
                        va_sum += wt * wt * a_variance[j];
                    }
                    if (kCross && e_b <= kMaxExponent) {
                        const float wt = k * std::exp(-e_b);
                        sum_b += wt * b_light[j];
                        wb_sum += wt;
                        vb_sum += wt * wt * b_variance[j];
                    }
                }
            }
            a.next[i] = sum_a / wa_sum;  // the centre's own weight is > 0
            a.next_variance[i] = va_sum / (wa_sum * wa_sum);
            if (kCross) {
                b.next[i] = sum_b / wb_sum;
                b.next_variance[i] = vb_sum / (wb_sum * wb_sum);
            }
        }
    }

    std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * w_ + x; }
    template <class F>
    void rows(F&& f) {
        arena_.execute([&] {
            tbb::parallel_for(tbb::blocked_range<int>(0, h_), [&](const tbb::blocked_range<int>& r) {
                for (int y = r.begin(); y != r.end(); ++y) f(y);
            });
        });
    }

    int w_, h_;
    const Guide& g_;
    tbb::task_arena arena_;
};

// The halves merged into `a` by their shares of the samples.
void merge(Buffer& a, const Buffer& b, const std::vector<float>& share) {
    for (std::size_t i = 0; i < share.size(); ++i) {
        const float s = share[i];
        a.light[i] = s * a.light[i] + (1.0f - s) * b.light[i];
        a.variance[i] = s * s * a.variance[i] + (1.0f - s) * (1.0f - s) * b.variance[i];
    }
}

}  // namespace

void denoise(Image& rgba, const PixelFeatures& features, int threads) {
    const int w = rgba.width, h = rgba.height;
    const std::size_t count = static_cast<std::size_t>(w) * h;
    const bool halves = features.half_a.size() == count;
    Guide guide(count);
    std::vector<V3> albedo(count);
    Buffer a(count);
    std::optional<Buffer> b;
    if (halves) b.emplace(count);
    for (std::size_t i = 0; i < count; ++i) {
        guide.n[i] = features.normal[i];
        guide.sky[i] = guide.n[i].squaredNorm() == 0.0f;
        guide.depth[i] = features.depth[i];
        guide.covered[i] = rgba.pixels[4 * i + 3] > 0.0f;
        guide.cloth[i] = features.cloth.size() == count && features.cloth[i] > 0.5f;
        guide.turning[i] = features.turning.size() == count ? features.turning[i] : 0.0f;
        guide.albedo[i] = features.albedo[i];
        const float* c = &rgba.pixels[4 * i];
        for (int k = 0; k < 3; ++k) albedo[i][k] = demodulation_divisor(features.albedo[i][k]);
        const float al = std::max(kMinDemodulationAlbedo, luminance(albedo[i]));
        const float variance = features.variance[i] / (al * al);
        if (!halves) {
            for (int k = 0; k < 3; ++k) a.light[i][k] = c[k] / albedo[i][k];
            a.variance[i] = variance;
        } else {
            // Each half's variance from the whole pixel's, by its share of the samples.
            const float s = features.half_share[i];
            for (int k = 0; k < 3; ++k) {
                a.light[i][k] = features.half_a[i][k] / albedo[i][k];
                b->light[i][k] = features.half_b[i][k] / albedo[i][k];
            }
            a.variance[i] = variance / s;
            b->variance[i] = variance / (1.0f - s);
        }
    }
    // The depth tolerance: how much depth changes per pixel here, per axis the smaller of the
    // two one-sided differences, so that a silhouette beside the pixel (a thin rod or wire
    // against the backdrop) does not widen it.
    const std::vector<float>& depth = guide.depth;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * w + x;
            const auto diff = [&](int qx, int qy) {
                if (qx < 0 || qx >= w || qy < 0 || qy >= h) return -1.0f;
                return std::abs(depth[static_cast<std::size_t>(qy) * w + qx] - depth[i]);
            };
            const auto axis = [](float m, float n) { return m < 0.0f ? std::max(0.0f, n) : n < 0.0f ? m : std::min(m, n); };
            const float step = std::max(axis(diff(x - 1, y), diff(x + 1, y)), axis(diff(x, y - 1), diff(x, y + 1)));
            const float depth_step = std::max(step, 1e-3f * depth[i]) + 1e-6f;
            guide.inv_depth_tolerance[i] = 1.0f / (kSigmaDepth * depth_step);
        }

    Filter filter(w, h, guide, threads);
    for (int pass = 0; pass < kPasses; ++pass) {
        if (b && pass == kCrossPasses) merge(a, *b, features.half_share), b.reset();
        filter.prepare(a);
        if (b) filter.prepare(*b);
        filter.pass(1 << pass, a, b ? &*b : nullptr);
    }
    if (halves) {
        // One more pass at step 1 guided by the merged light, whose noise is half either
        // half's: it takes out the pixel-scale noise the halves' weights, each from fewer
        // samples, left, with the relaxed normal weight on cloth of one albedo.
        filter.prepare(a);
        filter.pass(1, a, nullptr, true);
    }
    for (std::size_t i = 0; i < count; ++i) {
        if (!guide.covered[i]) continue;
        for (int k = 0; k < 3; ++k) rgba.pixels[4 * i + k] = a.light[i][k] * albedo[i][k];
    }
}

}  // namespace foldcast::render
