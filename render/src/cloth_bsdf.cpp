#include <Eigen/Geometry>
#include "cloth_bsdf.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <array>
#include <cmath>

#include "random_stream.hpp"
#include "vec3_div.hpp"
#include "foldcast/core/colour.hpp"
#include "foldcast/core/fast_math.hpp"
#include "foldcast/core/math.hpp"
#include "foldcast/core/sampling.hpp"

namespace foldcast::render {
namespace {

constexpr float kMinAlpha = 2e-3f;       // GGX: below this the highlight is a near-delta
constexpr float kMinSheenRough = 0.07f;  // Charlie: exponent 1/alpha stays <= ~200

float sqr(float x) { return x * x; }

// --- GGX (anisotropic, height-correlated Smith) -------------------------------------------
float ggx_lambda(const V3& w, float ax, float ay) {
    const float z2 = sqr(w.z());
    if (z2 <= 0.0f) return 1e30f;
    const float t = (sqr(ax * w.x()) + sqr(ay * w.y())) / z2;
    return 0.5f * (-1.0f + std::sqrt(1.0f + t));
}
float schlick(float f0, float c) {
    const float m = std::clamp(1.0f - c, 0.0f, 1.0f);
    const float m2 = m * m;
    return f0 + (1.0f - f0) * m2 * m2 * m;
}
// Heitz 2018, "Sampling the GGX distribution of visible normals".
V3 sample_vndf(const V3& wo, float ax, float ay, float u1, float u2) {
    const V3 vh = normalized3(V3(ax * wo.x(), ay * wo.y(), wo.z()));
    const float lensq = sqr(vh.x()) + sqr(vh.y());
    const V3 t1 = lensq > 0.0f ? V3(-vh.y(), vh.x(), 0.0f) / std::sqrt(lensq) : V3(1.0f, 0.0f, 0.0f);
    const V3 t2 = vh.cross(t1);
    const float r = std::sqrt(u1);
    const SinCos phi = sincos_turns(u2);  // the azimuth 2 pi u2
    const float p1 = r * phi.cos;
    float p2 = r * phi.sin;
    const float s = 0.5f * (1.0f + vh.z());
    p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
    const V3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
    return normalized3(V3(ax * nh.x(), ay * nh.y(), std::max(1e-6f, nh.z())));
}

// --- Charlie sheen with Neubelt-Pettineo visibility ----------------------------------------
float charlie_d(float cos_h, float alpha) {
    const float inv = 1.0f / alpha;
    const float sin2 = std::max(0.0f, 1.0f - cos_h * cos_h);
    return (2.0f + inv) * fast_pow_unit(sin2, 0.5f * inv) / (2.0f * kPiF);  // no libm powf call
}
float neubelt_v(float no, float ni) { return 1.0f / (4.0f * (ni + no - ni * no)); }

// --- Albedo tables: 32 x 32 over (mu, roughness), bilinear -------------------------------
constexpr int kN = 32;
float node_mu(int i) { return std::max(0.02f, static_cast<float>(i) / (kN - 1)); }
float node_rough(int j) { return static_cast<float>(j) / (kN - 1); }

struct AlbedoTables {
    std::array<float, kN * kN> spec_a{};  // E = f0 * A + B
    std::array<float, kN * kN> spec_b{};
    std::array<float, kN * kN> sheen{};

    AlbedoTables() {
        constexpr int kStrata = 48;  // kStrata^2 stratified samples per entry
        for (int i = 0; i < kN; ++i) {
            const float mu = node_mu(i);
            const V3 wo(std::sqrt(1.0f - mu * mu), 0.0f, mu);
            for (int j = 0; j < kN; ++j) {
                const float alpha = std::max(kMinAlpha, sqr(node_rough(j)));
                const float sheen_alpha = sqr(std::max(kMinSheenRough, node_rough(j)));
                double a = 0.0, b = 0.0, sh = 0.0;
                RandomStream rng(0x7ab1e5, static_cast<std::uint64_t>(i * kN + j), 0);
                for (int sy = 0; sy < kStrata; ++sy)
                    for (int sx = 0; sx < kStrata; ++sx) {
                        const float u1 = (static_cast<float>(sx) + rng.next()) / kStrata;
                        const float u2 = (static_cast<float>(sy) + rng.next()) / kStrata;
                        // GGX: VNDF sampling, weight G2 / G1(o).
                        const V3 h = sample_vndf(wo, alpha, alpha, u1, u2);
                        const V3 wi = reflect(wo, h);
                        if (wi.z() > 0.0f) {
                            const float lo = ggx_lambda(wo, alpha, alpha);
                            const float li = ggx_lambda(wi, alpha, alpha);
                            const float w = (1.0f + lo) / (1.0f + lo + li);
                            const float m = 1.0f - std::clamp(wo.dot(h), 0.0f, 1.0f);
                            const float m5 = m * m * m * m * m;
                            a += (1.0f - m5) * w;
                            b += m5 * w;
                        }
                        // Sheen: uniform hemisphere, weight f cos 2 pi.
                        const float z = u1;
                        const V3 ws = sample_uniform_hemisphere(z, u2);
                        const V3 hs = (wo + ws).normalized();
                        sh += charlie_d(hs.z(), sheen_alpha) * neubelt_v(mu, z) * z * 2.0f * kPiF;
                    }
                const double n = static_cast<double>(kStrata) * kStrata;
                spec_a[i * kN + j] = static_cast<float>(a / n);
                spec_b[i * kN + j] = static_cast<float>(b / n);
                sheen[i * kN + j] = static_cast<float>(std::min(1.0, sh / n));
            }
        }
    }

    // A bilinear look-up's cell and weights, shared by the tables looked up at one (mu, rough).
    struct Cell {
        int index;  // of the cell's low corner
        float di, dj;
        Cell(float mu, float rough) {
            const float fi = std::clamp(mu, 0.0f, 1.0f) * (kN - 1);
            const float fj = std::clamp(rough, 0.0f, 1.0f) * (kN - 1);
            const int i0 = std::min(static_cast<int>(fi), kN - 2);
            const int j0 = std::min(static_cast<int>(fj), kN - 2);
            index = i0 * kN + j0;
            di = fi - static_cast<float>(i0);
            dj = fj - static_cast<float>(j0);
        }
    };
    static float lookup(const std::array<float, kN * kN>& t, const Cell& c) {
        const float v00 = t[c.index], v01 = t[c.index + 1];
        const float v10 = t[c.index + kN], v11 = t[c.index + kN + 1];
        return (1 - c.di) * ((1 - c.dj) * v00 + c.dj * v01) + c.di * ((1 - c.dj) * v10 + c.dj * v11);
    }
};

const AlbedoTables& albedo_tables() {
    static const AlbedoTables t;  // thread-safe static init, ~0.1 s once per process
    return t;
}

}  // namespace

float ggx_albedo(float mu, float roughness, float f0) {
    const AlbedoTables& t = albedo_tables();
    const AlbedoTables::Cell cell(mu, roughness);
    return std::clamp(f0 * AlbedoTables::lookup(t.spec_a, cell) + AlbedoTables::lookup(t.spec_b, cell), 0.0f, 1.0f);
}
float sheen_albedo(float mu, float sheen_roughness) {
    return std::clamp(AlbedoTables::lookup(albedo_tables().sheen, AlbedoTables::Cell(mu, sheen_roughness)), 0.0f, 1.0f);
}

BsdfLobes::BsdfLobes(const BsdfParams& params) {
    roughness = std::clamp(params.roughness, 0.0f, 1.0f);
    sheen_roughness = std::clamp(params.sheen_roughness, kMinSheenRough, 1.0f);
    // Disney's anisotropy mapping: the geometric mean of the two alphas stays r^2.
    const float alpha = std::max(kMinAlpha, sqr(roughness));
    const float aspect = std::sqrt(1.0f - 0.9f * std::clamp(params.anisotropy, 0.0f, 0.99f));
    ax = std::max(kMinAlpha, alpha / aspect);
    ay = std::max(kMinAlpha, alpha * aspect);
    inv_ax2 = 1.0f / (ax * ax), inv_ay2 = 1.0f / (ay * ay);
    d_scale = 1.0f / (kPiF * ax * ay);
    isotropic = ax == ay;
    table_roughness = std::sqrt(std::sqrt(ax * ay));  // the albedo table's (perceptual) roughness
    sheen_alpha = sqr(sheen_roughness);
    sheen_exponent = 0.5f / sheen_alpha;
    sheen_d_scale = (2.0f + 1.0f / sheen_alpha) / (2.0f * kPiF);
    sheen_scale = std::clamp(params.sheen.maxCoeff(), 0.0f, 1.0f);
    sheen_luminance = luminance(params.sheen);
}

ClothBsdf::ClothBsdf(const BsdfParams& params, const BsdfLobes& lobes, const V3& wo)
    : p_(params), lobes_(lobes), wo_(wo) {
    const float mu = std::clamp(wo_.z(), 0.0f, 1.0f);
    // Anisotropic lobes: Smith's Lambda depends on the roughness projected on the view's
    // azimuth, so look the isotropic table up at that roughness (for an isotropic lobe it is
    // the lobe's own, set up with the lobes: the look-up then waits on no division).
    const float sxy = sqr(wo_.x()) + sqr(wo_.y());
    const float z2 = sqr(wo_.z());
    const float t_num = sqr(lobes_.ax * wo_.x()) + sqr(lobes_.ay * wo_.y());
    float table_roughness = lobes_.table_roughness;
#if defined(__SSE2__)
    // That roughness and Smith's Lambda(wo) (ggx_lambda) share their numerator: both
    // quotients in one SSE2 division and both roots in one square root.
    std::array<float, 4> q, root;
    _mm_storeu_ps(q.data(), _mm_div_ps(_mm_set1_ps(t_num), _mm_setr_ps(sxy, z2, 1.0f, 1.0f)));
    _mm_storeu_ps(root.data(), _mm_sqrt_ps(_mm_setr_ps(q[0], 1.0f + q[1], 0.0f, 0.0f)));
    if (!lobes_.isotropic && sxy > 1e-12f) table_roughness = std::sqrt(root[0]);
    lambda_o_ = z2 <= 0.0f ? 1e30f : 0.5f * (-1.0f + root[1]);
#else
    if (!lobes_.isotropic && sxy > 1e-12f) table_roughness = std::sqrt(std::sqrt(t_num / sxy));
    lambda_o_ = ggx_lambda(wo_, lobes_.ax, lobes_.ay);
#endif
    e_spec_ = ggx_albedo(mu, table_roughness, p_.f0);
    e_sheen_ = lobes_.sheen_scale > 0.0f ? sheen_albedo(mu, lobes_.sheen_roughness) : 0.0f;
    base_weight_ = 1.0f - e_spec_;
    diffuse_weight_ = base_weight_ * (1.0f - lobes_.sheen_scale * e_sheen_);
    // Lobe selection in proportion to each lobe's share of the albedo.
    const float ws = e_spec_;
    const float wsh = base_weight_ * e_sheen_ * lobes.sheen_luminance;
    const float wd = diffuse_weight_ * luminance(p_.diffuse);
    const float sum = ws + wsh + wd;
    const float pdf_denominator = 4.0f * wo_.z() * (1.0f + lambda_o_);
#if defined(__SSE2__)
    // The three shares and the VNDF pdf's scale in one division.
    std::array<float, 4> shares;
    _mm_storeu_ps(shares.data(), _mm_div_ps(_mm_setr_ps(ws, wsh, wd, 1.0f),
                                            _mm_setr_ps(sum > 0.0f ? sum : 1.0f, sum > 0.0f ? sum : 1.0f,
                                                        sum > 0.0f ? sum : 1.0f, pdf_denominator)));
    pdf_scale_ = wo_.z() > 0.0f ? shares[3] : 0.0f;
    if (sum > 0.0f) p_spec_ = shares[0], p_sheen_ = shares[1], p_diffuse_ = shares[2];
#else
    pdf_scale_ = wo_.z() > 0.0f ? 1.0f / pdf_denominator : 0.0f;
    if (sum > 0.0f) p_spec_ = ws / sum, p_sheen_ = wsh / sum, p_diffuse_ = wd / sum;
#endif
    else
        p_spec_ = 1.0f;
}

// The specular lobe's value (f, without the cosine) and its sampling pdf at wi.  The half
// vector is left unnormalised: with s = wo + wi, D's quadratic form of h = s / |s| is that of
// s over |s|^2, so D = d_scale |s|^4 / e(s)^2, and wo . h = |s| / 2 for unit wo and wi.  So
// D's quotient and Smith Lambda(wi)'s go in one SSE2 division, |s| and Lambda's root in
// square roots beside and after it, and the chain is division, square root, division (it
// was square root, division, division, division).  Every factor that depends on wo alone is
// set up in the constructor (D's 1/ax^2, 1/ay^2 and scale, the pdf's scale).
ClothBsdf::SpecTerms ClothBsdf::spec_terms(const V3& wi) const {
    const V3 sum = wo_ + wi;
    const float s2 = sum.squaredNorm();
    const float e = sqr(sum.x()) * lobes_.inv_ax2 + sqr(sum.y()) * lobes_.inv_ay2 + sqr(sum.z());
    const float t_num = sqr(lobes_.ax * wi.x()) + sqr(lobes_.ay * wi.y());
#if defined(__SSE2__)
    std::array<float, 4> q;
    _mm_storeu_ps(q.data(), _mm_div_ps(_mm_setr_ps(lobes_.d_scale * (s2 * s2), t_num, 0.0f, 0.0f),
                                       _mm_setr_ps(e * e, sqr(wi.z()), 1.0f, 1.0f)));
    const float d = q[0], t = q[1];  // GGX D, and Lambda(wi)'s tan^2 term
#else
    const float d = lobes_.d_scale * (s2 * s2) / (e * e), t = t_num / sqr(wi.z());
#endif
    const float lambda_i = 0.5f * (-1.0f + std::sqrt(1.0f + t));
    const float f =
        schlick(p_.f0, 0.5f * std::sqrt(s2)) * d / ((1.0f + lambda_o_ + lambda_i) * 4.0f * wo_.z() * wi.z());
    return {f, d * pdf_scale_};
}

// charlie_d(h.z) * neubelt_v as above, with the half vector's sin^2 from the unnormalised
// sum s = wo + wi, (s.x^2 + s.y^2) / |s|^2 (no square root), that quotient and V's in one
// SSE2 division, and D's exponent and scale from the lobes.
float ClothBsdf::sheen_d_v(const V3& wi) const {
    const V3 sum = wo_ + wi;
    const float across = sqr(sum.x()) + sqr(sum.y());
    const float no = wo_.z(), ni = wi.z();
#if defined(__SSE2__)
    std::array<float, 4> q;
    _mm_storeu_ps(q.data(), _mm_div_ps(_mm_setr_ps(across, 1.0f, 0.0f, 0.0f),
                                       _mm_setr_ps(across + sqr(sum.z()), 4.0f * (ni + no - ni * no), 1.0f, 1.0f)));
    const float sin2 = q[0], v = q[1];
#else
    const float sin2 = across / (across + sqr(sum.z())), v = neubelt_v(no, ni);
#endif
    return lobes_.sheen_d_scale * fast_pow_unit(sin2, lobes_.sheen_exponent) * v;
}

#if defined(__SSE2__)
// spec_terms of two directions, each lane spec_terms' operations in its order: D's and
// Lambda's quotients of both in one division, the four roots in one square root, the two
// values in one division.
void ClothBsdf::spec_terms2(const V3& wi_a, const V3& wi_b, SpecTerms* a, SpecTerms* b) const {
    const V3 sa = wo_ + wi_a, sb = wo_ + wi_b;
    const float s2a = sa.squaredNorm(), s2b = sb.squaredNorm();
    const float ea = sqr(sa.x()) * lobes_.inv_ax2 + sqr(sa.y()) * lobes_.inv_ay2 + sqr(sa.z());
    const float eb = sqr(sb.x()) * lobes_.inv_ax2 + sqr(sb.y()) * lobes_.inv_ay2 + sqr(sb.z());
    const float ta = sqr(lobes_.ax * wi_a.x()) + sqr(lobes_.ay * wi_a.y());
    const float tb = sqr(lobes_.ax * wi_b.x()) + sqr(lobes_.ay * wi_b.y());
    std::array<float, 4> q, root, f;
    _mm_storeu_ps(q.data(), _mm_div_ps(_mm_setr_ps(lobes_.d_scale * (s2a * s2a), lobes_.d_scale * (s2b * s2b), ta, tb),
                                       _mm_setr_ps(ea * ea, eb * eb, sqr(wi_a.z()), sqr(wi_b.z()))));
    _mm_storeu_ps(root.data(), _mm_sqrt_ps(_mm_setr_ps(1.0f + q[2], 1.0f + q[3], s2a, s2b)));
    const float lambda_a = 0.5f * (-1.0f + root[0]), lambda_b = 0.5f * (-1.0f + root[1]);
    _mm_storeu_ps(f.data(),
                  _mm_div_ps(_mm_setr_ps(schlick(p_.f0, 0.5f * root[2]) * q[0], schlick(p_.f0, 0.5f * root[3]) * q[1],
                                         0.0f, 0.0f),
                             _mm_setr_ps((1.0f + lambda_o_ + lambda_a) * 4.0f * wo_.z() * wi_a.z(),
                                         (1.0f + lambda_o_ + lambda_b) * 4.0f * wo_.z() * wi_b.z(), 1.0f, 1.0f)));
    *a = {f[0], q[0] * pdf_scale_};
    *b = {f[1], q[1] * pdf_scale_};
}
#else
void ClothBsdf::spec_terms2(const V3& wi_a, const V3& wi_b, SpecTerms* a, SpecTerms* b) const {
    *a = spec_terms(wi_a);
    *b = spec_terms(wi_b);
}
#endif

V3 ClothBsdf::eval_rest(const V3& wi, const SpecTerms* spec, float* pdf) const {
    V3 f = V3::Zero();
    float pd = 0.0f;
    if (spec) {
        f += V3::Constant(spec->f);
        pd += p_spec_ * spec->pdf;
    }
    if (lobes_.sheen_scale > 0.0f) {
        f += base_weight_ * sheen_d_v(wi) * p_.sheen;
        pd += p_sheen_ / (2.0f * kPiF);
    }
    f += diffuse_weight_ / kPiF * p_.diffuse;
    pd += p_diffuse_ * wi.z() / kPiF;
    *pdf = pd;
    return f * wi.z();
}

V3 ClothBsdf::eval(const V3& wi, float* pdf) const {
    *pdf = 0.0f;
    if (wi.z() <= 0.0f || wo_.z() <= 0.0f) return V3::Zero();
    if (p_spec_ > 0.0f || e_spec_ > 0.0f) {
        const SpecTerms spec = spec_terms(wi);
        return eval_rest(wi, &spec, pdf);
    }
    return eval_rest(wi, nullptr, pdf);
}

void ClothBsdf::eval2(const V3& wi_a, const V3& wi_b, V3* f_a, float* pdf_a, V3* f_b, float* pdf_b) const {
    const bool above_a = wi_a.z() > 0.0f && wo_.z() > 0.0f, above_b = wi_b.z() > 0.0f && wo_.z() > 0.0f;
    if (!(above_a && above_b) || !(p_spec_ > 0.0f || e_spec_ > 0.0f)) {
        *f_a = eval(wi_a, pdf_a);
        *f_b = eval(wi_b, pdf_b);
        return;
    }
    SpecTerms sa, sb;
    spec_terms2(wi_a, wi_b, &sa, &sb);
    *f_a = eval_rest(wi_a, &sa, pdf_a);
    *f_b = eval_rest(wi_b, &sb, pdf_b);
}

std::optional<V3> ClothBsdf::sample_direction(float u_lobe, float u1, float u2) const {
    if (wo_.z() <= 0.0f) return std::nullopt;
    V3 wi;
    if (u_lobe < p_spec_) {
        wi = reflect(wo_, sample_vndf(wo_, lobes_.ax, lobes_.ay, u1, u2));
    } else if (u_lobe < p_spec_ + p_sheen_) {
        wi = sample_uniform_hemisphere(u1, u2);
    } else {
        wi = sample_cosine_hemisphere(u1, u2);
    }
    if (wi.z() <= 1e-6f) return std::nullopt;
    return wi;
}

std::optional<BsdfSample> ClothBsdf::sample(float u_lobe, float u1, float u2) const {
    const std::optional<V3> wi = sample_direction(u_lobe, u1, u2);
    if (!wi) return std::nullopt;
    float pdf = 0.0f;
    const V3 fc = eval(*wi, &pdf);
    if (!(pdf > 0.0f)) return std::nullopt;
    return BsdfSample{*wi, fc / pdf, pdf};
}

V3 ClothBsdf::albedo() const {
    return V3::Constant(e_spec_) + base_weight_ * e_sheen_ * p_.sheen + diffuse_weight_ * p_.diffuse;
}

}  // namespace foldcast::render
