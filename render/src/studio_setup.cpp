#include <Eigen/Geometry>
#include "foldcast/render/studio_setup.hpp"

#include <cmath>

#include "foldcast/core/error.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast::render {

StudioSetup::StudioSetup(const SceneSpec& scene, GarmentData garment) : scene_(scene), garment_(std::move(garment)) {
    if (garment_.animation.frames.empty() || garment_.animation.vertex_count() == 0)
        throw InputError("garment: no vertices to render");
    const Bounds b = bounds(garment_.animation);
    centre_ = 0.5f * (b.min + b.max);
    bottom_ = b.min.y();
    radius_ = 0.0f;
    for (const auto& f : garment_.animation.frames)
        for (const Vec3f& p : f) radius_ = std::max(radius_, std::hypot(p.x() - centre_.x(), p.z() - centre_.z()));
    radius_ += 0.05f;  // clips and rod overhang
    if (scene_.studio_preset) {
        const float size = (b.max - b.min).maxCoeff();
        for (const AreaLight& l : studio_lights(centre_, size)) scene_.lights.push_back(l);
    }
}

Vec3f StudioSetup::turn(const Vec3f& p, double turn_deg) const {
    if (turn_deg == 0.0) return p;
    const double a = turn_deg * kPi / 180.0;
    const float c = static_cast<float>(std::cos(a)), s = static_cast<float>(std::sin(a));
    const Vec3f d = p - centre_;
    return centre_ + Vec3f(c * d.x() + s * d.z(), d.y(), -s * d.x() + c * d.z());
}

std::vector<Vec3f> StudioSetup::garment_points(int frame, double turn_deg) const {
    std::vector<Vec3f> pts = garment_.animation.frames.at(static_cast<std::size_t>(frame));
    for (Vec3f& p : pts) p = turn(p, turn_deg);
    return pts;
}

std::vector<StudioMesh> StudioSetup::hardware(const std::vector<Vec3f>& garment_positions) const {
    // The clips hold the support vertices, so they follow the garment's own motion.
    std::vector<Vec3f> supports;
    for (std::uint32_t v : garment_.support_vertices)
        if (v < garment_positions.size()) supports.push_back(garment_positions[v]);
    return build_supports(scene_.supports, supports);
}

std::vector<Vec3f> StudioSetup::framing_points(int frame, double turn_deg) const {
    std::vector<Vec3f> pts = garment_points(frame, turn_deg);
    for (const StudioMesh& m : hardware(pts))
        if (m.material != MaterialId::wire) pts.insert(pts.end(), m.positions.begin(), m.positions.end());
    return pts;
}

FrameGeometry StudioSetup::geometry(int frame, double turn_deg) const {
    FrameGeometry g;
    g.garment.positions = garment_points(frame, turn_deg);
    g.garment.topology = garment_.animation.topology;
    g.garment.normals = vertex_normals(g.garment.positions, g.garment.topology.triangles);
    g.fold_sign = garment_.fold_sign.at(static_cast<std::size_t>(frame));
    if (scene_.backdrop == SceneSpec::Backdrop::cyclorama)
        g.studio.push_back(build_cyclorama(centre_, radius_, bottom_));
    for (StudioMesh& m : hardware(g.garment.positions)) g.studio.push_back(std::move(m));
    return g;
}

}  // namespace foldcast::render
