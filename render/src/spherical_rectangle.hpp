#pragma once
// Uniform sampling of the solid angle a rectangle subtends at a point (Urena, Conty and Kulla,
// "An Area-Preserving Parametrization for Spherical Rectangles", EGSR 2013): the light's
// points are drawn with density 1 / solid angle in directions, so the falloff 1/d^2 and the
// light's cosine no longer scatter the estimate as they do with points drawn uniformly over
// its area (a soft box close to the cloth covers a wide cone).
#include <optional>

#include <Eigen/Geometry>

#include "foldcast/core/mesh.hpp"

namespace foldcast::render {

class SphericalRectangle {
public:
    // The rectangle corner + a ex + b ey, a in [0, width], b in [0, height] (ex, ey unit and
    // orthogonal) seen from `from`; nothing when it subtends no measurable solid angle
    // (`from` in its plane, or too far for the parametrization to be accurate).
    static std::optional<SphericalRectangle> make(const Vec3f& from, const Vec3f& corner, const Vec3f& ex,
                                                  const Vec3f& ey, float width, float height);

    float solid_angle() const { return solid_angle_; }
    // The point on the rectangle for (u, v) in [0, 1)^2; uniform in solid angle.
    Vec3f sample(float u, float v) const;

    // Below this solid angle (steradians) make() gives up: area sampling is as good there,
    // and single precision's cancellation error (~1e-6 sr) stays under 0.1 % above it.
    static constexpr float kMinSolidAngle = 1e-3f;

private:
    Vec3f origin_, x_, y_, z_;
    float x0_ = 0, x1_ = 0, y0_ = 0, y1_ = 0, z0_ = 0;
    float b0_ = 0, b1_ = 0, k_ = 0, solid_angle_ = 0;
    float one_minus_b0sq_ = 0;
};

}  // namespace foldcast::render
