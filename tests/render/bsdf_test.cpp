// The cloth BSDF creates no energy: its directional albedo, integrated by Monte Carlo with
// its own sampling, stays at or below 1 and reaches 1 for white non-absorbing materials; and
// its sampling draws directions from the pdf it reports (chi-square).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cloth_bsdf.hpp"
#include "foldcast/core/math.hpp"
#include "foldcast/core/sampling.hpp"
#include "foldcast/looks/looks.hpp"
#include "garment_surface.hpp"
#include "random_stream.hpp"

namespace foldcast::render {
namespace {

V3 albedo_by_sampling(const BsdfParams& p, float mu, int n = 200000) {
    const V3 wo(std::sqrt(1.0f - mu * mu), 0.0f, mu);
    const ClothBsdf bsdf(p, wo);
    RandomStream rng(42, 7, 0);
    V3 sum = V3::Zero();
    for (int i = 0; i < n; ++i) {
        const float a = rng.next(), b = rng.next(), c = rng.next();
        if (const auto s = bsdf.sample(a, b, c)) sum += s->weight;
    }
    return sum / static_cast<float>(n);
}

TEST(ClothBsdf, WhiteNonAbsorbingMaterialReflectsEverything) {
    for (const float rough : {0.3f, 0.6f, 0.9f})
        for (const float mu : {0.15f, 0.5f, 0.95f}) {
            BsdfParams p;
            p.diffuse = V3::Ones();
            p.sheen = V3::Ones();
            p.sheen_roughness = 0.4f;
            p.f0 = 0.04f;
            p.roughness = rough;
            const V3 a = albedo_by_sampling(p, mu);
            EXPECT_NEAR(a.x(), 1.0f, 0.01f) << "roughness " << rough << " mu " << mu;
        }
}

TEST(ClothBsdf, AnisotropicAndShinyLobesStayBelowOne) {
    BsdfParams p;
    p.diffuse = V3::Ones();
    p.sheen = V3::Ones();
    p.f0 = 0.08f;
    p.roughness = 0.35f;
    p.anisotropy = 0.8f;
    for (const float mu : {0.1f, 0.4f, 0.9f}) {
        const V3 a = albedo_by_sampling(p, mu);
        // The albedo tables are isotropic: anisotropy costs a little accuracy, not energy.
        EXPECT_LT(a.maxCoeff(), 1.02f) << "mu " << mu;
        EXPECT_GT(a.minCoeff(), 0.95f) << "mu " << mu;
    }
}

// Chi-square goodness of fit of sample() against the pdf eval() reports, as pbrt-v4's and
// Mitsuba's BSDF tests do: directions binned over (cos theta, phi), expected counts from
// integrating the pdf over each bin, sparse bins pooled, and the fit rejected when the
// p-value falls below 1% (Sidak-corrected for the number of fits).  A sampler that does not
// draw from the pdf it reports (a lobe mis-weighted, a missing Jacobian, a pdf for another
// mapping) biases every MIS weight and fails here.
constexpr int kThetaBins = 24, kPhiBins = 48;

// Regularised upper incomplete gamma Q(a, x) (Numerical Recipes' series / continued fraction).
double gamma_q(double a, double x) {
    if (x <= 0.0) return 1.0;
    const double log_prefix = -x + a * std::log(x) - std::lgamma(a);
    if (x < a + 1.0) {
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < 100000 && std::abs(term) > std::abs(sum) * 1e-15; ++n) sum += term *= x / (a + n);
        return 1.0 - sum * std::exp(log_prefix);
    }
    double b = x + 1.0 - a, c = 1e300, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        d = std::abs(d) < 1e-300 ? 1e-300 : d;
        c = b + an / c;
        c = std::abs(c) < 1e-300 ? 1e-300 : c;
        d = 1.0 / d;
        const double del = d * c;
        h *= del;
        if (std::abs(del - 1.0) < 1e-15) break;
    }
    return std::exp(log_prefix) * h;
}

V3 direction(double cos_theta, double phi) {
    const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    return V3(static_cast<float>(s * std::cos(phi)), static_cast<float>(s * std::sin(phi)),
              static_cast<float>(cos_theta));
}

// The p-value of the sampled histogram against the pdf.
double chi2_p_value(const ClothBsdf& bsdf, int samples, std::uint64_t seed) {
    const int bins = kThetaBins * kPhiBins;
    std::vector<double> observed(bins, 0.0), expected(bins, 0.0);
    RandomStream rng(seed, 0, 0);
    for (int i = 0; i < samples; ++i) {
        const float a = rng.next(), b = rng.next(), c = rng.next();
        const auto s = bsdf.sample(a, b, c);
        if (!s) continue;
        const double z = std::clamp(static_cast<double>(s->wi.z()), 0.0, 1.0);
        double phi = std::atan2(static_cast<double>(s->wi.y()), static_cast<double>(s->wi.x()));
        if (phi < 0.0) phi += 2.0 * kPi;
        const int ti = std::min(kThetaBins - 1, static_cast<int>(z * kThetaBins));
        const int pi = std::min(kPhiBins - 1, static_cast<int>(phi / (2.0 * kPi) * kPhiBins));
        observed[ti * kPhiBins + pi] += 1.0;
    }
    // Solid angle is dz dphi: integrate the pdf over each bin on a 12x12 midpoint grid.
    constexpr int kSub = 12;
    const double dz = 1.0 / kThetaBins, dphi = 2.0 * kPi / kPhiBins;
    for (int ti = 0; ti < kThetaBins; ++ti)
        for (int pi = 0; pi < kPhiBins; ++pi) {
            double sum = 0.0;
            for (int sz = 0; sz < kSub; ++sz)
                for (int sp = 0; sp < kSub; ++sp) {
                    const double z = (ti + (sz + 0.5) / kSub) * dz, phi = (pi + (sp + 0.5) / kSub) * dphi;
                    float pdf = 0.0f;
                    bsdf.eval(direction(z, phi), &pdf);
                    sum += pdf;
                }
            expected[ti * kPhiBins + pi] = sum / (kSub * kSub) * dz * dphi * samples;
        }
    // Pool bins expecting fewer than 5 samples into one (pbrt-v4's rule).
    double chi2 = 0.0, pooled_obs = 0.0, pooled_exp = 0.0;
    int dof = -1;
    for (int i = 0; i < bins; ++i) {
        if (expected[i] < 5.0) {
            pooled_obs += observed[i];
            pooled_exp += expected[i];
            continue;
        }
        chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
        ++dof;
    }
    if (pooled_exp > 0.0) {
        chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
        ++dof;
    } else if (pooled_obs > 0.0) {
        return 0.0;  // samples where the pdf says none can be
    }
    return gamma_q(0.5 * dof, 0.5 * chi2);
}

struct Case {
    std::string name;
    BsdfParams params;
};

std::vector<Case> chi2_cases() {
    std::vector<Case> cases;
    BsdfParams diffuse;
    diffuse.diffuse = V3(0.7f, 0.6f, 0.5f);
    cases.push_back({"diffuse", diffuse});
    BsdfParams sheen;
    sheen.diffuse = V3::Constant(0.05f);
    sheen.sheen = V3::Ones();
    sheen.sheen_roughness = 0.3f;
    cases.push_back({"sheen", sheen});
    BsdfParams glossy;
    glossy.diffuse = V3::Zero();
    glossy.f0 = 0.9f;
    glossy.roughness = 0.35f;
    cases.push_back({"ggx", glossy});
    BsdfParams aniso = glossy;
    aniso.anisotropy = 0.8f;
    cases.push_back({"ggx_anisotropic", aniso});
    // Every look of the library as the garment shader gives it, on and between threads.
    const looks::Library library = looks::Library::load_default();
    for (const std::string& name : library.names()) {
        const GarmentShader shader(library.get(name).appearance);
        cases.push_back({name, shader.shade(Eigen::Vector2f(0.0123f, 0.0456f), 1e-4f).bsdf});
    }
    return cases;
}

TEST(ClothBsdf, SampledDirectionsFollowThePdfChiSquare) {
    const std::vector<Case> cases = chi2_cases();
    const std::vector<float> view_cos = {0.2f, 0.6f, 0.95f};
    const std::vector<float> view_phi = {0.0f, 1.1f};
    const int fits = static_cast<int>(cases.size() * view_cos.size() * view_phi.size());
    const double threshold = 1.0 - std::pow(1.0 - 0.01, 1.0 / fits);  // Sidak
    std::uint64_t seed = 1;
    for (const Case& c : cases)
        for (const float mu : view_cos)
            for (const float phi : view_phi) {
                const float s = std::sqrt(1.0f - mu * mu);
                const ClothBsdf bsdf(c.params, V3(s * std::cos(phi), s * std::sin(phi), mu));
                const double p = chi2_p_value(bsdf, 100000, seed++);
                EXPECT_GT(p, threshold) << c.name << " at cos(theta_o) " << mu << ", phi_o " << phi;
            }
}

// The test above must be able to fail: a sampler whose pdf is off by a smooth factor
// (here the pdf reported for a cosine-weighted sampler is the uniform one) is rejected.
TEST(ClothBsdf, ChiSquareRejectsAWrongPdf) {
    struct WrongPdf {
        static double p_value(int samples) {
            std::vector<double> observed(kThetaBins, 0.0);
            RandomStream rng(9, 9, 9);
            for (int i = 0; i < samples; ++i) {
                const V3 w = sample_cosine_hemisphere(rng.next(), rng.next());
                observed[std::min(kThetaBins - 1, static_cast<int>(w.z() * kThetaBins))] += 1.0;
            }
            double chi2 = 0.0;
            for (int i = 0; i < kThetaBins; ++i) {
                const double expected = static_cast<double>(samples) / kThetaBins;  // uniform in z
                chi2 += (observed[i] - expected) * (observed[i] - expected) / expected;
            }
            return gamma_q(0.5 * (kThetaBins - 1), 0.5 * chi2);
        }
    };
    EXPECT_LT(WrongPdf::p_value(20000), 1e-6);
    EXPECT_NEAR(gamma_q(1.0, 2.0), std::exp(-2.0), 1e-12);  // Q(1, x) = e^-x
    EXPECT_NEAR(gamma_q(5.0, 4.0), 0.628836935, 1e-8);      // tabulated
}

TEST(ClothBsdf, DarkerDiffuseReflectsLess) {
    BsdfParams p;
    p.diffuse = V3::Constant(0.2f);
    const V3 a = albedo_by_sampling(p, 0.7f, 50000);
    EXPECT_LT(a.x(), 0.3f);
    EXPECT_GT(a.x(), 0.2f);
}

}  // namespace
}  // namespace foldcast::render
