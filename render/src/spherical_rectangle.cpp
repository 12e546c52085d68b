// Urena, Conty and Kulla 2013, section 3; in double precision, which the parametrization
// needs for rectangles far away or seen at a grazing angle.
#include "spherical_rectangle.hpp"

#include <algorithm>
#include <cmath>

namespace foldcast::render {

std::optional<SphericalRectangle> SphericalRectangle::make(const Vec3f& from, const Vec3f& corner, const Vec3f& ex,
                                                           const Vec3f& ey, float width, float height) {
    SphericalRectangle r;
    r.origin_ = from.cast<double>();
    r.x_ = ex.cast<double>();
    r.y_ = ey.cast<double>();
    r.z_ = r.x_.cross(r.y_);
    const Eigen::Vector3d d = corner.cast<double>() - r.origin_;
    r.z0_ = d.dot(r.z_);
    if (r.z0_ > 0.0) {  // the local frame's z points away from the rectangle
        r.z_ = -r.z_;
        r.z0_ = -r.z0_;
    }
    if (!(std::abs(r.z0_) > 1e-9)) return std::nullopt;
    r.x0_ = d.dot(r.x_);
    r.y0_ = d.dot(r.y_);
    r.x1_ = r.x0_ + width;
    r.y1_ = r.y0_ + height;
    const Eigen::Vector3d v00(r.x0_, r.y0_, r.z0_), v01(r.x0_, r.y1_, r.z0_), v10(r.x1_, r.y0_, r.z0_),
        v11(r.x1_, r.y1_, r.z0_);
    const Eigen::Vector3d n0 = v00.cross(v10).normalized(), n1 = v10.cross(v11).normalized(),
                          n2 = v11.cross(v01).normalized(), n3 = v01.cross(v00).normalized();
    const auto angle = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
        return std::acos(std::clamp(-a.dot(b), -1.0, 1.0));
    };
    const double g0 = angle(n0, n1), g1 = angle(n1, n2), g2 = angle(n2, n3), g3 = angle(n3, n0);
    r.b0_ = n0.z();
    r.b1_ = n2.z();
    r.k_ = 2.0 * M_PI - g2 - g3;
    r.solid_angle_ = g0 + g1 - r.k_;
    if (!(r.solid_angle_ > kMinSolidAngle)) return std::nullopt;
    return r;
}

Vec3f SphericalRectangle::sample(float u, float v) const {
    // The x of the sample: the solid angle left of it is u times the whole.
    const double au = double(u) * solid_angle_ + k_;
    const double fu = (std::cos(au) * b0_ - b1_) / std::sin(au);
    double cu = (fu > 0.0 ? 1.0 : -1.0) / std::sqrt(fu * fu + b0_ * b0_);
    cu = std::clamp(cu, -1.0, 1.0);
    const double xu = std::clamp(-(cu * z0_) / std::max(1e-12, std::sqrt(1.0 - cu * cu)), x0_, x1_);
    // Its y: uniform in the projected height of that column.
    const double dist = std::sqrt(xu * xu + z0_ * z0_);
    const double h0 = y0_ / std::sqrt(dist * dist + y0_ * y0_), h1 = y1_ / std::sqrt(dist * dist + y1_ * y1_);
    const double hv = h0 + double(v) * (h1 - h0), hv2 = hv * hv;
    const double yv = hv2 < 1.0 - 1e-12 ? std::clamp(hv * dist / std::sqrt(1.0 - hv2), y0_, y1_) : y1_;
    return (origin_ + xu * x_ + yv * y_ + z0_ * z_).cast<float>();
}

}  // namespace foldcast::render
