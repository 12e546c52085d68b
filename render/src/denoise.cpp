#include "denoise.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
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

struct Pixel {
    V3 n = V3::Zero();  // unit normal, or zero for the sky
    float depth = 0.0f;
    float depth_step = 0.0f;  // how much depth changes per pixel here
    bool covered = true;      // alpha > 0
    bool cloth = false;       // most of its samples hit the garment
    float turning = 0.0f;     // share of its samples that hit the garment or its supports
    V3 albedo = V3::Zero();   // first-hit albedo
};

float normal_weight(const V3& a, const V3& b, int squarings) {
    const bool sky_a = a.squaredNorm() == 0.0f, sky_b = b.squaredNorm() == 0.0f;
    if (sky_a || sky_b) return sky_a == sky_b ? 1.0f : 0.0f;
    float c = std::max(0.0f, a.dot(b));
    for (int i = 0; i < squarings; ++i) c *= c;
    return c;
}

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
    Filter(int w, int h, const std::vector<Pixel>& px, int threads)
        : w_(w), h_(h), px_(px), arena_(threads > 0 ? threads : tbb::task_arena::automatic) {}

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
                        if (!px_[j].covered) continue;
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
        float inv_distance[3][3];
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                inv_distance[dy + 1][dx + 1] =
                    1.0f / std::max(1.0f, static_cast<float>(stride) * std::sqrt(static_cast<float>(dx * dx + dy * dy)));
        // Buffer a is guided by g, b by a.
        const Buffer& g = b ? *b : a;
        rows([&](int y) {
            for (int x = 0; x < w_; ++x) {
                const std::size_t i = index(x, y);
                const Pixel& p = px_[i];
                if (!p.covered) {
                    a.next[i] = a.light[i];
                    a.next_variance[i] = a.variance[i];
                    if (b) b->next[i] = b->light[i], b->next_variance[i] = b->variance[i];
                    continue;
                }
                const float inv_sigma_g = 1.0f / g.sigma[i], inv_sigma_a = 1.0f / a.sigma[i];
                const float inv_depth = 1.0f / (kSigmaDepth * p.depth_step);
                const float lum_g = g.lum[i], lum_a = a.lum[i];
                V3 sum_a = V3::Zero(), sum_b = V3::Zero();
                float wa_sum = 0.0f, va_sum = 0.0f, wb_sum = 0.0f, vb_sum = 0.0f;
                for (int dy = -1; dy <= 1; ++dy) {
                    const int qy = y + dy * stride;
                    if (qy < 0 || qy >= h_) continue;
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int qx = x + dx * stride;
                        if (qx < 0 || qx >= w_) continue;
                        const std::size_t j = index(qx, qy);
                        const Pixel& q = px_[j];
                        if (!q.covered) continue;
                        const float e_depth = std::abs(q.depth - p.depth) * inv_depth * inv_distance[dy + 1][dx + 1] +
                                              kMixScale * std::max(0.0f, std::abs(q.turning - p.turning) - kMixDeadZone);
                        const float e_a = e_depth + std::abs(g.lum[j] - lum_g) * inv_sigma_g;
                        const float e_b = b ? e_depth + std::abs(a.lum[j] - lum_a) * inv_sigma_a : kMaxExponent + 1.0f;
                        // Beyond this the tap's weight (< 1e-9) is lost in the centre's (>= 1/4).
                        if (e_a > kMaxExponent && e_b > kMaxExponent) continue;
                        const bool same_cloth = relaxed && p.cloth && q.cloth &&
                                                (p.albedo - q.albedo).cwiseAbs().maxCoeff() < kSameAlbedo;
                        const float nw = normal_weight(p.n, q.n, same_cloth ? kRelaxedNormalSquarings : kNormalSquarings);
                        if (nw == 0.0f) continue;
                        const float k = kKernel[dx + 1] * kKernel[dy + 1] * nw;
                        if (e_a <= kMaxExponent) {
                            const float wt = k * std::exp(-e_a);
                            sum_a += wt * a.light[j];
                            wa_sum += wt;
                            va_sum += wt * wt * a.variance[j];
                        }
                        if (e_b <= kMaxExponent) {
                            const float wt = k * std::exp(-e_b);
                            sum_b += wt * b->light[j];
                            wb_sum += wt;
                            vb_sum += wt * wt * b->variance[j];
                        }
                    }
                }
                a.next[i] = sum_a / wa_sum;  // the centre's own weight is > 0
                a.next_variance[i] = va_sum / (wa_sum * wa_sum);
                if (b) {
                    b->next[i] = sum_b / wb_sum;
                    b->next_variance[i] = vb_sum / (wb_sum * wb_sum);
                }
            }
        });
        a.swap();
        if (b) b->swap();
    }

private:
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
    const std::vector<Pixel>& px_;
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
    std::vector<Pixel> px(count);
    std::vector<V3> albedo(count);
    Buffer a(count);
    std::optional<Buffer> b;
    if (halves) b.emplace(count);
    for (std::size_t i = 0; i < count; ++i) {
        Pixel& p = px[i];
        p.n = features.normal[i];
        p.depth = features.depth[i];
        p.covered = rgba.pixels[4 * i + 3] > 0.0f;
        p.cloth = features.cloth.size() == count && features.cloth[i] > 0.5f;
        p.turning = features.turning.size() == count ? features.turning[i] : 0.0f;
        p.albedo = features.albedo[i];
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
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            Pixel& p = px[static_cast<std::size_t>(y) * w + x];
            const auto diff = [&](int qx, int qy) {
                if (qx < 0 || qx >= w || qy < 0 || qy >= h) return -1.0f;
                return std::abs(px[static_cast<std::size_t>(qy) * w + qx].depth - p.depth);
            };
            const auto axis = [](float m, float n) { return m < 0.0f ? std::max(0.0f, n) : n < 0.0f ? m : std::min(m, n); };
            const float step = std::max(axis(diff(x - 1, y), diff(x + 1, y)), axis(diff(x, y - 1), diff(x, y + 1)));
            p.depth_step = std::max(step, 1e-3f * p.depth) + 1e-6f;
        }

    Filter filter(w, h, px, threads);
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
        if (!px[i].covered) continue;
        for (int k = 0; k < 3; ++k) rgba.pixels[4 * i + k] = a.light[i][k] * albedo[i][k];
    }
}

}  // namespace foldcast::render
