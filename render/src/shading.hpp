#pragma once
// What the integrator needs at a surface point: the shading frame and the BSDF parameters of
// its material (the garment's look, the backdrop, the hardware).
#include <Eigen/Geometry>

#include <cmath>
#include <memory>

#include "cloth_bsdf.hpp"
#include "embree_scene.hpp"
#include "garment_surface.hpp"
#include "vec3_div.hpp"

namespace foldcast::render {

// An orthonormal basis; the tangent follows `t_hint` where possible.
struct Frame {
    Vec3f t, b, n;
    Frame() = default;  // unset, for Materials::at to fill
    Frame(const Vec3f& normal, const Vec3f& t_hint) : n(normal) {
        Vec3f tt = t_hint - n * n.dot(t_hint);
        if (tt.squaredNorm() < 1e-10f) {
            const Vec3f h = std::abs(n.x()) < 0.9f ? Vec3f::UnitX() : Vec3f::UnitY();
            tt = h - n * n.dot(h);
        }
        t = normalized3(tt);
        b = n.cross(t);
    }
    V3 to_local(const Vec3f& w) const { return V3(w.dot(t), w.dot(b), w.dot(n)); }
    Vec3f to_world(const V3& v) const { return v.x() * t + v.y() * b + v.z() * n; }
};

class Materials {
public:
    Materials(const SceneSpec& scene);

    // The material at `hit` seen from `wo` (world, pointing away from the surface), with
    // `footprint_m` of cloth per pixel.  Orients the hit's normals towards wo (cloth is
    // two-sided) and sets the shading frame and the material's BsdfLobes (of the params
    // returned: they vary over the garment only in their diffuse colour).
    BsdfParams at(Hit& hit, const Vec3f& wo, float footprint_m, Frame* frame, const BsdfLobes** lobes) const;

private:
    std::unique_ptr<GarmentShader> garment_;
    BsdfParams backdrop_, metal_, wood_, wire_;
    BsdfLobes garment_lobes_, backdrop_lobes_, metal_lobes_, wood_lobes_, wire_lobes_;
};

}  // namespace foldcast::render
