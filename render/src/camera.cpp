// Camera placement: manual (position/target) or auto-framed around the garment.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "foldcast/render/render.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast::render {
namespace {

constexpr double kDegToRad = kPi / 180.0;

struct ProjectedBox {
    double min_x = 1e30, max_x = -1e30, min_y = 1e30, max_y = -1e30;  // in [-1,1] NDC
};

// NDC of every point for a camera at `pos` looking along `forward`.
ProjectedBox project_all(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& pos,
                         const Eigen::Vector3d& forward, double tan_x, double tan_y) {
    const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitY()).normalized();
    const Eigen::Vector3d up = right.cross(forward);
    ProjectedBox box;
    for (const auto& p : points) {
        const Eigen::Vector3d d = p - pos;
        const double z = std::max(1e-6, d.dot(forward));
        const double x = d.dot(right) / (z * tan_x);
        const double y = d.dot(up) / (z * tan_y);
        box.min_x = std::min(box.min_x, x);
        box.max_x = std::max(box.max_x, x);
        box.min_y = std::min(box.min_y, y);
        box.max_y = std::max(box.max_y, y);
    }
    return box;
}

}  // namespace

Camera frame_camera(const CameraSpec& spec, const std::vector<std::vector<Vec3f>>& fit_frames, double aspect) {
    Camera cam;
    cam.fov_deg = spec.fov_deg;
    cam.aperture_m = spec.aperture_m;
    if (!spec.auto_frame) {
        cam.position = spec.position;
        cam.target = spec.target;
        cam.focus_distance_m =
            spec.focus_distance_m > 0.0 ? spec.focus_distance_m : (spec.target - spec.position).norm();
        return cam;
    }
    // Every point of every frame, thinned to at most ~50k for speed (the box barely changes).
    std::size_t total = 0;
    for (const auto& f : fit_frames) total += f.size();
    const std::size_t stride = std::max<std::size_t>(1, total / 50000);
    std::vector<Eigen::Vector3d> points;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e30), hi = Eigen::Vector3d::Constant(-1e30);
    std::size_t k = 0;
    for (const auto& f : fit_frames)
        for (const Vec3f& p : f) {
            lo = lo.cwiseMin(p.cast<double>());
            hi = hi.cwiseMax(p.cast<double>());
            if (k++ % stride == 0) points.push_back(p.cast<double>());
        }
    if (points.empty()) return cam;
    Eigen::Vector3d target = 0.5 * (lo + hi);
    const double az = spec.azimuth_deg * kDegToRad, el = spec.elevation_deg * kDegToRad;
    const Eigen::Vector3d back(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
    const Eigen::Vector3d forward = -back;
    const double tan_y = std::tan(0.5 * spec.fov_deg * kDegToRad);
    const double tan_x = tan_y * aspect;
    double distance = std::max(1e-3, (hi - lo).norm() / tan_y);
    // Fixed-point iteration: projected size scales ~1/distance; re-centre by shifting the
    // camera parallel to the image plane.  Converges in a handful of steps.
    const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitY()).normalized();
    const Eigen::Vector3d up = right.cross(forward);
    for (int it = 0; it < 40; ++it) {
        const Eigen::Vector3d pos = target + distance * back;
        const ProjectedBox box = project_all(points, pos, forward, tan_x, tan_y);
        const double share = std::max(box.max_x - box.min_x, box.max_y - box.min_y) * 0.5;
        const double cx = 0.5 * (box.min_x + box.max_x), cy = 0.5 * (box.min_y + box.max_y);
        target += right * (cx * distance * tan_x) + up * (cy * distance * tan_y);
        const double ratio = share / spec.frame_share;
        distance *= ratio;
        if (std::abs(ratio - 1.0) < 1e-6 && std::abs(cx) < 1e-6 && std::abs(cy) < 1e-6) break;
    }
    cam.target = target.cast<float>();
    cam.position = (target + distance * back).cast<float>();
    cam.focus_distance_m = spec.focus_distance_m > 0.0 ? spec.focus_distance_m : distance;
    return cam;
}

bool project(const Camera& camera, int width, int height, const Vec3f& point, Eigen::Vector2d* pixel) {
    const Eigen::Vector3d pos = camera.position.cast<double>();
    const Eigen::Vector3d forward = (camera.target - camera.position).cast<double>().normalized();
    const Eigen::Vector3d right = forward.cross(camera.up.cast<double>()).normalized();
    const Eigen::Vector3d up = right.cross(forward);
    const Eigen::Vector3d d = point.cast<double>() - pos;
    const double z = d.dot(forward);
    if (z <= 0.0) return false;
    const double tan_y = std::tan(0.5 * camera.fov_deg * kDegToRad);
    const double tan_x = tan_y * width / height;
    const double x = d.dot(right) / (z * tan_x), y = d.dot(up) / (z * tan_y);
    *pixel = Eigen::Vector2d((x + 1.0) * 0.5 * width, (1.0 - y) * 0.5 * height);
    return true;
}

}  // namespace foldcast::render
