// Light sampling: the spherical-rectangle parametrization (render/src/spherical_rectangle.*)
// and the light sampler's pdfs, which MIS needs to agree with what it samples.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "light_sampler.hpp"
#include "spherical_rectangle.hpp"

namespace foldcast::render {
namespace {

struct Rect {
    Vec3f corner, ex, ey;
    float width, height;
};

// A 0.8 x 0.5 m soft box, tilted, seen from a point 0.6 m in front of it and off to the side.
const Rect kBox{Vec3f(-0.3f, 0.9f, 0.4f), Vec3f(1, 0, 0), Vec3f(0, 0.6f, 0.8f), 0.8f, 0.5f};
const Vec3f kFrom(0.5f, 0.2f, 0.1f);

// Solid angle by the midpoint rule over the rectangle's area: sum of cos / d^2 dA.
double solid_angle_by_quadrature(const Rect& r, const Vec3f& from, int steps) {
    const Eigen::Vector3d n = r.ex.cast<double>().cross(r.ey.cast<double>());
    const double da = double(r.width) * r.height / (double(steps) * steps);
    double sum = 0.0;
    for (int i = 0; i < steps; ++i)
        for (int j = 0; j < steps; ++j) {
            const Eigen::Vector3d q = r.corner.cast<double>() + (i + 0.5) / steps * r.width * r.ex.cast<double>() +
                                      (j + 0.5) / steps * r.height * r.ey.cast<double>();
            const Eigen::Vector3d d = q - from.cast<double>();
            sum += std::abs(d.dot(n)) / std::pow(d.norm(), 3) * da;
        }
    return sum;
}

TEST(SphericalRectangle, SolidAngleMatchesQuadrature) {
    const auto cone = SphericalRectangle::make(kFrom, kBox.corner, kBox.ex, kBox.ey, kBox.width, kBox.height);
    ASSERT_TRUE(cone.has_value());
    EXPECT_NEAR(cone->solid_angle(), solid_angle_by_quadrature(kBox, kFrom, 600), 1e-4);
}

TEST(SphericalRectangle, SamplesLieOnTheRectangle) {
    const auto cone = SphericalRectangle::make(kFrom, kBox.corner, kBox.ex, kBox.ey, kBox.width, kBox.height);
    ASSERT_TRUE(cone.has_value());
    const Vec3f n = kBox.ex.cross(kBox.ey);
    for (int i = 0; i < 32; ++i)
        for (int j = 0; j < 32; ++j) {
            const Vec3f q = cone->sample((i + 0.5f) / 32, (j + 0.5f) / 32) - kBox.corner;
            EXPECT_NEAR(q.dot(n), 0.0f, 1e-5f);
            EXPECT_GE(q.dot(kBox.ex), -1e-5f);
            EXPECT_LE(q.dot(kBox.ex), kBox.width + 1e-5f);
            EXPECT_GE(q.dot(kBox.ey), -1e-5f);
            EXPECT_LE(q.dot(kBox.ey), kBox.height + 1e-5f);
        }
}

// Uniform in solid angle: stratified (u, v) put into each of 4 x 4 tiles of the rectangle the
// share of samples that the tile's own solid angle is of the whole.
TEST(SphericalRectangle, SamplesAreUniformInSolidAngle) {
    const auto cone = SphericalRectangle::make(kFrom, kBox.corner, kBox.ex, kBox.ey, kBox.width, kBox.height);
    ASSERT_TRUE(cone.has_value());
    constexpr int kTiles = 4, kSide = 256;
    std::vector<double> count(kTiles * kTiles, 0.0);
    for (int i = 0; i < kSide; ++i)
        for (int j = 0; j < kSide; ++j) {
            const Vec3f q = cone->sample((i + 0.5f) / kSide, (j + 0.5f) / kSide) - kBox.corner;
            const int a = std::min(kTiles - 1, int(q.dot(kBox.ex) / kBox.width * kTiles));
            const int b = std::min(kTiles - 1, int(q.dot(kBox.ey) / kBox.height * kTiles));
            count[std::size_t(b * kTiles + a)] += 1.0 / (kSide * kSide);
        }
    for (int a = 0; a < kTiles; ++a)
        for (int b = 0; b < kTiles; ++b) {
            const Vec3f corner =
                kBox.corner + (kBox.width * a / kTiles) * kBox.ex + (kBox.height * b / kTiles) * kBox.ey;
            const auto tile =
                SphericalRectangle::make(kFrom, corner, kBox.ex, kBox.ey, kBox.width / kTiles, kBox.height / kTiles);
            ASSERT_TRUE(tile.has_value());
            EXPECT_NEAR(count[std::size_t(b * kTiles + a)], tile->solid_angle() / cone->solid_angle(), 2e-3)
                << "tile " << a << "," << b;
        }
}

TEST(SphericalRectangle, NothingFromThePlaneOrTooFar) {
    EXPECT_FALSE(
        SphericalRectangle::make(kBox.corner + 0.1f * kBox.ex, kBox.corner, kBox.ex, kBox.ey, kBox.width, kBox.height)
            .has_value());
    const Vec3f far = kBox.corner + 1e4f * kBox.ex.cross(kBox.ey);
    EXPECT_FALSE(SphericalRectangle::make(far, kBox.corner, kBox.ex, kBox.ey, kBox.width, kBox.height).has_value());
}

// MIS: the pdf a BSDF-sampled ray that reaches a light is given is the one light sampling
// would have used for that point, near the light (solid angle) and far away (area).
TEST(LightSampler, PdfAgreesWithSample) {
    AreaLight box;
    box.position = Vec3f(0.0f, 1.0f, 1.0f);
    box.target = Vec3f(0.0f, 0.0f, 0.0f);
    box.width_m = 0.8f;
    box.height_m = 0.5f;
    box.radiance = Vec3f(5.0f, 5.0f, 5.0f);
    const LightSampler lights({box}, V3(0.1f, 0.1f, 0.1f));
    for (const Vec3f& p : {Vec3f(0.1f, 0.2f, 0.1f), Vec3f(0.4f, -0.3f, 0.5f), Vec3f(0.0f, -300.0f, -300.0f)}) {
        const Vec3f n = (box.position - p).normalized();
        const LightChoice choice = lights.choose(p, n);
        int checked = 0;
        for (int i = 0; i < 8; ++i) {
            const auto s = lights.sample(choice, p, n, n.unitOrthogonal(), (i + 0.5f) / 8 * choice.prob[0], 0.37f);
            if (!s || !std::isfinite(s->distance)) continue;
            const Vec3f q = p + s->distance * s->wi;
            EXPECT_NEAR(lights.pdf(choice, 0, p, q) / s->pdf, 1.0f, 1e-3f);
            ++checked;
        }
        EXPECT_GT(checked, 0);
    }
}

// A dim environment beside a bright area light is left to BSDF sampling (no light samples,
// so MIS gives its BSDF-sampled hits full weight); where the light is out of sight, or the
// sky is bright, the environment keeps its light samples.
TEST(LightSampler, DimEnvironmentIsLeftToBsdfSampling) {
    AreaLight box;
    box.position = Vec3f(0.0f, 1.0f, 1.0f);
    box.target = Vec3f(0.0f, 0.0f, 0.0f);
    box.radiance = Vec3f(20.0f, 20.0f, 20.0f);
    const LightSampler dim({box}, V3(0.02f, 0.02f, 0.02f));
    const Vec3f facing = (box.position - Vec3f::Zero()).normalized();
    const LightChoice lit = dim.choose(Vec3f::Zero(), facing);
    EXPECT_EQ(lit.prob[1], 0.0f);
    EXPECT_FLOAT_EQ(lit.prob[0], 1.0f);
    EXPECT_EQ(dim.environment_pdf(lit, facing, facing), 0.0f);
    const LightChoice behind = dim.choose(Vec3f(0.0f, 2.0f, 2.0f), facing);  // behind the one-sided light
    EXPECT_FLOAT_EQ(behind.prob[1], 1.0f);
    const LightSampler bright({box}, V3(5.0f, 5.0f, 5.0f));
    EXPECT_GT(bright.choose(Vec3f::Zero(), facing).prob[1], 0.25f);
}

}  // namespace
}  // namespace foldcast::render
