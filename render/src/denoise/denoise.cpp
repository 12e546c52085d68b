#include "denoise.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>

#include "backdrop_light_fit.hpp"
#include "cloth_light_fit.hpp"
#include "pixel_sums.hpp"
#include "fit_selection.hpp"
#include "support_light_fit.hpp"
#include "tap_weights.hpp"
#include "foldcast/core/colour.hpp"
#include "foldcast/core/fast_math.hpp"
#include "mixed_pixels.hpp"

namespace foldcast::render {
namespace {

constexpr int kPasses = 5;       // steps 1-16
constexpr int kCrossPasses = 3;  // of them cross-filtered when there are two halves
static_assert(kCrossPasses < kPasses, "the halves are merged before the last passes");
constexpr float kSigmaLuminance = 4.0f;  // in standard deviations of the pixel's noise
constexpr float kSigmaDepth = 1.0f;      // in local depth steps per pixel of distance
// The normal weight is cos^(2^k): cos^128, and cos^4 in the last pass between two cloth
// pixels whose albedos agree within kSameAlbedo (the weave not resolved there: their
// shading normals differ by the bump averaged over a few samples and by the fold's curvature,
// which in the shadowed troughs turns faster than cos^128 allows from one pixel to the next).
constexpr int kNormalSquarings = 7;
constexpr int kRelaxedNormalSquarings = 2;
constexpr float kSameAlbedo = 0.005f;
constexpr float kRegressionNoisyShare = 0.25f;  // of the light the cloth's regression fits (below)

// The guide the passes compare taps by, one array per quantity, so that the pass loads the
// same quantity for four neighbouring pixels at once.
struct Guide {
    std::vector<float> nx, ny, nz;  // unit normal, or zero for the sky
    // Flags as 0 / 1 of the floats' width, so that the SSE2 loop tests four at a time.
    std::vector<std::int32_t> sky;  // the normal is zero
    std::vector<float> depth;
    std::vector<float> inv_depth_tolerance;  // 1 / (kSigmaDepth * how much depth changes per pixel here)
    std::vector<std::int32_t> covered;       // alpha > 0
    std::vector<std::int32_t> cloth;         // most of its samples hit the garment
    std::vector<float> turning;              // share of its samples that hit the garment or its supports
    std::vector<float> ax, ay, az;           // first-hit albedo
    explicit Guide(std::size_t count)
        : nx(count),
          ny(count),
          nz(count),
          sky(count),
          depth(count),
          inv_depth_tolerance(count),
          covered(count),
          cloth(count),
          turning(count),
          ax(count),
          ay(count),
          az(count) {}
};

constexpr float kKernel[3] = {0.25f, 0.5f, 0.25f};

// One buffer the passes filter: demodulated light, the variance of its luminance, and per
// pass its luminance and the reciprocal of the colour weight's scale.
struct Buffer {
    std::vector<V3> light, next;
    std::vector<float> variance, next_variance, lum, inv_sigma;
    explicit Buffer(std::size_t count)
        : light(count), next(count), variance(count), next_variance(count), lum(count), inv_sigma(count) {}
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
        row_ranges([&](int y0, int y1) {
            std::vector<float> sum(w_), sum_w(w_);
            for (int y = y0; y < y1; ++y) {
                std::fill(sum.begin(), sum.end(), 0.0f);
                std::fill(sum_w.begin(), sum_w.end(), 0.0f);
                // Tap by tap over the row, each pixel's sums in the kernel's order.  A tap
                // that is not covered adds +0 instead of being skipped: the same sums (they
                // start at +0 and only grow), without a branch.
                for (int dy = -1; dy <= 1; ++dy) {
                    const int qy = y + dy;
                    if (qy < 0 || qy >= h_) continue;
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int x0 = std::max(0, -dx), x1 = std::min(w_, w_ - dx);
                        const std::size_t q0 = index(x0 + dx, qy);
                        const float* const variance = b.variance.data() + q0;
                        const std::int32_t* const covered = g_.covered.data() + q0;
                        const float k = kKernel[dx + 1] * kKernel[dy + 1];
                        int x = x0;
#if defined(__SSE2__)
                        // Four pixels at a time, each lane the loop's select and sums below.
                        const __m128 k4 = _mm_set1_ps(k);
                        for (; x + 4 <= x1; x += 4) {
                            const __m128 taken = _mm_castsi128_ps(_mm_cmpeq_epi32(
                                _mm_cmpeq_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(covered + (x - x0))),
                                                _mm_setzero_si128()),
                                _mm_setzero_si128()));
                            _mm_storeu_ps(
                                &sum[x],
                                _mm_add_ps(_mm_loadu_ps(&sum[x]),
                                           _mm_and_ps(taken, _mm_mul_ps(k4, _mm_loadu_ps(variance + (x - x0))))));
                            _mm_storeu_ps(&sum_w[x], _mm_add_ps(_mm_loadu_ps(&sum_w[x]), _mm_and_ps(taken, k4)));
                        }
#endif
                        for (; x < x1; ++x) {
                            const bool taken = covered[x - x0] != 0;
                            sum[x] += taken ? k * variance[x - x0] : 0.0f;
                            sum_w[x] += taken ? k : 0.0f;
                        }
                    }
                }
                int x = 0;
#if defined(__SSE2__)
                // Four pixels' 1 / sigma at a time (each lane the loop's operations below).
                for (; x + 4 <= w_; x += 4) {
                    const __m128 sw = _mm_loadu_ps(&sum_w[x]);
                    const __m128 positive = _mm_cmpgt_ps(sw, _mm_setzero_ps());
                    // A zero weight's lane divides by 1 and is then masked to the loop's 0.
                    const __m128 v = _mm_and_ps(
                        positive,
                        _mm_div_ps(_mm_loadu_ps(&sum[x]),
                                   _mm_or_ps(_mm_and_ps(positive, sw), _mm_andnot_ps(positive, _mm_set1_ps(1.0f)))));
                    const __m128 sigma = _mm_add_ps(
                        _mm_mul_ps(_mm_set1_ps(kSigmaLuminance), _mm_sqrt_ps(_mm_max_ps(v, _mm_setzero_ps()))),
                        _mm_set1_ps(1e-4f));
                    _mm_storeu_ps(&b.inv_sigma[index(x, y)], _mm_div_ps(_mm_set1_ps(1.0f), sigma));
                }
#endif
                for (; x < w_; ++x) {
                    const float v = sum_w[x] > 0.0f ? sum[x] / sum_w[x] : 0.0f;
                    b.inv_sigma[index(x, y)] = 1.0f / (kSigmaLuminance * std::sqrt(std::max(0.0f, v)) + 1e-4f);
                }
                for (int xl = 0; xl < w_; ++xl) b.lum[index(xl, y)] = luminance(b.light[index(xl, y)]);
            }
        });
    }

    // One a-trous pass at `stride`.  With two buffers each is averaged with colour weights
    // from the other (cross-filtering): whether a tap is taken does not depend on the noise
    // it carries, so a pixel's own noise cannot make it refuse its neighbours.  With one
    // buffer (b == nullptr) it is guided by itself.  `relaxed`: cloth pixels of one albedo
    // take the relaxed normal weight.
    void pass(int stride, Buffer& a, Buffer* b, bool relaxed = false) {
        row_ranges([&](int y0, int y1) {
            Row row(w_);
            for (int y = y0; y < y1; ++y) {
                if (b)
                    pass_row<true>(row, y, stride, a, *b, relaxed);
                else
                    pass_row<false>(row, y, stride, a, a, relaxed);
            }
        });
        a.swap();
        if (b) b->swap();
    }

    // f() on the filter's threads (a further stage of the same image).
    template <class F>
    void execute(F&& f) {
        arena_.execute(std::forward<F>(f));
    }

private:
    // One row's scratch: per pixel of the row, the current tap's exponents, their exp(-e)
    // and normal weight (0: not taken), and the sums so far.
    struct Row {
        std::vector<float> e_a, e_b, x_a, x_b, nw, nw4, sum_a, wa, va, sum_b, wb, vb;
        explicit Row(int w)
            : e_a(w), e_b(w), x_a(w), x_b(w), nw(w), nw4(w), sum_a(3 * w), wa(w), va(w), sum_b(3 * w), wb(w), vb(w) {}
    };

    // Row y of a pass.  kCross: buffer a is guided by b (g_lum, g_inv_sigma: the guide's), b
    // by a; else a by itself (b is a, its own sums unused).  The row is filtered tap by tap: for each of the 9 taps, in
    // the kernel's order, first every pixel's weight terms and their exp (fast_exp, the SSE2 lanes giving the scalar
    // floats) in a branch-free loop (with SSE2 four pixels at a time), then the taps taken are weighted and added to
    // each pixel's sums.  Each pixel's sums thus add the same terms in the same order as a pixel-by-pixel loop, and
    // every term is the same expression, so the floats are the same as that loop's.
#if defined(__SSE2__)
    // The weighted sums of four pixels' taps (pass_row's scalar loop for each lane where
    // `taken` is set and the exponent is within kMaxExponent; the same products in the same
    // order): the colours are three floats a pixel, so the four weights are spread over
    // three registers to meet twelve contiguous floats of the sums and of the taps' colours.
    static void accumulate4(__m128 taken, __m128 k, const float* e, const float* ex, float* sum, float* wsum,
                            float* vsum, const V3* light, const float* variance) {
        const __m128 m = _mm_and_ps(taken, _mm_cmple_ps(_mm_loadu_ps(e), _mm_set1_ps(kMaxExponent)));
        const __m128 wt = _mm_mul_ps(k, _mm_loadu_ps(ex));
        static_assert(sizeof(V3) == 3 * sizeof(float), "V3: three packed floats");
        const float* const l = reinterpret_cast<const float*>(light);
        const auto add = [&](int at, __m128 w, __m128 mask) {
            _mm_storeu_ps(sum + at,
                          _mm_add_ps(_mm_loadu_ps(sum + at), _mm_and_ps(mask, _mm_mul_ps(w, _mm_loadu_ps(l + at)))));
        };
        add(0, _mm_shuffle_ps(wt, wt, _MM_SHUFFLE(1, 0, 0, 0)), _mm_shuffle_ps(m, m, _MM_SHUFFLE(1, 0, 0, 0)));
        add(4, _mm_shuffle_ps(wt, wt, _MM_SHUFFLE(2, 2, 1, 1)), _mm_shuffle_ps(m, m, _MM_SHUFFLE(2, 2, 1, 1)));
        add(8, _mm_shuffle_ps(wt, wt, _MM_SHUFFLE(3, 3, 3, 2)), _mm_shuffle_ps(m, m, _MM_SHUFFLE(3, 3, 3, 2)));
        _mm_storeu_ps(wsum, _mm_add_ps(_mm_loadu_ps(wsum), _mm_and_ps(m, wt)));
        _mm_storeu_ps(vsum, _mm_add_ps(_mm_loadu_ps(vsum),
                                       _mm_and_ps(m, _mm_mul_ps(_mm_mul_ps(wt, wt), _mm_loadu_ps(variance)))));
    }
#endif

    template <bool kCross>
    void pass_row(Row& row, int y, int stride, Buffer& a, Buffer& b, bool relaxed) {
        std::fill(row.sum_a.begin(), row.sum_a.end(), 0.0f);
        std::fill(row.wa.begin(), row.wa.end(), 0.0f);
        std::fill(row.va.begin(), row.va.end(), 0.0f);
        if (kCross) {
            std::fill(row.sum_b.begin(), row.sum_b.end(), 0.0f);
            std::fill(row.wb.begin(), row.wb.end(), 0.0f);
            std::fill(row.vb.begin(), row.vb.end(), 0.0f);
        }
        const std::ptrdiff_t r = static_cast<std::ptrdiff_t>(index(0, y));
        for (int dy = -1; dy <= 1; ++dy) {
            const int qy = y + dy * stride;
            if (qy < 0 || qy >= h_) continue;
            for (int dx = -1; dx <= 1; ++dx) {
                // The pixels x whose tap x + dx * stride is inside the row.
                const int x0 = std::max(0, -dx * stride), x1 = std::min(w_, w_ - dx * stride);
                if (x0 >= x1) continue;
                const std::ptrdiff_t offset = static_cast<std::ptrdiff_t>(dy) * stride * w_ + dx * stride;
                const float inv_distance = 1.0f / std::max(1.0f, static_cast<float>(stride) *
                                                                     std::sqrt(static_cast<float>(dx * dx + dy * dy)));
                tap_terms<kCross>(row, r, x0, x1, offset, inv_distance, a, b);
                if (relaxed) relax_normal_weights(row, r, x0, x1, offset);
                add_taps<kCross>(row, r, x0, x1, offset, kKernel[dx + 1] * kKernel[dy + 1], a, b);
            }
        }
        write_row<kCross>(row, r, a, b);
    }

    // One tap of row r's pixels x0..x1-1 (the tap at `offset` from each): their exponents
    // e_a (e_b), exp(-e) x_a (x_b) and normal weight nw (nw4: cos^4).
    template <bool kCross>
    void tap_terms(Row& row, std::ptrdiff_t r, int x0, int x1, std::ptrdiff_t offset, float inv_distance,
                   const Buffer& a, const Buffer& b) {
        const float* const nx = g_.nx.data();
        const float* const ny = g_.ny.data();
        const float* const nz = g_.nz.data();
        const std::int32_t* const sky = g_.sky.data();
        const float* const depth = g_.depth.data();
        const float* const inv_depth = g_.inv_depth_tolerance.data();
        const std::int32_t* const covered = g_.covered.data();
        const float* const turning = g_.turning.data();
        const float* const g_lum = b.lum.data();
        const float* const a_lum = a.lum.data();
        const float* const g_inv_sigma = b.inv_sigma.data();
        const float* const a_inv_sigma = a.inv_sigma.data();
        float* const e_a = row.e_a.data();
        float* const e_b = row.e_b.data();
        float* const x_a = row.x_a.data();
        float* const x_b = row.x_b.data();
        float* const nw = row.nw.data();
        float* const nw4 = row.nw4.data();
        // The row's pixels (p) from x0 on and their taps (q), indexed by t = x - x0.
        const float *const depth_p = depth + r + x0, *const depth_q = depth_p + offset;
        const float *const turning_p = turning + r + x0, *const turning_q = turning_p + offset;
        const float *const g_lum_p = g_lum + r + x0, *const g_lum_q = g_lum_p + offset;
        const float *const a_lum_p = a_lum + r + x0, *const a_lum_q = a_lum_p + offset;
        const float *const nx_p = nx + r + x0, *const nx_q = nx_p + offset;
        const float *const ny_p = ny + r + x0, *const ny_q = ny_p + offset;
        const float *const nz_p = nz + r + x0, *const nz_q = nz_p + offset;
        const std::int32_t *const sky_p = sky + r + x0, *const sky_q = sky_p + offset;
        const std::int32_t *const covered_p = covered + r + x0, *const covered_q = covered_p + offset;
        const float* const inv_depth_p = inv_depth + r + x0;
        const float* const g_inv_sigma_p = g_inv_sigma + r + x0;
        const float* const a_inv_sigma_p = a_inv_sigma + r + x0;
        const int taps = x1 - x0;
        float *const e_a_t = e_a + x0, *const e_b_t = e_b + x0, *const nw_t = nw + x0, *const nw4_t = nw4 + x0;
        float *const x_a_t = x_a + x0, *const x_b_t = x_b + x0;
        int t = 0;
#if defined(__SSE2__)
        // Four pixels at a time, each lane the same operations in the same order as
        // the loop below (which does the rest): the same floats.
        const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
        const __m128 sign_bit = _mm_set1_ps(-0.0f);
        const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
        const __m128 dead_zone = _mm_set1_ps(kMixDeadZone), mix_scale = _mm_set1_ps(kMixScale);
        const __m128 inv_distance4 = _mm_set1_ps(inv_distance);
        const auto abs_diff = [&](const float* q, const float* p) {
            return _mm_and_ps(_mm_sub_ps(_mm_loadu_ps(q), _mm_loadu_ps(p)), abs_mask);
        };
        const auto select = [](__m128 mask, __m128 if_set, __m128 if_clear) {
            return _mm_or_ps(_mm_and_ps(mask, if_set), _mm_andnot_ps(mask, if_clear));
        };
        const auto both = [](const std::int32_t* p, const std::int32_t* q) {
            const __m128i flags = _mm_and_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)),
                                                _mm_loadu_si128(reinterpret_cast<const __m128i*>(q)));
            return _mm_castsi128_ps(_mm_cmpeq_epi32(flags, _mm_set1_epi32(1)));
        };
        for (; t + 4 <= taps; t += 4) {
            const __m128 e_depth = _mm_mul_ps(
                _mm_mul_ps(abs_diff(depth_q + t, depth_p + t), _mm_loadu_ps(inv_depth_p + t)), inv_distance4);
            const __m128 mix = abs_diff(turning_q + t, turning_p + t);
            const __m128 e_mixed = _mm_add_ps(e_depth, _mm_mul_ps(mix_scale, _mm_sub_ps(mix, dead_zone)));
            const __m128 e = select(_mm_cmpgt_ps(mix, dead_zone), e_mixed, e_depth);
            const __m128 ea =
                _mm_add_ps(e, _mm_mul_ps(abs_diff(g_lum_q + t, g_lum_p + t), _mm_loadu_ps(g_inv_sigma_p + t)));
            _mm_storeu_ps(e_a_t + t, ea);
            _mm_storeu_ps(x_a_t + t, fast_exp4(_mm_xor_ps(ea, sign_bit)));
            if (kCross) {
                const __m128 eb =
                    _mm_add_ps(e, _mm_mul_ps(abs_diff(a_lum_q + t, a_lum_p + t), _mm_loadu_ps(a_inv_sigma_p + t)));
                _mm_storeu_ps(e_b_t + t, eb);
                _mm_storeu_ps(x_b_t + t, fast_exp4(_mm_xor_ps(eb, sign_bit)));
            }
            const __m128 dot = _mm_add_ps(_mm_mul_ps(_mm_loadu_ps(nx_p + t), _mm_loadu_ps(nx_q + t)),
                                          _mm_add_ps(_mm_mul_ps(_mm_loadu_ps(ny_p + t), _mm_loadu_ps(ny_q + t)),
                                                     _mm_mul_ps(_mm_loadu_ps(nz_p + t), _mm_loadu_ps(nz_q + t))));
            __m128 c = _mm_max_ps(dot, zero);  // dot > 0 ? dot : 0, as std::max(0.0f, dot)
            c = _mm_mul_ps(c, c);
            c = _mm_mul_ps(c, c);
            _mm_storeu_ps(nw4_t + t, c);
            for (int k = kRelaxedNormalSquarings; k < kNormalSquarings; ++k) c = _mm_mul_ps(c, c);
            const __m128 n = select(both(sky_p + t, sky_q + t), one, c);
            _mm_storeu_ps(nw_t + t, _mm_and_ps(both(covered_p + t, covered_q + t), n));
        }
#endif
        for (; t < taps; ++t) {
            const float e_depth = std::abs(depth_q[t] - depth_p[t]) * inv_depth_p[t] * inv_distance;
            // The mixture term, added only beyond the dead zone (where it is not 0).
            const float mix = std::abs(turning_q[t] - turning_p[t]);
            const float e = mix > kMixDeadZone ? e_depth + kMixScale * (mix - kMixDeadZone) : e_depth;
            e_a_t[t] = e + std::abs(g_lum_q[t] - g_lum_p[t]) * g_inv_sigma_p[t];
            x_a_t[t] = fast_exp(-e_a_t[t]);
            if (kCross) {
                e_b_t[t] = e + std::abs(a_lum_q[t] - a_lum_p[t]) * a_inv_sigma_p[t];
                x_b_t[t] = fast_exp(-e_b_t[t]);
            }
            // The normal weight cos^128, or cos^4 (the chain's second step) between
            // cloth pixels of one albedo in a relaxed pass (below); 0 between sky (zero
            // normal) and surface, 1 between two sky pixels.
            const float dot = nx_p[t] * nx_q[t] + (ny_p[t] * ny_q[t] + nz_p[t] * nz_q[t]);
            float c = std::max(0.0f, dot);
            c *= c;
            c *= c;
            nw4_t[t] = c;
            for (int k = kRelaxedNormalSquarings; k < kNormalSquarings; ++k) c *= c;
            // (bitwise & on the 0 / 1 flags: no branches)
            const float n = (sky_p[t] & sky_q[t]) ? 1.0f : c;
            nw_t[t] = (covered_p[t] & covered_q[t]) ? n : 0.0f;
        }
    }

    // The relaxed pass (one in six): cos^4 between cloth pixels of one albedo, apart so that
    // tap_terms' loop stays branch-free.
    void relax_normal_weights(Row& row, std::ptrdiff_t r, int x0, int x1, std::ptrdiff_t offset) {
        const std::int32_t* const sky = g_.sky.data();
        const std::int32_t* const covered = g_.covered.data();
        const std::int32_t* const cloth = g_.cloth.data();
        const float* const ax = g_.ax.data();
        const float* const ay = g_.ay.data();
        const float* const az = g_.az.data();
        float* const nw = row.nw.data();
        const float* const nw4 = row.nw4.data();
        for (int x = x0; x < x1; ++x) {
            const std::ptrdiff_t i = r + x, j = i + offset;
            const bool same_cloth = cloth[i] && cloth[j] && std::abs(ax[i] - ax[j]) < kSameAlbedo &&
                                    std::abs(ay[i] - ay[j]) < kSameAlbedo && std::abs(az[i] - az[j]) < kSameAlbedo;
            if (same_cloth && covered[i] && covered[j] && !(sky[i] && sky[j])) nw[x] = nw4[x];
        }
    }

    // The taps taken, weighted, added to each pixel's sums.
    template <bool kCross>
    void add_taps(Row& row, std::ptrdiff_t r, int x0, int x1, std::ptrdiff_t offset, float kernel, const Buffer& a,
                  const Buffer& b) {
        const V3* const a_light = a.light.data();
        const float* const a_variance = a.variance.data();
        const V3* const b_light = b.light.data();
        const float* const b_variance = b.variance.data();
        const float* const e_a = row.e_a.data();
        const float* const e_b = row.e_b.data();
        const float* const x_a = row.x_a.data();
        const float* const x_b = row.x_b.data();
        const float* const nw = row.nw.data();
        float* const sum_a = row.sum_a.data();
        float* const wa = row.wa.data();
        float* const va = row.va.data();
        float* const sum_b = row.sum_b.data();
        float* const wb = row.wb.data();
        float* const vb = row.vb.data();
        int x = x0;
#if defined(__SSE2__)
        // Four pixels at a time, branch-free: a tap not taken adds masked zeros
        // (+0 leaves every sum as it is), a taken one the loop's products below.
        const __m128 kernel4 = _mm_set1_ps(kernel);
        for (; x + 4 <= x1; x += 4) {
            const std::ptrdiff_t j = r + x + offset;
            const __m128 n = _mm_loadu_ps(nw + x);
            const __m128 taken = _mm_cmpneq_ps(n, _mm_setzero_ps());
            const __m128 k = _mm_mul_ps(kernel4, n);
            accumulate4(taken, k, e_a + x, x_a + x, sum_a + 3 * x, wa + x, va + x, a_light + j, a_variance + j);
            if (kCross)
                accumulate4(taken, k, e_b + x, x_b + x, sum_b + 3 * x, wb + x, vb + x, b_light + j, b_variance + j);
        }
#endif
        for (; x < x1; ++x) {
            if (nw[x] == 0.0f) continue;
            const std::ptrdiff_t j = r + x + offset;
            const float k = kernel * nw[x];
            // Beyond kMaxExponent the tap's weight (< 1e-9) is lost in the centre's (>= 1/4).
            if (e_a[x] <= kMaxExponent) {
                const float wt = k * x_a[x];
                for (int c = 0; c < 3; ++c) sum_a[3 * x + c] += wt * a_light[j][c];
                wa[x] += wt;
                va[x] += wt * wt * a_variance[j];
            }
            if (kCross && e_b[x] <= kMaxExponent) {
                const float wt = k * x_b[x];
                for (int c = 0; c < 3; ++c) sum_b[3 * x + c] += wt * b_light[j][c];
                wb[x] += wt;
                vb[x] += wt * wt * b_variance[j];
            }
        }
    }

    // The row's sums normalised into the buffers' next values (uncovered pixels as they are).
    template <bool kCross>
    void write_row(const Row& row, std::ptrdiff_t r, Buffer& a, Buffer& b) {
        const std::int32_t* const covered = g_.covered.data();
        const V3* const a_light = a.light.data();
        const float* const a_variance = a.variance.data();
        const V3* const b_light = b.light.data();
        const float* const b_variance = b.variance.data();
        const float* const sum_a = row.sum_a.data();
        const float* const wa = row.wa.data();
        const float* const va = row.va.data();
        const float* const sum_b = row.sum_b.data();
        const float* const wb = row.wb.data();
        const float* const vb = row.vb.data();
        for (int x = 0; x < w_; ++x) {
            const std::ptrdiff_t i = r + x;
            if (!covered[i]) {
                a.next[i] = a_light[i];
                a.next_variance[i] = a_variance[i];
                if (kCross) b.next[i] = b_light[i], b.next_variance[i] = b_variance[i];
                continue;
            }
            // The centre's own weight is > 0.
            a.next[i] = V3(sum_a[3 * x] / wa[x], sum_a[3 * x + 1] / wa[x], sum_a[3 * x + 2] / wa[x]);
            a.next_variance[i] = va[x] / (wa[x] * wa[x]);
            if (kCross) {
                b.next[i] = V3(sum_b[3 * x] / wb[x], sum_b[3 * x + 1] / wb[x], sum_b[3 * x + 2] / wb[x]);
                b.next_variance[i] = vb[x] / (wb[x] * wb[x]);
            }
        }
    }

    std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * w_ + x; }
    // f(y0, y1) for the rows of each task, which then allocates its row scratch once.
    template <class F>
    void row_ranges(F&& f) {
        arena_.execute([&] {
            tbb::parallel_for(tbb::blocked_range<int>(0, h_),
                              [&](const tbb::blocked_range<int>& r) { f(r.begin(), r.end()); });
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

namespace {

// The image divided by its first-hit albedo (what the passes and the fits filter), in one
// buffer or, where the tracer kept them, two halves, and the guide the passes read.
struct Demodulated {
    Guide guide;
    std::vector<V3> albedo;
    std::vector<float> fitted_variance;
    std::vector<float> noisy_variance;  // of the demodulated light's luminance
    std::vector<V3> noisy;              // the pixel's light, demodulated: what the regression fits (in part)
    Buffer a;
    std::optional<Buffer> b;
    explicit Demodulated(std::size_t count)
        : guide(count), albedo(count), fitted_variance(count), noisy_variance(count), noisy(count), a(count) {}
};

// A still's halves as the passes start (their noisy light and its variance) and after the
// cross passes, finished apart: for the regressions' choice of setting (fit_selection.hpp).
struct StillHalves {
    std::vector<V3> noisy_a, noisy_b;
    std::vector<float> noise_a, noise_b;
    std::optional<Buffer> half_a, half_b;
};

void demodulate_image(const Image& rgba, const PixelFeatures& features, Demodulated& d) {
    const std::size_t count = d.albedo.size();
    Guide& guide = d.guide;
    for (std::size_t i = 0; i < count; ++i) {
        guide.nx[i] = features.normal[i].x();
        guide.ny[i] = features.normal[i].y();
        guide.nz[i] = features.normal[i].z();
        guide.sky[i] = features.normal[i].squaredNorm() == 0.0f;
        guide.depth[i] = features.depth[i];
        guide.covered[i] = rgba.pixels[4 * i + 3] > 0.0f;
        guide.cloth[i] = features.cloth.size() == count && features.cloth[i] > 0.5f;
        guide.turning[i] = features.turning.size() == count ? features.turning[i] : 0.0f;
        guide.ax[i] = features.albedo[i].x();
        guide.ay[i] = features.albedo[i].y();
        guide.az[i] = features.albedo[i].z();
        const float* c = &rgba.pixels[4 * i];
        for (int k = 0; k < 3; ++k) d.albedo[i][k] = demodulation_divisor(features.albedo[i][k]);
        const float al = std::max(kMinDemodulationAlbedo, luminance(d.albedo[i]));
        const float variance = features.variance[i] / (al * al);
        d.noisy_variance[i] = variance;
        // What the regression's light carries of it (a quarter of the noisy light's).
        d.fitted_variance[i] = kRegressionNoisyShare * kRegressionNoisyShare * variance;
        for (int k = 0; k < 3; ++k) d.noisy[i][k] = c[k] / d.albedo[i][k];
        if (!d.b) {
            d.a.light[i] = d.noisy[i];
            d.a.variance[i] = variance;
        } else {
            // Each half's variance from the whole pixel's, by its share of the samples.
            const float s = features.half_share[i];
            for (int k = 0; k < 3; ++k) {
                d.a.light[i][k] = features.half_a[i][k] / d.albedo[i][k];
                d.b->light[i][k] = features.half_b[i][k] / d.albedo[i][k];
            }
            d.a.variance[i] = variance / s;
            d.b->variance[i] = variance / (1.0f - s);
        }
    }
}

// The depth tolerance: how much depth changes per pixel here, per axis the smaller of the
// two one-sided differences, so that a silhouette beside the pixel (a thin rod or wire
// against the backdrop) does not widen it.
void set_depth_tolerance(Guide& guide, int w, int h) {
    const std::vector<float>& depth = guide.depth;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * w + x;
            const auto diff = [&](int qx, int qy) {
                if (qx < 0 || qx >= w || qy < 0 || qy >= h) return -1.0f;
                return std::abs(depth[static_cast<std::size_t>(qy) * w + qx] - depth[i]);
            };
            const auto axis = [](float m, float n) {
                return m < 0.0f ? std::max(0.0f, n) : n < 0.0f ? m : std::min(m, n);
            };
            const float step = std::max(axis(diff(x - 1, y), diff(x + 1, y)), axis(diff(x, y - 1), diff(x, y + 1)));
            const float depth_step = std::max(step, 1e-3f * depth[i]) + 1e-6f;
            guide.inv_depth_tolerance[i] = 1.0f / (kSigmaDepth * depth_step);
        }
}

// The passes after the cross passes and, with halves, one more at step 1 guided by the
// merged light, whose noise is half either half's: it takes out the pixel-scale noise the
// halves' weights, each from fewer samples, left, with the relaxed normal weight on cloth
// of one albedo.
void finish_passes(Filter& filter, Buffer& buffer, bool halves) {
    for (int pass = kCrossPasses; pass < kPasses; ++pass) {
        filter.prepare(buffer);
        filter.pass(1 << pass, buffer, nullptr);
    }
    if (!halves) return;
    filter.prepare(buffer);
    filter.pass(1, buffer, nullptr, true);
}

// The a-trous passes: the cross passes on the halves, merged, then the rest (a still's
// halves also finished apart, for the regressions' choice of setting).
void run_passes(Filter& filter, Demodulated& d, const PixelFeatures& features, DenoiseBudget budget, bool halves,
                StillHalves& still) {
    for (int pass = 0; pass < kCrossPasses; ++pass) {
        filter.prepare(d.a);
        if (d.b) filter.prepare(*d.b);
        filter.pass(1 << pass, d.a, d.b ? &*d.b : nullptr);
    }
    if (d.b) {
        if (budget == DenoiseBudget::still) still.half_a.emplace(d.a), still.half_b.emplace(*d.b);
        merge(d.a, *d.b, features.half_share), d.b.reset();
    }
    finish_passes(filter, d.a, halves);
    if (still.half_a) finish_passes(filter, *still.half_a, halves), finish_passes(filter, *still.half_b, halves);
}

// A still's fits of the cloth and the backdrop (by the halves where kept) and of the supports.
void fit_still(Filter& filter, const PixelFeatures& features, Demodulated& d, StillHalves& still,
               ClothRegressionInput& in, const std::vector<V3>& whole_noisy) {
    const std::size_t count = d.albedo.size();
    const Guide& guide = d.guide;
    in.depth_regressor = true, in.average_fits = true;
    std::size_t cloth_pixels = 0;
    for (std::size_t i = 0; i < count; ++i) cloth_pixels += guide.cloth[i] != 0;
    in.spatial_sigma = still_spatial_sigma(cloth_pixels);
    // A still's backdrop regression (backdrop_light_fit.hpp) fits the same blend with
    // the same guide: fitted to the noisy light alone, it lowered the error at 320x180
    // more but left blotches on the backdrop of the 1280x720 render with adaptive
    // sampling, which the passes' result there does not have (docs/benchmarks.md, "The
    // backdrop's regression").  It reads and writes backdrop pixels only, the cloth's
    // regression cloth pixels only.
    std::vector<std::int32_t> backdrop(count);
    for (std::size_t i = 0; i < count; ++i) backdrop[i] = guide.covered[i] && !guide.sky[i] && guide.turning[i] == 0.0f;
    BackdropRegressionInput back;
    back.width = in.width, back.height = in.height;
    back.light = in.light, back.guide = in.guide, back.variance = &d.a.variance, back.depth = &guide.depth;
    back.backdrop = &backdrop;
    if (!still.half_a) {
        filter.execute([&] {
            regress_backdrop(back, d.a.light);
            regress_cloth(in, d.a.light);
        });
    } else {
        SelectionInput select;
        select.cloth = in, select.backdrop = back;
        std::vector<V3> error_weight(count);
        for (std::size_t i = 0; i < count; ++i)
            for (int k = 0; k < 3; ++k) {
                const float weight = d.albedo[i][k] * srgb_slope(d.a.light[i][k] * d.albedo[i][k]);
                error_weight[i][k] = weight * weight;
            }
        select.whole = {&whole_noisy, &d.noisy_variance, &d.a.light, &d.a.variance};
        select.half_a = {&still.noisy_a, &still.noise_a, &still.half_a->light, &still.half_a->variance};
        select.half_b = {&still.noisy_b, &still.noise_b, &still.half_b->light, &still.half_b->variance};
        select.error_weight = &error_weight;
        filter.execute([&] { regress_still_by_halves(select, d.a.light); });
    }
    // And the supports' regression along their axis (support_light_fit.hpp), on the
    // same blend: pixels with samples on the rod, a clip or a wire and none on the garment.
    std::vector<std::int32_t> support(count);
    for (std::size_t i = 0; i < count; ++i)
        support[i] = guide.covered[i] && !guide.sky[i] && guide.turning[i] > 0.0f &&
                     (features.cloth.size() != count || features.cloth[i] == 0.0f);
    SupportRegressionInput supports;
    static_cast<RegressionInput&>(supports) = in;  // the same light, guide and surface
    supports.turning = &guide.turning, supports.support = &support;
    filter.execute([&] { regress_supports(supports, d.a.light); });
}

// The cloth's first-order regression (cloth_light_fit.hpp), its colour weight from what the
// passes made of the light, and a still's other fits.  It fits kRegressionNoisyShare of the
// noisy light and the rest of the passes' result: fitted to the noisy light alone, the fit's
// own noise, shared by neighbours whose windows overlap, showed as blotches on the flat cloth
// of the default 1280x720 render with adaptive sampling; fitted to the passes' result alone,
// it kept less of its gain (docs/benchmarks.md, "Cloth regression").
void fit_light(Filter& filter, const PixelFeatures& features, DenoiseBudget budget, int w, int h, Demodulated& d,
               StillHalves& still) {
    const std::size_t count = d.albedo.size();
    std::vector<float> filtered_lum(count);
    const std::vector<V3> whole_noisy = still.half_a ? d.noisy : std::vector<V3>();
    std::vector<V3>& fitted = d.noisy;  // blended in place
    for (std::size_t i = 0; i < count; ++i) {
        filtered_lum[i] = luminance(d.a.light[i]);
        fitted[i] = kRegressionNoisyShare * d.noisy[i] + (1.0f - kRegressionNoisyShare) * d.a.light[i];
    }
    const Guide& guide = d.guide;
    ClothRegressionInput in;
    in.width = w, in.height = h;
    in.light = &fitted, in.guide = &filtered_lum, in.variance = &d.a.variance, in.fitted_variance = &d.fitted_variance;
    in.nx = &guide.nx, in.ny = &guide.ny, in.nz = &guide.nz, in.depth = &guide.depth;
    in.ax = &guide.ax, in.ay = &guide.ay, in.az = &guide.az, in.cloth = &guide.cloth;
    if (budget == DenoiseBudget::frame)
        filter.execute([&] { regress_cloth(in, d.a.light); });
    else
        fit_still(filter, features, d, still, in, whole_noisy);
}

}  // namespace

void denoise(Image& rgba, const PixelFeatures& features, int threads, DenoiseBudget budget) {
    const int w = rgba.width, h = rgba.height;
    const std::size_t count = static_cast<std::size_t>(w) * h;
    const bool halves = features.half_a.size() == count;
    Demodulated d(count);
    if (halves) d.b.emplace(count);
    demodulate_image(rgba, features, d);
    set_depth_tolerance(d.guide, w, h);
    StillHalves still;
    if (d.b && budget == DenoiseBudget::still)
        still.noisy_a = d.a.light, still.noise_a = d.a.variance, still.noisy_b = d.b->light,
        still.noise_b = d.b->variance;
    Filter filter(w, h, d.guide, threads);
    run_passes(filter, d, features, budget, halves, still);
    fit_light(filter, features, budget, w, h, d, still);
    for (std::size_t i = 0; i < count; ++i) {
        if (!d.guide.covered[i]) continue;
        for (int k = 0; k < 3; ++k) rgba.pixels[4 * i + k] = d.a.light[i][k] * d.albedo[i][k];
    }
    if (budget == DenoiseBudget::still) rebuild_mixed_pixels(rgba, features, d.a.light);
}

}  // namespace foldcast::render
