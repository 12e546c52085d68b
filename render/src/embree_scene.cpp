#include "embree_scene.hpp"
#include "vec3_div.hpp"

#include <tbb/task_arena.h>

#include <stdexcept>

namespace foldcast::render {

void unpack_lane(const RTCRayHit16& packet, int k, RTCRay* r, RTCHit* h) {
    r->org_x = packet.ray.org_x[k];
    r->org_y = packet.ray.org_y[k];
    r->org_z = packet.ray.org_z[k];
    r->dir_x = packet.ray.dir_x[k];
    r->dir_y = packet.ray.dir_y[k];
    r->dir_z = packet.ray.dir_z[k];
    r->tfar = packet.ray.tfar[k];
    h->geomID = packet.hit.geomID[k];
    h->primID = packet.hit.primID[k];
    h->u = packet.hit.u[k];
    h->v = packet.hit.v[k];
    h->Ng_x = packet.hit.Ng_x[k];
    h->Ng_y = packet.hit.Ng_y[k];
    h->Ng_z = packet.hit.Ng_z[k];
}

namespace {
const char* error_name(RTCError code) {
    switch (code) {
        case RTC_ERROR_NONE:
            return "no error";
        case RTC_ERROR_UNKNOWN:
            return "unknown error";
        case RTC_ERROR_INVALID_ARGUMENT:
            return "invalid argument";
        case RTC_ERROR_INVALID_OPERATION:
            return "invalid operation";
        case RTC_ERROR_OUT_OF_MEMORY:
            return "out of memory";
        case RTC_ERROR_UNSUPPORTED_CPU:
            return "unsupported CPU";
        case RTC_ERROR_CANCELLED:
            return "cancelled";
    }
    return "error";
}
}  // namespace

void EmbreeScene::on_error(void* self, RTCError code, const char* message) {
    auto* scene = static_cast<EmbreeScene*>(self);
    if (scene->error_.empty())
        scene->error_ = std::string(error_name(code)) + (message && *message ? std::string(": ") + message : "");
}

void EmbreeScene::throw_if_failed(const char* what) const {
    if (!error_.empty()) throw std::runtime_error(std::string("Embree, ") + what + ": " + error_);
}

EmbreeScene::EmbreeScene() {
    // No thread count in the device's configuration: Embree turns one into a process-wide
    // tbb::global_control, which silently capped every TBB arena of the process, the
    // tracer's tiles included, at that many threads (RenderKit/embree#507).
    device_ = rtcNewDevice(nullptr);
    if (!device_)
        throw std::runtime_error(std::string("Embree: cannot create a device (") +
                                 error_name(rtcGetDeviceError(nullptr)) + ")");
    rtcSetDeviceErrorFunction(device_, &EmbreeScene::on_error, this);
    scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    if (!error_.empty()) {  // no destructor runs for a constructor that throws
        if (scene_) rtcReleaseScene(scene_);
        rtcReleaseDevice(device_);
        throw_if_failed("creating the scene");
    }
}

EmbreeScene::~EmbreeScene() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
}

void EmbreeScene::add(GeometryData data) {
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), data.positions.size()));
    for (std::size_t i = 0; i < data.positions.size(); ++i)
        for (int k = 0; k < 3; ++k) v[3 * i + k] = data.positions[i][k];
    auto* idx = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                    3 * sizeof(std::uint32_t), data.triangles.size()));
    for (std::size_t i = 0; i < data.triangles.size(); ++i)
        for (int k = 0; k < 3; ++k) idx[3 * i + k] = data.triangles[i][k];
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(scene_, g, static_cast<unsigned>(geoms_.size()));
    rtcReleaseGeometry(g);
    throw_if_failed("adding a mesh");
    geoms_.push_back(std::move(data));
}

void EmbreeScene::commit() {
    // The BVH is built by one thread, in an arena of its own: Embree's multi-threaded
    // high-quality builds can differ from run to run, and a different hierarchy can report
    // a different one of two triangles hit at the same distance (determinism).  Builds are
    // per frame and take ~10-30 ms.
    tbb::task_arena one_thread(1);
    one_thread.execute([&] { rtcCommitScene(scene_); });
    throw_if_failed("building the BVH");
}

bool EmbreeScene::intersect(const Vec3f& o, const Vec3f& d, RTCRayHit& rh, std::uint64_t& rays) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    set_ray(rh.ray, o, d, kInf);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &ctx, &rh);
    ++rays;
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
}

bool EmbreeScene::occluded(const Vec3f& o, const Vec3f& d, float tmax, std::uint64_t& rays) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay r;
    set_ray(r, o, d, tmax);
    rtcOccluded1(scene_, &ctx, &r);
    ++rays;
    return r.tfar < 0.0f;
}

Hit EmbreeScene::surface(const RTCRay& ray, const RTCHit& h) const {
    const GeometryData& g = geoms_[h.geomID];
    const Triangle& tri = g.triangles[h.primID];
    const float u = h.u, v = h.v, w = 1.0f - u - v;
    Hit hit;
    hit.t = ray.tfar;
    hit.p = Vec3f(ray.org_x, ray.org_y, ray.org_z) + ray.tfar * Vec3f(ray.dir_x, ray.dir_y, ray.dir_z);
    hit.ng = Vec3f(h.Ng_x, h.Ng_y, h.Ng_z);
    hit.ns = (w * g.normals[tri[0]] + u * g.normals[tri[1]] + v * g.normals[tri[2]]);
    const bool has_ns = hit.ns.squaredNorm() > 0.0f;
    normalize_pair(hit.ng, hit.ns);  // both roots at once
    if (!has_ns) hit.ns = hit.ng;
    hit.material = g.material;
    if (!g.uvs.empty()) {
        hit.uv = w * g.uvs[tri[0]] + u * g.uvs[tri[1]] + v * g.uvs[tri[2]];
        hit.has_uv = true;
    }
    if (!g.fold_sign.empty()) hit.fold = w * g.fold_sign[tri[0]] + u * g.fold_sign[tri[1]] + v * g.fold_sign[tri[2]];
    hit.tangent = g.tangents.empty() ? Vec3f::UnitX() : g.tangents[h.primID];
    return hit;
}

}  // namespace foldcast::render
