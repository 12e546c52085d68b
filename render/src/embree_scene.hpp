#pragma once
// The Embree side of the tracer: one device and scene holding the garment and the studio
// meshes with their per-vertex data, the ray set-up shared by every ray the tracer casts,
// and the surface point a hit describes.
#include <embree3/rtcore.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "foldcast/core/mesh.hpp"
#include "foldcast/render/studio.hpp"

namespace foldcast::render {

constexpr float kInf = std::numeric_limits<float>::infinity();

struct GeometryData {
    std::vector<Vec3f> positions;
    std::vector<Vec3f> normals;
    std::vector<Triangle> triangles;
    std::vector<Vec2f> uvs;        // garment only
    std::vector<float> fold_sign;  // garment only
    std::vector<Vec3f> tangents;   // per triangle dP/du (garment), empty otherwise
    MaterialId material = MaterialId::backdrop;
};

// A surface point: geometric and interpolated shading normal, the garment's cloth
// coordinates and fold sign, and the distance along the ray.
struct Hit {
    Vec3f p, ng, ns, tangent;
    Vec2f uv{0, 0};
    float fold = 0.0f;
    float t = 0.0f;
    MaterialId material = MaterialId::backdrop;
    bool has_uv = false;
};

// The one ray construction: origin, direction, [0, tmax).
inline void set_ray(RTCRay& r, const Vec3f& o, const Vec3f& d, float tmax) {
    r.org_x = o.x();
    r.org_y = o.y();
    r.org_z = o.z();
    r.dir_x = d.x();
    r.dir_y = d.y();
    r.dir_z = d.z();
    r.tnear = 0.0f;
    r.tfar = tmax;
    r.time = 0.0f;
    r.mask = 0xFFFFFFFF;
    r.id = 0;
    r.flags = 0;
}
// The same for lane k of a 16-wide packet, with no hit yet.
inline void set_packet_ray(RTCRayHit16& packet, int k, const Vec3f& o, const Vec3f& d) {
    RTCRay16& r = packet.ray;
    r.org_x[k] = o.x();
    r.org_y[k] = o.y();
    r.org_z[k] = o.z();
    r.dir_x[k] = d.x();
    r.dir_y[k] = d.y();
    r.dir_z[k] = d.z();
    r.tnear[k] = 0.0f;
    r.tfar[k] = kInf;
    r.time[k] = 0.0f;
    r.mask[k] = 0xFFFFFFFF;
    r.id[k] = 0;
    r.flags[k] = 0;
    packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
}
// Lane k of a traced packet as a single ray and hit.
void unpack_lane(const RTCRayHit16& packet, int k, RTCRay* ray, RTCHit* hit);

// Moves a ray origin off the surface to the side `dir` leaves by.
inline Vec3f offset_origin(const Vec3f& p, const Vec3f& ng, const Vec3f& dir) {
    const float eps = 1e-4f * (1.0f + p.cwiseAbs().maxCoeff());
    return p + (dir.dot(ng) > 0.0f ? eps : -eps) * ng;
}

class EmbreeScene {
public:
    EmbreeScene();
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    void add(GeometryData data);
    // Builds the BVH with one thread (see the definition for why).
    void commit();

    RTCScene handle() const { return scene_; }
    // Closest hit along o + t d, t in [0, inf); counts the ray.
    bool intersect(const Vec3f& o, const Vec3f& d, RTCRayHit& rh, std::uint64_t& rays) const;
    // Anything along o + t d, t in [0, tmax); counts the ray.
    bool occluded(const Vec3f& o, const Vec3f& d, float tmax, std::uint64_t& rays) const;
    Hit surface(const RTCRay& ray, const RTCHit& h) const;
    // The meshes as added (Embree's geometry IDs are their indices).
    const std::vector<GeometryData>& geometries() const { return geoms_; }

private:
    // Embree reports errors to a handler, not by return values: the first one is kept here
    // and thrown by throw_if_failed() after each call that can fail (device, geometry, build).
    static void on_error(void* self, RTCError code, const char* message);
    void throw_if_failed(const char* what) const;

    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    std::vector<GeometryData> geoms_;
    std::string error_;  // written once by on_error, read on the calling thread
};

}  // namespace foldcast::render
