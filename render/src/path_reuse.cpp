#include "path_reuse.hpp"

#include <algorithm>
#include <utility>

#include "foldcast/render/tracer.hpp"

namespace foldcast::render {

std::shared_ptr<PathReuse> make_path_reuse(std::size_t budget_bytes) {
    return std::make_shared<PathReuse>(budget_bytes);
}

void PathReuse::begin_frame(std::uint64_t signature, int tile_count) {
    if (signature_ == signature && tiles_.size() == static_cast<std::size_t>(tile_count)) return;
    tiles_.assign(static_cast<std::size_t>(tile_count), KeptTile{});
    signature_ = signature;
}

TurningMeshes::TurningMeshes(const EmbreeScene& all)
    : scene_(std::make_unique<EmbreeScene>()), lo_(Vec3f::Constant(kInf)), hi_(Vec3f::Constant(-kInf)) {
    const std::vector<GeometryData>& geoms = all.geometries();
    flags.assign(geoms.size(), 0);
    for (std::size_t i = 0; i < geoms.size(); ++i) {
        if (geoms[i].material == MaterialId::backdrop) continue;
        flags[i] = 1;
        GeometryData g;
        g.material = geoms[i].material;
        g.positions = geoms[i].positions;
        g.triangles = geoms[i].triangles;
        for (const Vec3f& p : g.positions) lo_ = lo_.cwiseMin(p), hi_ = hi_.cwiseMax(p);
        scene_->add(std::move(g));
    }
    scene_->commit();
    // Generous against the slab test's rounding (millimetres on a garment's metre).
    const Vec3f pad = Vec3f::Constant(1e-3f * (1.0f + (hi_ - lo_).cwiseAbs().maxCoeff()));
    lo_ -= pad;
    hi_ += pad;
}

void TurningMeshes::fingerprint_still(const EmbreeScene& all, Fingerprint& f) const {
    const std::vector<GeometryData>& geoms = all.geometries();
    for (std::size_t i = 0; i < geoms.size(); ++i) {
        f.value(flags[i]);
        if (flags[i]) continue;
        f.value(geoms[i].material);
        f.bytes(geoms[i].positions.data(), geoms[i].positions.size() * sizeof(Vec3f));
        f.bytes(geoms[i].triangles.data(), geoms[i].triangles.size() * sizeof(Triangle));
        f.bytes(geoms[i].normals.data(), geoms[i].normals.size() * sizeof(Vec3f));
    }
}

bool TurningMeshes::crosses_box(const KeptRay& r) const {
    float t0 = 0.0f, t1 = r.tmax;
    for (int a = 0; a < 3; ++a) {
        if (r.d[a] == 0.0f) {  // parallel to the slab: inside it or missing the box
            if (r.o[a] < lo_[a] || r.o[a] > hi_[a]) return false;
            continue;
        }
        const float inv = 1.0f / r.d[a];
        float near = (lo_[a] - r.o[a]) * inv, far = (hi_[a] - r.o[a]) * inv;
        if (near > far) std::swap(near, far);
        t0 = std::max(t0, near);
        t1 = std::min(t1, far);
        if (t0 > t1) return false;
    }
    return true;
}

bool TurningMeshes::still_clear(const KeptRay* rays, std::uint32_t count) const {
    std::uint64_t unused = 0;  // not counted as the frame's rays
    for (std::uint32_t i = 0; i < count; ++i) {
        const KeptRay& r = rays[i];
        if (!crosses_box(r)) continue;
        if (scene_->occluded(Vec3f(r.o[0], r.o[1], r.o[2]), Vec3f(r.d[0], r.d[1], r.d[2]), r.tmax, unused))
            return false;
    }
    return true;
}

}  // namespace foldcast::render
