// The cloth BSDF creates no energy: its directional albedo, integrated by Monte Carlo with
// its own sampling, stays at or below 1 and reaches 1 for white non-absorbing materials.
#include <gtest/gtest.h>

#include <cmath>

#include "cloth_bsdf.hpp"
#include "random_stream.hpp"

namespace foldcast::render {
namespace {

V3 albedo_by_sampling(const BsdfParams& p, float mu, int n = 200000) {
    const V3 wo(std::sqrt(1.0f - mu * mu), 0.0f, mu);
    const ClothBsdf bsdf(p, wo);
    RandomStream rng(42, 7, 0);
    V3 sum = V3::Zero();
    for (int i = 0; i < n; ++i) {
        BsdfSample s;
        const float a = rng.next(), b = rng.next(), c = rng.next();
        if (bsdf.sample(a, b, c, &s)) sum += s.weight;
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

TEST(ClothBsdf, EvalAgreesWithSampleWeight) {
    BsdfParams p;
    p.diffuse = V3(0.5f, 0.4f, 0.3f);
    p.sheen = V3::Constant(0.5f);
    p.roughness = 0.4f;
    p.anisotropy = 0.5f;
    const ClothBsdf bsdf(p, V3(0.6f, 0.0f, 0.8f));
    RandomStream rng(1, 2, 3);
    for (int i = 0; i < 100; ++i) {
        BsdfSample s;
        if (!bsdf.sample(rng.next(), rng.next(), rng.next(), &s)) continue;
        float pdf = 0.0f;
        const V3 fc = bsdf.eval(s.wi, &pdf);
        EXPECT_NEAR(pdf, s.pdf, 1e-4f * pdf);
        EXPECT_TRUE((fc / pdf - s.weight).norm() < 1e-4f);
    }
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
