#include <Eigen/Geometry>
#include "foldcast/render/tracer.hpp"

#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <xmmintrin.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "camera_model.hpp"
#include "foldcast/core/error.hpp"
#include "cloth_bsdf.hpp"
#include "garment_surface.hpp"
#include "random_stream.hpp"
#include "foldcast/core/colour.hpp"
#include "foldcast/core/math.hpp"
#include "foldcast/core/sampling.hpp"

namespace foldcast::render {
namespace {

constexpr int kTile = 32;          // tile side in pixels (DESIGN.md: 16-32 px, no false sharing)
constexpr int kBlock = 4;          // 4x4 pixel packets for camera rays
constexpr int kMaxLights = 16;
constexpr float kIndirectClamp = 20.0f;  // caps rare caustic fireflies off the metal rod
constexpr float kInf = std::numeric_limits<float>::infinity();

float power_heuristic(float a, float b) { return a * a / (a * a + b * b); }

struct GeometryData {
    std::vector<Vec3f> positions;
    std::vector<Vec3f> normals;
    std::vector<Triangle> triangles;
    std::vector<Vec2f> uvs;        // garment only
    std::vector<float> fold_sign;  // garment only
    std::vector<Vec3f> tangents;   // per triangle dP/du (garment), empty otherwise
    MaterialId material = MaterialId::backdrop;
};

struct Light {
    Vec3f centre, normal, ex, ey;  // ex, ey: unit axes
    float half_w = 0, half_h = 0, area = 0;
    V3 radiance;
};

struct Hit {
    Vec3f p, ng, ns, tangent;
    Vec2f uv{0, 0};
    float fold = 0.0f;
    float t = 0.0f;
    MaterialId material = MaterialId::backdrop;
    bool has_uv = false;
};

// A simple orthonormal basis; tangent follows `t_hint` where possible.
struct Frame {
    Vec3f t, b, n;
    Frame(const Vec3f& normal, const Vec3f& t_hint) : n(normal) {
        Vec3f tt = t_hint - n * n.dot(t_hint);
        if (tt.squaredNorm() < 1e-10f) {
            const Vec3f h = std::abs(n.x()) < 0.9f ? Vec3f::UnitX() : Vec3f::UnitY();
            tt = h - n * n.dot(h);
        }
        t = tt.normalized();
        b = n.cross(t);
    }
    V3 to_local(const Vec3f& w) const { return V3(w.dot(t), w.dot(b), w.dot(n)); }
    Vec3f to_world(const V3& v) const { return v.x() * t + v.y() * b + v.z() * n; }
};

Vec3f offset_origin(const Vec3f& p, const Vec3f& ng, const Vec3f& dir) {
    const float eps = 1e-4f * (1.0f + p.cwiseAbs().maxCoeff());
    return p + (dir.dot(ng) > 0.0f ? eps : -eps) * ng;
}

}  // namespace

void set_ftz_daz() {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

struct Tracer::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<GeometryData> geoms;
    std::vector<Light> lights;
    V3 environment = V3::Zero();
    bool transparent = false;
    int max_depth = 5;
    std::unique_ptr<GarmentShader> garment_shader;
    BsdfParams backdrop, metal, wood, wire;

    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }

    void add(GeometryData data) {
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), data.positions.size()));
        for (std::size_t i = 0; i < data.positions.size(); ++i)
            for (int k = 0; k < 3; ++k) v[3 * i + k] = data.positions[i][k];
        auto* idx = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), data.triangles.size()));
        for (std::size_t i = 0; i < data.triangles.size(); ++i)
            for (int k = 0; k < 3; ++k) idx[3 * i + k] = data.triangles[i][k];
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(scene, g, static_cast<unsigned>(geoms.size()));
        rtcReleaseGeometry(g);
        geoms.push_back(std::move(data));
    }

    Hit surface(const RTCRay& ray, const RTCHit& h) const {
        const GeometryData& g = geoms[h.geomID];
        const Triangle& tri = g.triangles[h.primID];
        const float u = h.u, v = h.v, w = 1.0f - u - v;
        Hit hit;
        hit.t = ray.tfar;
        hit.p = Vec3f(ray.org_x, ray.org_y, ray.org_z) + ray.tfar * Vec3f(ray.dir_x, ray.dir_y, ray.dir_z);
        hit.ng = Vec3f(h.Ng_x, h.Ng_y, h.Ng_z).normalized();
        hit.ns = (w * g.normals[tri[0]] + u * g.normals[tri[1]] + v * g.normals[tri[2]]);
        hit.ns = hit.ns.squaredNorm() > 0.0f ? hit.ns.normalized() : hit.ng;
        hit.material = g.material;
        if (!g.uvs.empty()) {
            hit.uv = w * g.uvs[tri[0]] + u * g.uvs[tri[1]] + v * g.uvs[tri[2]];
            hit.has_uv = true;
        }
        if (!g.fold_sign.empty())
            hit.fold = w * g.fold_sign[tri[0]] + u * g.fold_sign[tri[1]] + v * g.fold_sign[tri[2]];
        hit.tangent = g.tangents.empty() ? Vec3f::UnitX() : g.tangents[h.primID];
        return hit;
    }

    // Material at a hit seen from direction wo (world, pointing away from the surface).
    // Orients the normals towards wo (cloth is two-sided) and builds the shading frame.
    BsdfParams material(Hit& hit, const Vec3f& wo, float footprint_m, Frame* frame) const {
        if (hit.ng.dot(wo) < 0.0f) {
            hit.ng = -hit.ng;
            hit.ns = -hit.ns;
        }
        if (hit.ns.dot(wo) <= 1e-4f) hit.ns = hit.ng;  // shading normal facing away: fall back
        switch (hit.material) {
            case MaterialId::garment: {
                const GarmentSurface s = garment_shader->shade(hit.uv, footprint_m);
                const Frame base(hit.ns, hit.tangent);
                Vec3f n = base.to_world(s.normal_ts).normalized();
                if (n.dot(wo) <= 1e-4f) n = hit.ns;
                *frame = Frame(n, s.anisotropy_along_weft ? base.b : base.t);
                return s.bsdf;
            }
            case MaterialId::backdrop: *frame = Frame(hit.ns, hit.tangent); return backdrop;
            case MaterialId::metal: *frame = Frame(hit.ns, Vec3f::UnitX()); return metal;
            case MaterialId::wood: *frame = Frame(hit.ns, Vec3f::UnitY()); return wood;
            case MaterialId::wire: *frame = Frame(hit.ns, Vec3f::UnitY()); return wire;
        }
        throw std::logic_error("unknown material");
    }

    // Nearest light hit along a ray (front faces only), or -1.
    int hit_light(const Vec3f& o, const Vec3f& d, float tmax, float* t_out) const {
        int best = -1;
        float best_t = tmax;
        for (std::size_t i = 0; i < lights.size(); ++i) {
            const Light& l = lights[i];
            const float dn = d.dot(l.normal);
            if (dn >= 0.0f) continue;
            const float t = (l.centre - o).dot(l.normal) / dn;
            if (t <= 0.0f || t >= best_t) continue;
            const Vec3f q = o + t * d - l.centre;
            if (std::abs(q.dot(l.ex)) > l.half_w || std::abs(q.dot(l.ey)) > l.half_h) continue;
            best = static_cast<int>(i);
            best_t = t;
        }
        *t_out = best_t;
        return best;
    }

    // Probabilities of picking each light (and the environment, last) for NEE at p.
    int light_choice(const Vec3f& p, const Vec3f& n, std::array<float, kMaxLights + 1>& prob) const {
        const int count = static_cast<int>(lights.size());
        float sum = 0.0f;
        for (int i = 0; i < count; ++i) {
            const Light& l = lights[i];
            const Vec3f d = l.centre - p;
            const float dist2 = std::max(1e-4f, d.squaredNorm());
            const Vec3f dn = d / std::sqrt(dist2);
            const float facing = std::max(0.0f, -dn.dot(l.normal));
            const float receive = std::max(0.0f, dn.dot(n)) + 0.05f;
            prob[i] = facing > 0.0f ? luminance(l.radiance) * l.area * facing * receive / dist2 : 0.0f;
            sum += prob[i];
        }
        prob[count] = luminance(environment) * kPiF;
        sum += prob[count];
        if (sum > 0.0f)
            for (int i = 0; i <= count; ++i) prob[i] /= sum;
        return count + 1;
    }

    bool occluded(const Vec3f& o, const Vec3f& d, float tmax, std::uint64_t& rays) const {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        RTCRay r;
        r.org_x = o.x(); r.org_y = o.y(); r.org_z = o.z();
        r.dir_x = d.x(); r.dir_y = d.y(); r.dir_z = d.z();
        r.tnear = 0.0f; r.tfar = tmax; r.time = 0.0f; r.mask = 0xFFFFFFFF; r.id = 0; r.flags = 0;
        rtcOccluded1(scene, &ctx, &r);
        ++rays;
        return r.tfar < 0.0f;
    }

    bool intersect(const Vec3f& o, const Vec3f& d, RTCRayHit& rh, std::uint64_t& rays) const {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        rh.ray.org_x = o.x(); rh.ray.org_y = o.y(); rh.ray.org_z = o.z();
        rh.ray.dir_x = d.x(); rh.ray.dir_y = d.y(); rh.ray.dir_z = d.z();
        rh.ray.tnear = 0.0f; rh.ray.tfar = kInf; rh.ray.time = 0.0f; rh.ray.mask = 0xFFFFFFFF;
        rh.ray.id = 0; rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &rh);
        ++rays;
        return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }

    struct SampleOut {
        V3 radiance = V3::Zero();
        bool foreground = true;  // false: the camera saw the backdrop or the sky
        V3 albedo = V3::Zero();
        Vec3f normal = Vec3f::Zero();
        float depth = 0.0f;
        float fold = 0.0f;
    };

    // One camera path, given the camera ray and its packet-traced first hit.
    SampleOut trace(const Vec3f& cam_o, const Vec3f& cam_d, bool first_hit, const RTCRay& ray0,
                    const RTCHit& hit0, float pixel_angle, RandomStream& rng, std::uint64_t& rays) const {
        SampleOut out;
        V3 beta = V3::Ones();
        Vec3f o = cam_o, d = cam_d;
        bool have_hit = first_hit;
        RTCRay cur_ray = ray0;
        RTCHit cur_hit = hit0;
        RTCRayHit rh;
        float prev_bsdf_pdf = 0.0f;
        bool prev_specular_only = true;  // camera ray: lights are not seen directly
        std::array<float, kMaxLights + 1> prev_choice{};
        Vec3f prev_n = Vec3f::UnitY();
        float cone = 0.0f, spread = pixel_angle;
        for (int depth = 0;; ++depth) {
            // Emission seen along the ray: lights (not for camera rays) and the environment.
            float t_surface = have_hit ? cur_ray.tfar : kInf;
            if (depth > 0 && !lights.empty()) {
                float t_light = 0.0f;
                const int li = hit_light(o, d, t_surface, &t_light);
                if (li >= 0) {
                    const Light& l = lights[li];
                    const float cos_l = -d.dot(l.normal);
                    const float pdf_light = prev_choice[li] * t_light * t_light / (l.area * cos_l);
                    const float w = prev_specular_only ? 1.0f : power_heuristic(prev_bsdf_pdf, pdf_light);
                    add(out.radiance, beta.cwiseProduct(l.radiance) * w, depth);
                    break;
                }
            }
            if (!have_hit) {
                if (depth == 0) {
                    out.foreground = !transparent;
                    out.radiance = environment;
                } else {
                    const float pdf_env =
                        prev_choice[lights.size()] * std::max(0.0f, d.dot(prev_n)) / kPiF;
                    const float w = power_heuristic(prev_bsdf_pdf, pdf_env);
                    add(out.radiance, beta.cwiseProduct(environment) * w, depth);
                }
                break;
            }
            Hit hit = surface(cur_ray, cur_hit);
            cone += hit.t * spread;
            const Vec3f wo = -d;
            Frame frame(hit.ns, hit.tangent);
            const float cos_view = std::max(0.2f, std::abs(wo.dot(hit.ng)));
            const BsdfParams params = material(hit, wo, cone / cos_view, &frame);
            const ClothBsdf bsdf(params, frame.to_local(wo));
            if (depth == 0) {
                out.albedo = bsdf.albedo();
                out.normal = hit.ns;
                out.depth = hit.t;
                out.fold = hit.material == MaterialId::garment ? hit.fold : 0.0f;
                if (transparent && hit.material == MaterialId::backdrop) out.foreground = false;
            }
            if (depth + 1 >= max_depth) break;

            // Next-event estimation: one light (or the environment) picked by expected
            // contribution, MIS-weighted against BSDF sampling.
            std::array<float, kMaxLights + 1> choice{};
            const int options = light_choice(hit.p, hit.ns, choice);
            const float u_pick = rng.next(), u_a = rng.next(), u_b = rng.next();
            {
                int pick = 0;
                float acc = choice[0];
                while (pick + 1 < options && u_pick >= acc) acc += choice[++pick];
                if (choice[pick] > 0.0f) {
                    Vec3f wi;
                    float dist = kInf, pdf_light = 0.0f;
                    V3 le = V3::Zero();
                    if (pick < static_cast<int>(lights.size())) {
                        const Light& l = lights[pick];
                        const Vec3f q = l.centre + (2.0f * u_a - 1.0f) * l.half_w * l.ex +
                                        (2.0f * u_b - 1.0f) * l.half_h * l.ey;
                        const Vec3f to = q - hit.p;
                        dist = to.norm();
                        wi = to / dist;
                        const float cos_l = -wi.dot(l.normal);
                        if (cos_l > 0.0f) {
                            pdf_light = choice[pick] * dist * dist / (l.area * cos_l);
                            le = l.radiance;
                        }
                    } else {
                        const V3 local = sample_cosine_hemisphere(u_a, u_b);
                        const Frame nf(hit.ns, hit.tangent);
                        wi = nf.to_world(local);
                        pdf_light = choice[pick] * local.z() / kPiF;
                        le = environment;
                    }
                    if (pdf_light > 0.0f && wi.dot(hit.ng) > 0.0f) {
                        float pdf_bsdf = 0.0f;
                        const V3 fc = bsdf.eval(frame.to_local(wi), &pdf_bsdf);
                        if (fc.maxCoeff() > 0.0f) {
                            const Vec3f so = offset_origin(hit.p, hit.ng, wi);
                            const float tmax = std::isfinite(dist) ? dist * (1.0f - 1e-3f) : kInf;
                            if (!occluded(so, wi, tmax, rays)) {
                                const float w = power_heuristic(pdf_light, pdf_bsdf);
                                add(out.radiance, beta.cwiseProduct(fc).cwiseProduct(le) * (w / pdf_light), depth + 1);
                            }
                        }
                    }
                }
            }

            // Continue the path by sampling the BSDF.
            BsdfSample bs;
            const float u_lobe = rng.next(), u1 = rng.next(), u2 = rng.next();
            if (!bsdf.sample(u_lobe, u1, u2, &bs)) break;
            const Vec3f wi = frame.to_world(bs.wi);
            if (wi.dot(hit.ng) <= 0.0f) break;
            beta = beta.cwiseProduct(bs.weight);
            if (depth >= 2) {  // Russian roulette
                const float q = std::min(0.95f, beta.maxCoeff());
                if (rng.next() >= q) break;
                beta /= q;
            }
            prev_bsdf_pdf = bs.pdf;
            prev_specular_only = false;
            prev_choice = choice;
            prev_n = hit.ns;
            spread += 0.2f;  // a rough bounce widens the footprint cone
            o = offset_origin(hit.p, hit.ng, wi);
            d = wi;
            have_hit = intersect(o, d, rh, rays);
            cur_ray = rh.ray;
            cur_hit = rh.hit;
        }
        return out;
    }

    static void add(V3& radiance, const V3& contribution, int depth) {
        if (!contribution.allFinite()) return;
        if (depth >= 2) {
            const float m = contribution.maxCoeff();
            if (m > kIndirectClamp) {
                radiance += contribution * (kIndirectClamp / m);
                return;
            }
        }
        radiance += contribution;
    }
};

Tracer::Tracer(const SceneSpec& scene, FrameGeometry geometry) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    // No thread count in the device's configuration: Embree turns one into a process-wide
    // tbb::global_control, which silently capped every TBB arena of the process, the
    // tracer's tiles included, at that many threads (RenderKit/embree#507).
    m.device = rtcNewDevice(nullptr);
    if (!m.device) throw std::runtime_error("Embree: cannot create a device");
    m.scene = rtcNewScene(m.device);
    rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_HIGH);
    m.environment = scene.environment;
    m.transparent = scene.transparent;
    m.max_depth = std::max(1, scene.max_depth);
    m.garment_shader = std::make_unique<GarmentShader>(scene.look.appearance);
    m.backdrop.diffuse = scene.backdrop_colour;
    m.backdrop.f0 = 0.02f;
    m.backdrop.roughness = 0.9f;
    m.metal = {V3::Constant(0.02f), V3::Zero(), 0.5f, 0.7f, 0.3f, 0.6f};
    m.wood = {V3(0.60f, 0.43f, 0.27f), V3::Zero(), 0.5f, 0.04f, 0.55f, 0.0f};
    m.wire = {V3::Constant(0.03f), V3::Zero(), 0.5f, 0.5f, 0.35f, 0.0f};

    GeometryData garment;
    garment.material = MaterialId::garment;
    garment.positions = std::move(geometry.garment.positions);
    garment.triangles = std::move(geometry.garment.topology.triangles);
    garment.normals = geometry.garment.normals.empty() ? vertex_normals(garment.positions, garment.triangles)
                                                       : std::move(geometry.garment.normals);
    garment.uvs = std::move(geometry.garment.topology.uvs);
    garment.fold_sign = std::move(geometry.fold_sign);
    garment.tangents.resize(garment.triangles.size(), Vec3f::UnitX());
    if (!garment.uvs.empty())
        for (std::size_t i = 0; i < garment.triangles.size(); ++i) {
            const Triangle& t = garment.triangles[i];
            const Vec3f e1 = garment.positions[t[1]] - garment.positions[t[0]];
            const Vec3f e2 = garment.positions[t[2]] - garment.positions[t[0]];
            const Vec2f d1 = garment.uvs[t[1]] - garment.uvs[t[0]];
            const Vec2f d2 = garment.uvs[t[2]] - garment.uvs[t[0]];
            const float det = d1.x() * d2.y() - d1.y() * d2.x();
            if (std::abs(det) > 1e-12f) garment.tangents[i] = ((e1 * d2.y() - e2 * d1.y()) / det).normalized();
        }
    m.add(std::move(garment));
    for (StudioMesh& s : geometry.studio) {
        GeometryData g;
        g.material = s.material;
        g.positions = std::move(s.positions);
        g.normals = std::move(s.normals);
        g.triangles = std::move(s.triangles);
        m.add(std::move(g));
    }
    // The BVH is built by one thread, in an arena of its own: Embree's multi-threaded
    // high-quality builds can differ from run to run, and a different hierarchy can report
    // a different one of two triangles hit at the same distance (determinism).  Builds are
    // per frame and take ~10-30 ms.
    tbb::task_arena one_thread(1);
    one_thread.execute([&] { rtcCommitScene(m.scene); });

    if (scene.lights.size() > static_cast<std::size_t>(kMaxLights))
        throw InputError(scene.file.string() + ": at most " + std::to_string(kMaxLights) + " lights are supported");
    for (const AreaLight& a : scene.lights) {
        Light l;
        l.centre = a.position;
        l.normal = (a.target - a.position).normalized();
        const Vec3f helper = std::abs(l.normal.y()) < 0.95f ? Vec3f::UnitY() : Vec3f::UnitX();
        l.ex = helper.cross(l.normal).normalized();
        l.ey = l.normal.cross(l.ex);
        l.half_w = 0.5f * a.width_m;
        l.half_h = 0.5f * a.height_m;
        l.area = a.width_m * a.height_m;
        l.radiance = a.radiance;
        m.lights.push_back(l);
    }
}

Tracer::~Tracer() = default;

void* Tracer::embree_scene() const { return impl_->scene; }

RenderResult Tracer::render(const Camera& camera, const TraceSettings& settings, const ProgressFn& progress) const {
    const auto start = std::chrono::steady_clock::now();
    const Impl& m = *impl_;
    const int width = settings.width, height = settings.height, spp = std::max(1, settings.spp);
    const CameraModel cam(camera, width, height);
    const float pixel_angle = cam.pixel_angle();
    RenderResult result;
    result.beauty = Image{width, height, 4, std::vector<float>(static_cast<std::size_t>(width) * height * 4, 0.0f)};
    bool want[4] = {false, false, false, false};
    for (Aov a : settings.aovs) want[static_cast<int>(a)] = true;
    const int aov_channels[4] = {3, 3, 1, 1};
    Image aov_img[4];
    for (int a = 0; a < 4; ++a)
        if (want[a])
            aov_img[a] = Image{width, height, aov_channels[a],
                               std::vector<float>(static_cast<std::size_t>(width) * height * aov_channels[a], 0.0f)};

    const int tiles_x = (width + kTile - 1) / kTile, tiles_y = (height + kTile - 1) / kTile;
    const int tile_count = tiles_x * tiles_y;
    std::atomic<std::uint64_t> total_rays{0};
    std::atomic<int> tiles_done{0};

    auto render_tile = [&](int tile) {
        set_ftz_daz();
        const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
        const int x1 = std::min(width, x0 + kTile), y1 = std::min(height, y0 + kTile);
        std::uint64_t rays = 0;
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        for (int by = y0; by < y1; by += kBlock)
            for (int bx = x0; bx < x1; bx += kBlock) {
                // Per-pixel accumulators for the 4x4 block.
                std::array<V3, 16> fg_sum{}, all_sum{};
                std::array<int, 16> fg_count{};
                std::array<V3, 16> albedo{}, normal{};
                std::array<float, 16> depth{}, fold{};
                for (int k = 0; k < 16; ++k) {
                    fg_sum[k] = all_sum[k] = albedo[k] = normal[k] = V3::Zero();
                    depth[k] = fold[k] = 0.0f;
                }
                for (int s = 0; s < spp; ++s) {
                    alignas(64) RTCRayHit16 packet;
                    alignas(64) int valid[16];
                    std::array<RandomStream, 16> rng{RandomStream(0, 0, 0), RandomStream(0, 0, 0), RandomStream(0, 0, 0),
                                                     RandomStream(0, 0, 0), RandomStream(0, 0, 0), RandomStream(0, 0, 0),
                                                     RandomStream(0, 0, 0), RandomStream(0, 0, 0), RandomStream(0, 0, 0),
                                                     RandomStream(0, 0, 0), RandomStream(0, 0, 0), RandomStream(0, 0, 0),
                                                     RandomStream(0, 0, 0), RandomStream(0, 0, 0), RandomStream(0, 0, 0),
                                                     RandomStream(0, 0, 0)};
                    std::array<Vec3f, 16> origin, dir;
                    for (int k = 0; k < 16; ++k) {
                        const int x = bx + k % kBlock, y = by + k / kBlock;
                        valid[k] = (x < x1 && y < y1) ? -1 : 0;
                        rng[k] = RandomStream(settings.seed, static_cast<std::uint64_t>(y) * width + x,
                                              static_cast<std::uint32_t>(s));
                        Vec3f o = Vec3f::Zero(), d = Vec3f::UnitZ();
                        if (valid[k]) {
                            const float jx = rng[k].next(), jy = rng[k].next(), lu = rng[k].next(), lv = rng[k].next();
                            cam.ray(static_cast<float>(x) + jx, static_cast<float>(y) + jy, lu, lv, &o, &d);
                        }
                        origin[k] = o;
                        dir[k] = d;
                        packet.ray.org_x[k] = o.x(); packet.ray.org_y[k] = o.y(); packet.ray.org_z[k] = o.z();
                        packet.ray.dir_x[k] = d.x(); packet.ray.dir_y[k] = d.y(); packet.ray.dir_z[k] = d.z();
                        packet.ray.tnear[k] = 0.0f; packet.ray.tfar[k] = kInf; packet.ray.time[k] = 0.0f;
                        packet.ray.mask[k] = 0xFFFFFFFF; packet.ray.id[k] = 0; packet.ray.flags[k] = 0;
                        packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                        packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
                    }
                    rtcIntersect16(valid, m.scene, &ctx, &packet);
                    for (int k = 0; k < 16; ++k) {
                        if (!valid[k]) continue;
                        ++rays;
                        RTCRay r;
                        RTCHit h;
                        r.org_x = packet.ray.org_x[k]; r.org_y = packet.ray.org_y[k]; r.org_z = packet.ray.org_z[k];
                        r.dir_x = packet.ray.dir_x[k]; r.dir_y = packet.ray.dir_y[k]; r.dir_z = packet.ray.dir_z[k];
                        r.tfar = packet.ray.tfar[k];
                        h.geomID = packet.hit.geomID[k]; h.primID = packet.hit.primID[k];
                        h.u = packet.hit.u[k]; h.v = packet.hit.v[k];
                        h.Ng_x = packet.hit.Ng_x[k]; h.Ng_y = packet.hit.Ng_y[k]; h.Ng_z = packet.hit.Ng_z[k];
                        const Impl::SampleOut o = m.trace(origin[k], dir[k], h.geomID != RTC_INVALID_GEOMETRY_ID, r, h,
                                                          pixel_angle, rng[k], rays);
                        all_sum[k] += o.radiance;
                        if (o.foreground) {
                            fg_sum[k] += o.radiance;
                            ++fg_count[k];
                        }
                        albedo[k] += o.albedo;
                        normal[k] += V3(o.normal.x(), o.normal.y(), o.normal.z());
                        depth[k] += o.depth;
                        fold[k] += o.fold;
                    }
                }
                const float inv = 1.0f / static_cast<float>(spp);
                for (int k = 0; k < 16; ++k) {
                    const int x = bx + k % kBlock, y = by + k / kBlock;
                    if (x >= x1 || y >= y1) continue;
                    float* px = result.beauty.at(x, y);
                    const V3 c = m.transparent ? (fg_count[k] > 0 ? V3(fg_sum[k] / static_cast<float>(fg_count[k])) : V3::Zero())
                                               : V3(all_sum[k] * inv);
                    px[0] = c.x(); px[1] = c.y(); px[2] = c.z();
                    px[3] = m.transparent ? static_cast<float>(fg_count[k]) * inv : 1.0f;
                    if (want[0]) { float* a = aov_img[0].at(x, y); for (int i = 0; i < 3; ++i) a[i] = albedo[k][i] * inv; }
                    if (want[1]) {
                        const V3 n = normal[k].squaredNorm() > 0.0f ? V3(normal[k].normalized()) : V3::Zero();
                        float* a = aov_img[1].at(x, y);
                        for (int i = 0; i < 3; ++i) a[i] = n[i];
                    }
                    if (want[2]) *aov_img[2].at(x, y) = depth[k] * inv;
                    if (want[3]) *aov_img[3].at(x, y) = fold[k] * inv;
                }
            }
        total_rays += rays;
        const int done = ++tiles_done;
        if (progress) progress("render", static_cast<double>(done) / tile_count);
    };

    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, tile_count, 1), [&](const tbb::blocked_range<int>& r) {
            for (int t = r.begin(); t != r.end(); ++t) render_tile(t);
        });
    });

    for (int a = 0; a < 4; ++a)
        if (want[a]) result.aovs.push_back({static_cast<Aov>(a), std::move(aov_img[a])});
    result.stats.width = width;
    result.stats.height = height;
    result.stats.spp = spp;
    result.stats.rays = total_rays.load();
    result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

std::uint64_t Tracer::primary_visibility(const Camera& camera, int width, int height, int threads) const {
    const Impl& m = *impl_;
    const CameraModel cam(camera, width, height);
    const int tiles_x = (width + kTile - 1) / kTile, tiles_y = (height + kTile - 1) / kTile;
    std::atomic<std::uint64_t> hits{0};
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(0, tiles_x * tiles_y, [&](int tile) {
            set_ftz_daz();
            const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
            const int x1 = std::min(width, x0 + kTile), y1 = std::min(height, y0 + kTile);
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
            std::uint64_t local = 0;
            for (int by = y0; by < y1; by += kBlock)
                for (int bx = x0; bx < x1; bx += kBlock) {
                    alignas(64) RTCRayHit16 packet;
                    alignas(64) int valid[16];
                    for (int k = 0; k < 16; ++k) {
                        const int x = bx + k % kBlock, y = by + k / kBlock;
                        valid[k] = (x < x1 && y < y1) ? -1 : 0;
                        Vec3f o, d;
                        cam.ray(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f, 0.5f, 0.5f, &o, &d);
                        packet.ray.org_x[k] = o.x(); packet.ray.org_y[k] = o.y(); packet.ray.org_z[k] = o.z();
                        packet.ray.dir_x[k] = d.x(); packet.ray.dir_y[k] = d.y(); packet.ray.dir_z[k] = d.z();
                        packet.ray.tnear[k] = 0.0f; packet.ray.tfar[k] = kInf; packet.ray.time[k] = 0.0f;
                        packet.ray.mask[k] = 0xFFFFFFFF; packet.ray.id[k] = 0; packet.ray.flags[k] = 0;
                        packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                    }
                    rtcIntersect16(valid, m.scene, &ctx, &packet);
                    for (int k = 0; k < 16; ++k)
                        if (valid[k] && packet.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID) ++local;
                }
            hits += local;
        });
    });
    return hits.load();
}

}  // namespace foldcast::render
