#pragma once
// The cloth BSDF: Lambert diffuse + Charlie sheen (Estevez & Kulla 2017) + anisotropic GGX
// specular, layered so energy is never created: each layer passes on only what it did not
// reflect, using tabulated directional albedos (Kulla & Conty 2017 style):
//
//   f = f_spec + (1 - E_spec(mu_o)) * [ f_sheen + (1 - s E_sheen(mu_o)) * rho / pi ]
//
// where E_* are the lobes' directional albedos and s = max(sheen colour).  With rho = 1 the
// albedo is exactly 1 for every view direction (up to the tables' accuracy): the white
// furnace test checks that.  All vectors are in the local shading frame (n = +z).
#include <Eigen/Core>
#include <optional>

namespace foldcast::render {

using V3 = Eigen::Vector3f;

struct BsdfParams {
    V3 diffuse{0.5f, 0.5f, 0.5f};  // Lambert albedo
    V3 sheen{0.0f, 0.0f, 0.0f};    // sheen colour
    float sheen_roughness = 0.5f;  // [0,1]
    float f0 = 0.04f;              // Schlick normal-incidence reflectance (dielectric)
    float roughness = 0.5f;        // GGX perceptual roughness [0,1], alpha = r^2
    float anisotropy = 0.0f;       // [0,1): stretches the highlight along the local x axis
};

// What the lobes take from the parameters alone, whatever the view: set up once per material
// (Materials) rather than at every path vertex, where it was a third of the constructor's
// square roots and divisions.
struct BsdfLobes {
    BsdfLobes() = default;
    explicit BsdfLobes(const BsdfParams& params);
    float roughness = 0.5f, sheen_roughness = 0.5f;  // clamped to their ranges
    float ax = 0.0f, ay = 0.0f;                      // GGX alphas along x and y
    float inv_ax2 = 0.0f, inv_ay2 = 0.0f;            // 1 / alpha^2 along x and y, for D
    float d_scale = 0.0f;                            // 1 / (pi ax ay): GGX D = d_scale / e^2
    bool isotropic = true;                           // ax == ay: the view's roughness is the lobe's
    float table_roughness = 0.0f;                    // sqrt(sqrt(ax ay)): the albedo table's at any
                                                     // view of an isotropic lobe, and looking down
    float sheen_alpha = 0.0f;
    float sheen_exponent = 0.0f, sheen_d_scale = 0.0f;  // Charlie D = scale sin(h)^(2 exponent)
    float sheen_scale = 0.0f;  // s = max(sheen colour)
    float sheen_luminance = 0.0f;
};

struct BsdfSample {
    V3 wi;
    V3 weight;  // f * cos / pdf
    float pdf = 0.0f;
};

class ClothBsdf {
public:
    ClothBsdf(const BsdfParams& params, const V3& wo) : ClothBsdf(params, BsdfLobes(params), wo) {}
    // The same with the lobes' set-up done beforehand (`lobes` must be BsdfLobes(params)).
    ClothBsdf(const BsdfParams& params, const BsdfLobes& lobes, const V3& wo);

    // f(wo, wi) * cos(wi) and the sampling pdf of wi (solid angle).  Zero below the horizon.
    V3 eval(const V3& wi, float* pdf) const;
    // Samples wi from the lobe mixture with three uniforms; nothing if no direction.
    std::optional<BsdfSample> sample(float u_lobe, float u1, float u2) const;
    // The direction sample() draws (before it evaluates there); nothing if none.
    std::optional<V3> sample_direction(float u_lobe, float u1, float u2) const;
    // eval at two directions at once (a vertex's light sample and its BSDF sample): both
    // specular terms in SSE2 lanes, so that their divisions and square roots overlap.  The
    // same floats as two eval calls.
    void eval2(const V3& wi_a, const V3& wi_b, V3* f_a, float* pdf_a, V3* f_b, float* pdf_b) const;
    // Directional albedo estimate (for Russian roulette and the albedo AOV).
    V3 albedo() const;

private:
    struct SpecTerms {
        float f, pdf;
    };
    SpecTerms spec_terms(const V3& wi) const;
    void spec_terms2(const V3& wi_a, const V3& wi_b, SpecTerms* a, SpecTerms* b) const;
    // eval's terms other than the specular ones, added to spec's.
    V3 eval_rest(const V3& wi, const SpecTerms* spec, float* pdf) const;
    float sheen_d_v(const V3& wi) const;

    BsdfParams p_;     // its roughness and sheen roughness unclamped: lobes_ has the clamped ones
    BsdfLobes lobes_;  // what does not depend on wo
    V3 wo_;
    float lambda_o_ = 0.0f;   // Smith Lambda of wo, used by every evaluation
    float pdf_scale_ = 0.0f;  // 1 / (4 cos_o (1 + Lambda_o)): the VNDF pdf of a reflection is D times it
    float e_spec_ = 0.0f;     // E_spec(mu_o) including Fresnel
    float e_sheen_ = 0.0f;         // E_sheen(mu_o) for a white sheen
    float base_weight_ = 1.0f;     // 1 - E_spec
    float diffuse_weight_ = 1.0f;  // (1 - E_spec)(1 - s E_sheen)
    float p_spec_ = 0.0f, p_sheen_ = 0.0f, p_diffuse_ = 0.0f;
};

// w mirrored about the unit vector n (a microfacet normal, or a surface's shading normal).
inline V3 reflect(const V3& w, const V3& n) { return 2.0f * w.dot(n) * n - w; }

// Tabulated albedos (exposed for tests).
float ggx_albedo(float mu, float roughness, float f0);
float sheen_albedo(float mu, float sheen_roughness);

}  // namespace foldcast::render
