// The turntable's temporal filter (foldcast/render/temporal_filter.hpp): reprojection by the
// known turn, rejection by first-hit features, a centred average of the traced illumination,
// then the spatial denoiser over the average.
#include "foldcast/render/temporal_filter.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "camera_model.hpp"
#include "denoise/denoise.hpp"
#include "foldcast/core/colour.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast::render {
namespace {

// A pixel is reprojected as cloth (turned) or as backdrop (kept) only when nearly all its
// samples agree; silhouettes and the rod, clips and wires (thin, metal: a reprojected
// highlight lands beside itself) keep their own value.
constexpr float kPureShare = 0.9f;
constexpr float kHistoryDepthTolerance = 1.5f;  // in the pixel's depth steps (the depth change to a neighbour)
constexpr float kMinNormalCos = 0.9f;    // ~25 degrees: the weave's bump varies within a pixel
constexpr float kAlbedoTolerance = 0.08f;  // absolute, per channel
// Luminance may differ from frame f's by this many standard deviations of the two pixels'
// noise plus this share of their mean (the shading's change over two frames' turn): a
// highlight sliding over the cloth or a shadow edge passing a point does not fit in it.
constexpr float kNoiseSigmas = 3.0f;
constexpr float kShadingTolerance = 0.1f;
constexpr float kMinTapWeight = 0.5f;  // of the bilinear footprint that must agree

Vec3f demodulate(const float* rgba, const Vec3f& albedo) {
    Vec3f l;
    for (int k = 0; k < 3; ++k) l[k] = rgba[k] / demodulation_divisor(albedo[k]);
    return l;
}

// p and directions turned about the vertical axis through `centre` (StudioSetup's sense).
Vec3f turn_vector(const Vec3f& d, float c, float s) { return Vec3f(c * d.x() + s * d.z(), d.y(), -s * d.x() + c * d.z()); }
Vec3f turn_point(const Vec3f& p, const Vec3f& centre, float c, float s) { return centre + turn_vector(p - centre, c, s); }

// What frame f saw at a pixel, moved into another frame.
struct Expected {
    Vec3f point, normal, albedo;
    float depth_step;
    bool cloth;
    float luminance;  // of the pixel's colour (not divided by albedo)
    float variance;   // of that luminance, over the pixel's 3x3 neighbourhood: one pixel's
                      // estimate from a few samples can be near zero
};

struct HistoryTap {
    Vec3f light;     // colour / albedo
    float variance;  // of the luminance
    Vec3f light_a = Vec3f::Zero(), light_b = Vec3f::Zero();  // the same of the two half buffers, when kept
};

// The illumination another frame shows at the surface point `e`, or none where too little
// of the bilinear footprint agrees with it.
std::optional<HistoryTap> fetch(const TemporalFrame& g, const CameraModel& cam, const Vec3f& camera_position,
                                const Expected& e) {
    const int w = g.beauty.width, h = g.beauty.height;
    float px = 0.0f, py = 0.0f;
    if (!cam.project(e.point, &px, &py)) return std::nullopt;
    const float fx = px - 0.5f, fy = py - 0.5f;
    if (!(fx > -1.0f && fy > -1.0f && fx < static_cast<float>(w) && fy < static_cast<float>(h))) return std::nullopt;
    const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
    const float tx = fx - static_cast<float>(x0), ty = fy - static_cast<float>(y0);
    const float distance = (e.point - camera_position).norm();
    const PixelFeatures& f = g.features;
    Vec3f sum = Vec3f::Zero(), sum_a = Vec3f::Zero(), sum_b = Vec3f::Zero();
    const bool halves = !f.half_a.empty();
    float sum_w = 0.0f, sum_v = 0.0f, sum_l = 0.0f;
    for (int j = 0; j < 4; ++j) {
        const int x = x0 + (j & 1), y = y0 + (j >> 1);
        if (x < 0 || y < 0 || x >= w || y >= h) continue;
        const float b = ((j & 1) ? tx : 1.0f - tx) * ((j >> 1) ? ty : 1.0f - ty);
        if (b <= 0.0f) continue;
        const std::size_t q = static_cast<std::size_t>(y) * w + x;
        if (e.cloth ? f.cloth[q] < kPureShare : f.turning[q] > 1.0f - kPureShare) continue;
        if (f.depth[q] <= 0.0f || std::abs(f.depth[q] - distance) > kHistoryDepthTolerance * e.depth_step) continue;
        if (f.normal[q].dot(e.normal) < kMinNormalCos) continue;
        if ((f.albedo[q] - e.albedo).cwiseAbs().maxCoeff() > kAlbedoTolerance) continue;
        const float* c = g.beauty.at(x, y);
        sum += b * demodulate(c, f.albedo[q]);
        if (halves) {
            sum_a += b * demodulate(f.half_a[q].data(), f.albedo[q]);
            sum_b += b * demodulate(f.half_b[q].data(), f.albedo[q]);
        }
        sum_l += b * luminance(Vec3f(c[0], c[1], c[2]));
        sum_v += b * f.variance[q];
        sum_w += b;
    }
    if (sum_w < kMinTapWeight) return std::nullopt;
    const float l = sum_l / sum_w, variance = sum_v / sum_w;
    const float allowed =
        kNoiseSigmas * std::sqrt(std::max(variance, e.variance) + e.variance) + kShadingTolerance * 0.5f * (l + e.luminance);
    if (std::abs(l - e.luminance) > allowed + 1e-4f) return std::nullopt;
    return HistoryTap{sum / sum_w, variance, sum_a / sum_w, sum_b / sum_w};
}

// How much depth changes per pixel at (x, y), as the denoiser's depth weight measures it.
float depth_step(const std::vector<float>& depth, int w, int h, int x, int y) {
    const float d0 = depth[static_cast<std::size_t>(y) * w + x];
    float step = 0.0f;
    for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int qx = x + dx, qy = y + dy;
        if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
        const float d = depth[static_cast<std::size_t>(qy) * w + qx];
        if (d > 0.0f) step = std::max(step, std::abs(d - d0));
    }
    return std::max(step, 2e-3f * d0);
}

}  // namespace

Image temporal_filter(const std::vector<const TemporalFrame*>& window, const Camera& camera, const Vec3f& turn_centre,
                      bool denoise_after, int threads) {
    const int radius = static_cast<int>(window.size() / 2);
    const TemporalFrame& c = *window[static_cast<std::size_t>(radius)];
    const PixelFeatures& f = c.features;
    const int w = c.beauty.width, h = c.beauty.height;
    Image out = c.beauty;
    std::vector<float> variance = f.variance;  // of the averaged pixels' luminance, for the denoiser
    // The half buffers averaged alike (each frame's first halves together, and its second
    // halves), when the frames kept them: the denoiser cross-filters the two averages.
    const bool halves =
        f.half_a.size() == f.variance.size() && std::all_of(window.begin(), window.end(), [&](const TemporalFrame* g) {
            return g->features.half_a.size() == f.half_a.size();
        });
    std::vector<Vec3f> half_a = halves ? f.half_a : std::vector<Vec3f>{},
                       half_b = halves ? f.half_b : std::vector<Vec3f>{};
    const CameraModel cam(camera, w, h);
    std::vector<float> local_variance(f.variance.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float sum = 0.0f;
            int n = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int qx = x + dx, qy = y + dy;
                    if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
                    sum += f.variance[static_cast<std::size_t>(qy) * w + qx];
                    ++n;
                }
            local_variance[static_cast<std::size_t>(y) * w + x] = sum / static_cast<float>(n);
        }
    // Each other frame's turn relative to this one, as cosine and sine.
    std::vector<float> cosine(window.size()), sine(window.size());
    for (std::size_t k = 0; k < window.size(); ++k) {
        const double a = (window[k]->turn_deg - c.turn_deg) * kPi / 180.0;
        cosine[k] = static_cast<float>(std::cos(a));
        sine[k] = static_cast<float>(std::sin(a));
    }
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
            for (int y = rows.begin(); y != rows.end(); ++y)
                for (int x = 0; x < w; ++x) {
                    const std::size_t i = static_cast<std::size_t>(y) * w + x;
                    const bool cloth = f.cloth[i] >= kPureShare, still = f.turning[i] <= 1.0f - kPureShare;
                    if (f.depth[i] <= 0.0f || (!cloth && !still) || c.beauty.at(x, y)[3] <= 0.0f) continue;
                    Vec3f origin, direction;
                    cam.ray(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f, 0.0f, 0.0f, &origin,
                            &direction);
                    const Vec3f point = origin + f.depth[i] * direction;
                    const float* own_colour = c.beauty.at(x, y);
                    const float step = depth_step(f.depth, w, h, x, y);
                    const float own_luminance = luminance(Vec3f(own_colour[0], own_colour[1], own_colour[2]));
                    Vec3f sum = demodulate(own_colour, f.albedo[i]);
                    Vec3f sum_a = halves ? demodulate(f.half_a[i].data(), f.albedo[i]) : Vec3f::Zero();
                    Vec3f sum_b = halves ? demodulate(f.half_b[i].data(), f.albedo[i]) : Vec3f::Zero();
                    float count = 1.0f, variance_sum = f.variance[i];
                    for (int k = 1; k <= radius; ++k) {
                        std::optional<HistoryTap> side[2];
                        for (int s = 0; s < 2; ++s) {
                            const std::size_t g = static_cast<std::size_t>(radius + (s == 0 ? -k : k));
                            const Expected e{cloth ? turn_point(point, turn_centre, cosine[g], sine[g]) : point,
                                             cloth ? turn_vector(f.normal[i], cosine[g], sine[g]) : f.normal[i],
                                             f.albedo[i],
                                             step,
                                             cloth,
                                             own_luminance,
                                             local_variance[i]};
                            side[s] = fetch(*window[g], cam, origin, e);
                            if (!side[s]) break;
                        }
                        // Both sides or neither: one side alone would pull the value towards
                        // where the shading is going (or coming from).
                        if (!side[0] || !side[1]) continue;
                        sum += side[0]->light + side[1]->light;
                        sum_a += side[0]->light_a + side[1]->light_a;
                        sum_b += side[0]->light_b + side[1]->light_b;
                        variance_sum += side[0]->variance + side[1]->variance;
                        count += 2.0f;
                    }
                    if (count == 1.0f) continue;
                    const Vec3f light = sum / count;
                    float* px = out.at(x, y);
                    for (int k = 0; k < 3; ++k) px[k] = light[k] * demodulation_divisor(f.albedo[i][k]);
                    if (halves)
                        for (int k = 0; k < 3; ++k) {
                            half_a[i][k] = sum_a[k] / count * demodulation_divisor(f.albedo[i][k]);
                            half_b[i][k] = sum_b[k] / count * demodulation_divisor(f.albedo[i][k]);
                        }
                    variance[i] = variance_sum / (count * count);
                }
        });
    });
    if (denoise_after) {
        PixelFeatures averaged = f;  // the denoiser reads the average's variance
        averaged.variance = std::move(variance);
        averaged.half_a = std::move(half_a);
        averaged.half_b = std::move(half_b);
        denoise(out, averaged, threads, DenoiseBudget::frame);
    }
    return out;
}

}  // namespace foldcast::render
