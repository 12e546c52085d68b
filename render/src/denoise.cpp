#include "denoise.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>

#include "foldcast/core/colour.hpp"

namespace foldcast::render {
namespace {

constexpr int kPasses = 5;
constexpr float kSigmaLuminance = 4.0f;  // in standard deviations of the pixel's noise
constexpr float kSigmaDepth = 1.0f;      // in local depth steps per pixel of distance
constexpr float kMaxExponent = 20.0f;    // taps weighted below exp(-20) are skipped

struct Pixel {
    V3 n = V3::Zero();  // unit normal, or zero for the sky
    float depth = 0.0f;
    float depth_step = 0.0f;  // how much depth changes per pixel here
    bool covered = true;      // alpha > 0
};

float normal_weight(const V3& a, const V3& b) {
    const bool sky_a = a.squaredNorm() == 0.0f, sky_b = b.squaredNorm() == 0.0f;
    if (sky_a || sky_b) return sky_a == sky_b ? 1.0f : 0.0f;
    float c = std::max(0.0f, a.dot(b));
    for (int i = 0; i < 7; ++i) c *= c;  // c^128
    return c;
}

}  // namespace

void denoise(Image& rgba, const PixelFeatures& features, int threads) {
    const int w = rgba.width, h = rgba.height;
    const std::size_t count = static_cast<std::size_t>(w) * h;
    std::vector<Pixel> px(count);
    std::vector<V3> albedo(count), light(count), next(count);
    std::vector<float> variance(count), next_variance(count);
    for (std::size_t i = 0; i < count; ++i) {
        Pixel& p = px[i];
        p.n = features.normal[i];
        p.depth = features.depth[i];
        p.covered = rgba.pixels[4 * i + 3] > 0.0f;
        const float* c = &rgba.pixels[4 * i];
        for (int k = 0; k < 3; ++k) {
            albedo[i][k] = demodulation_divisor(features.albedo[i][k]);
            light[i][k] = c[k] / albedo[i][k];
        }
        const float a = std::max(kMinDemodulationAlbedo, luminance(albedo[i]));
        variance[i] = features.variance[i] / (a * a);
    }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            Pixel& p = px[static_cast<std::size_t>(y) * w + x];
            float step = 0.0f;
            if (x + 1 < w) step = std::max(step, std::abs(px[static_cast<std::size_t>(y) * w + x + 1].depth - p.depth));
            if (x > 0) step = std::max(step, std::abs(px[static_cast<std::size_t>(y) * w + x - 1].depth - p.depth));
            if (y + 1 < h) step = std::max(step, std::abs(px[static_cast<std::size_t>(y + 1) * w + x].depth - p.depth));
            if (y > 0) step = std::max(step, std::abs(px[static_cast<std::size_t>(y - 1) * w + x].depth - p.depth));
            p.depth_step = std::max(step, 1e-3f * p.depth) + 1e-6f;
        }

    static constexpr float kKernel[3] = {0.25f, 0.5f, 0.25f};
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    std::vector<float> sigma(count), lum(count);
    for (int pass = 0; pass < kPasses; ++pass) {
        const int stride = 1 << pass;
        // The colour weight's scale from the variance blurred over 3x3 pixels (SVGF): a
        // pixel whose few samples happened to agree would otherwise refuse every neighbour
        // and stay a dark or bright speck.
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
                for (int y = rows.begin(); y != rows.end(); ++y)
                    for (int x = 0; x < w; ++x) {
                        float sum = 0.0f, sum_w = 0.0f;
                        for (int dy = -1; dy <= 1; ++dy)
                            for (int dx = -1; dx <= 1; ++dx) {
                                const int qx = x + dx, qy = y + dy;
                                if (qx < 0 || qx >= w || qy < 0 || qy >= h) continue;
                                const std::size_t j = static_cast<std::size_t>(qy) * w + qx;
                                if (!px[j].covered) continue;
                                const float k = kKernel[dx + 1] * kKernel[dy + 1];
                                sum += k * variance[j];
                                sum_w += k;
                            }
                        const float v = sum_w > 0.0f ? sum / sum_w : 0.0f;
                        sigma[static_cast<std::size_t>(y) * w + x] =
                            kSigmaLuminance * std::sqrt(std::max(0.0f, v)) + 1e-4f;
                    }
            });
        });
        for (std::size_t i = 0; i < count; ++i) lum[i] = luminance(light[i]);
        // 1 / the depth weight's distance factor max(1, |offset| pixels) for each tap.
        float inv_distance[3][3];
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                inv_distance[dy + 1][dx + 1] =
                    1.0f / std::max(1.0f, static_cast<float>(stride) * std::sqrt(static_cast<float>(dx * dx + dy * dy)));
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
                for (int y = rows.begin(); y != rows.end(); ++y)
                    for (int x = 0; x < w; ++x) {
                        const std::size_t i = static_cast<std::size_t>(y) * w + x;
                        const Pixel& p = px[i];
                        if (!p.covered) {
                            next[i] = light[i];
                            next_variance[i] = variance[i];
                            continue;
                        }
                        const float lum_p = lum[i];
                        const float inv_sigma = 1.0f / sigma[i], inv_depth = 1.0f / (kSigmaDepth * p.depth_step);
                        V3 sum = V3::Zero();
                        float sum_w = 0.0f, sum_v = 0.0f;
                        for (int dy = -1; dy <= 1; ++dy) {
                            const int qy = y + dy * stride;
                            if (qy < 0 || qy >= h) continue;
                            for (int dx = -1; dx <= 1; ++dx) {
                                const int qx = x + dx * stride;
                                if (qx < 0 || qx >= w) continue;
                                const std::size_t j = static_cast<std::size_t>(qy) * w + qx;
                                const Pixel& q = px[j];
                                if (!q.covered) continue;
                                const float e = std::abs(lum[j] - lum_p) * inv_sigma +
                                                std::abs(q.depth - p.depth) * inv_depth * inv_distance[dy + 1][dx + 1];
                                // Beyond this the tap's weight (< 1e-9) is lost in the centre's (>= 1/4).
                                if (e > kMaxExponent) continue;
                                const float nw = normal_weight(p.n, q.n);
                                if (nw == 0.0f) continue;
                                const float wt = kKernel[dx + 1] * kKernel[dy + 1] * nw * std::exp(-e);
                                sum += wt * light[j];
                                sum_w += wt;
                                sum_v += wt * wt * variance[j];
                            }
                        }
                        next[i] = sum / sum_w;  // the centre's own weight is > 0
                        next_variance[i] = sum_v / (sum_w * sum_w);
                    }
            });
        });
        std::swap(light, next);
        std::swap(variance, next_variance);
    }
    for (std::size_t i = 0; i < count; ++i) {
        if (!px[i].covered) continue;
        for (int k = 0; k < 3; ++k) rgba.pixels[4 * i + k] = light[i][k] * albedo[i][k];
    }
}

}  // namespace foldcast::render
