#pragma once
// The camera as the integrator uses it: pixel (continuous, y down) -> ray.
#include <Eigen/Geometry>
#include <cmath>

#include "foldcast/render/render.hpp"
#include "foldcast/core/math.hpp"
#include "vec3_div.hpp"

namespace foldcast::render {

class CameraModel {
public:
    CameraModel(const Camera& camera, int width, int height)
        : origin_(camera.position),
          width_(width),
          height_(height),
          aperture_(static_cast<float>(camera.aperture_m)),
          focus_(static_cast<float>(camera.focus_distance_m)) {
        forward_ = (camera.target - camera.position).normalized();
        right_ = forward_.cross(camera.up).normalized();
        up_ = right_.cross(forward_);
        tan_y_ = static_cast<float>(std::tan(camera.fov_deg * 0.5 * kPi / 180.0));
        tan_x_ = tan_y_ * static_cast<float>(width) / static_cast<float>(height);
        x_scale_ = 2.0f / static_cast<float>(width);
        y_scale_ = 2.0f / static_cast<float>(height);
    }

    // Direction through pixel position (px, py) and the lens sample (lu, lv) in [0,1)^2.
    void ray(float px, float py, float lu, float lv, Vec3f* origin, Vec3f* direction) const {
        // 2 / width and 2 / height kept from the constructor: no division per camera ray.
        const float sx = (px * x_scale_ - 1.0f) * tan_x_;
        const float sy = (1.0f - py * y_scale_) * tan_y_;
        Vec3f d = (forward_ + sx * right_ + sy * up_);
        if (aperture_ <= 0.0f) {
            *origin = origin_;
            *direction = normalized3(d);  // Eigen's normalized(), its three divisions in one
            return;
        }
        // Thin lens: uniform disc (concentric-free polar mapping is fine for a round bokeh).
        const float r = 0.5f * aperture_ * std::sqrt(lu);
        const float phi = 6.2831853f * lv;
        const Vec3f lens = r * std::cos(phi) * right_ + r * std::sin(phi) * up_;
        const Vec3f focus_point = origin_ + d * focus_;  // d has unit forward component
        *origin = origin_ + lens;
        *direction = (focus_point - *origin).normalized();
    }
    // The pixel position (px, py) a world point projects to through the lens centre (the
    // inverse of ray() with a centred lens sample); false behind the camera.
    bool project(const Vec3f& point, float* px, float* py) const {
        const Vec3f d = point - origin_;
        const float z = d.dot(forward_);
        if (z <= 0.0f) return false;
        *px = (d.dot(right_) / (z * tan_x_) + 1.0f) * 0.5f * static_cast<float>(width_);
        *py = (1.0f - d.dot(up_) / (z * tan_y_)) * 0.5f * static_cast<float>(height_);
        return true;
    }
    // Whether ray() reads its lens sample (a thin lens; a pinhole ignores it).
    bool has_lens() const { return aperture_ > 0.0f; }
    const Vec3f& forward() const { return forward_; }
    const Vec3f& position() const { return origin_; }
    // Cone spread of one pixel (radians), for texture footprints.
    float pixel_angle() const { return 2.0f * tan_y_ / static_cast<float>(height_); }

private:
    Vec3f origin_, forward_, right_, up_;
    int width_, height_;
    float tan_x_ = 0.0f, tan_y_ = 0.0f;
    float x_scale_ = 0.0f, y_scale_ = 0.0f;
    float aperture_ = 0.0f, focus_ = 1.0f;
};

}  // namespace foldcast::render
