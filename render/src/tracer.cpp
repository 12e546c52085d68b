// The tracer: a frame's Embree scene, lights and materials, rendered tile by tile over TBB
// with 16-wide camera-ray packets; each camera path is traced by the PathIntegrator.
#include "foldcast/render/tracer.hpp"

#include <pmmintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <xmmintrin.h>

#include <algorithm>
#include <thread>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "camera_model.hpp"
#include "embree_scene.hpp"
#include "foldcast/core/error.hpp"
#include "light_sampler.hpp"
#include "path_integrator.hpp"
#include "path_reuse.hpp"
#include "pixel_layers.hpp"
#include "pixel_sums.hpp"
#include "sobol_sampler.hpp"
#include "denoise/denoise.hpp"
#include "foldcast/core/colour.hpp"
#include "shading.hpp"

namespace foldcast::render {
namespace {

constexpr int kTile = 32;  // tile side in pixels (16-32 px: no false sharing between tiles)
constexpr int kBlock = 4;  // 4x4 pixel packets for camera rays
// In a denoised still, a pixel whose first spp samples saw two surfaces (a silhouette, a
// fold's front sheet over the back one, a wire: pixel_layers.hpp) or the rod's and wires'
// metal takes this many times the samples.  The denoiser averages a surface's light with its
// neighbours' but not a mixed pixel's coverage or a thin highlight, so those pixels kept most
// of a denoised still's error.  Turntable frames do not: their time budget (docs/benchmarks.md,
// "Mixed pixels sampled more", measures both).
constexpr int kMixedSppFactor = 4;
GeometryData garment_geometry(FrameGeometry& geometry) {
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
    return garment;
}

}  // namespace

void set_ftz_daz() {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

struct Tracer::Impl {
    EmbreeScene scene;
    LightSampler lights;
    Materials materials;
    PathIntegrator integrator;
    bool transparent;

    Impl(const SceneSpec& spec)
        : lights(spec.lights, spec.environment),
          materials(spec),
          integrator(scene, lights, materials, std::max(1, spec.max_depth), spec.transparent),
          transparent(spec.transparent) {}
};

Tracer::Tracer(const SceneSpec& scene, FrameGeometry geometry) {
    if (scene.lights.size() > static_cast<std::size_t>(kMaxLights))
        throw InputError(scene.file.string() + ": at most " + std::to_string(kMaxLights) + " lights are supported");
    impl_ = std::make_unique<Impl>(scene);
    impl_->scene.add(garment_geometry(geometry));
    for (StudioMesh& s : geometry.studio) {
        GeometryData g;
        g.material = s.material;
        g.positions = std::move(s.positions);
        g.normals = std::move(s.normals);
        g.triangles = std::move(s.triangles);
        impl_->scene.add(std::move(g));
    }
    impl_->scene.commit();
}

Tracer::~Tracer() = default;

void* Tracer::embree_scene() const { return impl_->scene.handle(); }

TraceSettings trace_settings(const SceneSpec& scene, const RenderOptions& options) {
    TraceSettings settings;
    settings.width = options.width > 0 ? options.width : scene.width;
    settings.height = options.height > 0 ? options.height : scene.height;
    settings.spp = options.spp > 0 ? options.spp : scene.spp;
    settings.seed = options.seed.value_or(scene.seed);
    // More threads than the machine has buy nothing (the image is the same for any count)
    // and make TBB print a warning of its own.
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    settings.threads = options.threads > 0 ? std::min(options.threads, cores) : 0;
    settings.aovs = options.aovs;
    settings.denoise = options.denoise;
    settings.keep_raw = options.keep_raw;
    settings.noise_threshold = options.noise_threshold;
    settings.exposure_ev = scene.exposure_ev;
    return settings;
}

namespace {
// The image kept as `raw` when asked, then denoised: render()'s last step and the turntable's.
void denoise_beauty(RenderResult& result, const PixelFeatures& features, bool keep_raw, int threads,
                    DenoiseBudget budget) {
    if (keep_raw) result.raw = result.beauty;
    denoise(result.beauty, features, threads, budget);
}
}  // namespace

void denoise_traced(RenderResult& result, bool keep_raw, int threads) {
    if (!result.features) throw std::logic_error("denoise_traced: the frame was traced without keep_features");
    denoise_beauty(result, *result.features, keep_raw, threads, DenoiseBudget::frame);
}

RenderResult Tracer::render(const Camera& camera, const TraceSettings& settings, const ProgressFn& progress) const {
    const auto start = std::chrono::steady_clock::now();
    const Impl& m = *impl_;
    const int width = settings.width, height = settings.height, spp = std::max(1, settings.spp);
    const std::size_t pixel_count = static_cast<std::size_t>(width) * height;
    const CameraModel cam(camera, width, height);
    const float pixel_angle = cam.pixel_angle();
    const float threshold = static_cast<float>(settings.noise_threshold);
    const float gain = static_cast<float>(std::exp2(settings.exposure_ev));
    RenderResult result;
    result.beauty = Image{width, height, 4, std::vector<float>(pixel_count * 4, 0.0f)};
    bool want[4] = {false, false, false, false};
    for (Aov a : settings.aovs) want[static_cast<int>(a)] = true;
    const int aov_channels[4] = {3, 3, 1, 1};
    Image aov_img[4];
    for (int a = 0; a < 4; ++a)
        if (want[a])
            aov_img[a] = Image{width, height, aov_channels[a], std::vector<float>(pixel_count * aov_channels[a], 0.0f)};
    // First-hit features: what the denoiser is guided by, and what a turntable's temporal
    // filter matches between frames.
    const bool features_wanted = settings.denoise || settings.keep_features;
    PixelFeatures features;
    if (features_wanted) {
        features.albedo.resize(pixel_count);
        features.normal.resize(pixel_count);
        features.depth.resize(pixel_count);
        features.turning.resize(pixel_count);
        features.cloth.resize(pixel_count);
        features.variance.resize(pixel_count);
    }
    // The half buffers for the denoiser (here or after a turntable's temporal filter).
    const bool halves_wanted = (settings.denoise || (settings.denoised_later && settings.keep_features)) && spp >= 2;
    if (halves_wanted) {
        features.half_a.resize(pixel_count);
        features.half_b.resize(pixel_count);
        features.half_share.resize(pixel_count);
    }
    // A still's layers, for the denoiser's mixed pixels (pixel_layers.hpp).
    const bool layers_wanted = settings.denoise && !m.transparent;
    // The pixels the layers find mixed (or on metal) take kMixedSppFactor x spp samples.
    const int most_spp = layers_wanted ? spp * kMixedSppFactor : spp;
    if (layers_wanted) {
        features.layer_share.resize(pixel_count);
        features.layer_metal.resize(pixel_count);
        for (int l = 0; l < 2; ++l) {
            features.layer_colour[l].resize(pixel_count);
            features.layer_albedo[l].resize(pixel_count);
            features.layer_normal[l].resize(pixel_count);
            features.layer_depth[l].resize(pixel_count);
        }
    }

    const int tiles_x = (width + kTile - 1) / kTile, tiles_y = (height + kTile - 1) / kTile;
    const int tile_count = tiles_x * tiles_y;
    std::atomic<std::uint64_t> total_rays{0}, total_samples{0};
    std::atomic<std::uint64_t> garment_pixels{0}, garment_samples{0};
    std::atomic<int> tiles_done{0};
    std::atomic<std::uint64_t> reused_paths{0};

    // Paths kept by the previous turntable frame (path_reuse.hpp): taken only when this frame
    // is rendered alike, with the same still meshes; within the reuse's memory budget, shared
    // evenly by the tiles so that what is kept does not depend on the threads' order.
    const int slots_per_tile = (kTile / kBlock) * (kTile / kBlock) * spp * 16;
    const std::size_t slot_bytes = std::size_t(tile_count) * std::size_t(slots_per_tile) * sizeof(std::uint32_t);
    // The slots are for spp samples a pixel: a frame whose mixed pixels take more keeps none.
    PathReuse* const reuse = settings.reuse && most_spp == spp && slot_bytes <= settings.reuse->budget_bytes() / 4
                                 ? settings.reuse.get()
                                 : nullptr;
    const std::size_t tile_budget_bytes = reuse ? (reuse->budget_bytes() - slot_bytes) / std::size_t(tile_count) : 0;
    std::optional<TurningMeshes> turning;
    if (reuse) {
        turning.emplace(m.scene);
        Fingerprint f;
        f.value(width), f.value(height), f.value(spp), f.value(settings.seed), f.value(threshold), f.value(gain);
        f.value(settings.denoise || settings.denoised_later), f.value(m.transparent);
        for (const float x : {0.5f, static_cast<float>(width) - 0.5f})
            for (const float y : {0.5f, static_cast<float>(height) - 0.5f}) {
                Vec3f o, d;
                cam.ray(x, y, 0.25f, 0.75f, &o, &d);
                f.value(o), f.value(d);
            }
        turning->fingerprint_still(m.scene, f);
        reuse->begin_frame(f.h, tile_count);
    }

    auto render_tile = [&](int tile) {
        set_ftz_daz();
        const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
        const int x1 = std::min(width, x0 + kTile), y1 = std::min(height, y0 + kTile);
        std::uint64_t rays = 0, samples = 0, tile_garment_pixels = 0, tile_garment_samples = 0, tile_reused = 0;
        KeptTile* const kept = reuse ? &reuse->tile(tile) : nullptr;
        KeptTile fresh;  // what this frame keeps for the next
        PathRecord record;
        if (turning) record.turning = &turning->flags;
        if (kept) {
            fresh.slot.assign(slots_per_tile, KeptTile::kNone);
            // About as many as the last frame kept: no growing by copies.
            fresh.paths.reserve(kept->paths.size() + kept->paths.size() / 8 + 64);
            fresh.rays.reserve(kept->rays.size() + kept->rays.size() / 8 + 256);
        }
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        for (int by = y0; by < y1; by += kBlock)
            for (int bx = x0; bx < x1; bx += kBlock) {
                std::array<PixelSums, 16> sums{};
                std::array<PixelLayers, 16> layers{};
                std::array<bool, 16> inside{}, more{};  // more: the pixel takes most_spp samples
                for (int k = 0; k < 16; ++k) inside[k] = bx + k % kBlock < x1 && by + k / kBlock < y1;
                for (int s = 0; s < most_spp; ++s) {
                    if (s == spp)
                        for (int k = 0; k < 16; ++k) more[k] = layers[k].mixed() || layers[k].any_metal();
                    alignas(64) RTCRayHit16 packet;
                    alignas(64) int valid[16];
                    std::array<Vec3f, 16> origin, dir;
                    std::array<std::optional<PixelSampler>, 16> sampler;
                    bool any = false;
                    for (int k = 0; k < 16; ++k) {
                        const int x = bx + k % kBlock, y = by + k / kBlock;
                        valid[k] = inside[k] && !sums[k].done && (s < spp || more[k]) ? -1 : 0;
                        Vec3f o = Vec3f::Zero(), d = Vec3f::UnitZ();
                        if (valid[k]) {
                            any = true;
                            sampler[k].emplace(settings.seed, static_cast<std::uint64_t>(y) * width + x,
                                               static_cast<std::uint32_t>(s));
                            const Eigen::Vector2f jitter = sampler[k]->get2d();
                            Eigen::Vector2f lens(0.5f, 0.5f);  // a pinhole's: unread
                            if (cam.has_lens())
                                lens = sampler[k]->get2d();
                            else
                                sampler[k]->skip2d();  // no hashing for a sample the pinhole ignores
                            cam.ray(static_cast<float>(x) + jitter.x(), static_cast<float>(y) + jitter.y(), lens.x(),
                                    lens.y(), &o, &d);
                        }
                        origin[k] = o;
                        dir[k] = d;
                        set_packet_ray(packet, k, o, d);
                    }
                    if (!any) break;
                    rtcIntersect16(valid, m.scene.handle(), &ctx, &packet);
                    for (int k = 0; k < 16; ++k) {
                        if (!valid[k]) continue;
                        ++rays;
                        ++samples;
                        RTCRay r;
                        RTCHit h;
                        unpack_lane(packet, k, &r, &h);
                        PathSample sample;
                        bool taken = false;
                        std::size_t slot = 0;
                        if (kept) {
                            const int block = ((by - y0) / kBlock) * (kTile / kBlock) + (bx - x0) / kBlock;
                            slot = (static_cast<std::size_t>(block) * spp + s) * 16 + k;
                            const KeptTile::Path* const p = kept->find(slot);
                            if (p && turning->still_clear(kept->rays_of(*p), p->ray_count)) {
                                sample = p->sample;
                                taken = true;
                                ++tile_reused;
                                fresh.keep(slot, p->sample, kept->rays_of(*p), p->ray_count, tile_budget_bytes);
                            }
                        }
                        if (!taken) {
                            record.clear();
                            sample = m.integrator.trace(origin[k], dir[k], h.geomID != RTC_INVALID_GEOMETRY_ID, r, h,
                                                        pixel_angle, *sampler[k], rays, kept ? &record : nullptr);
                            if (kept && record.keep)
                                fresh.keep(slot, sample, record.rays.data(),
                                           static_cast<std::uint32_t>(record.rays.size()), tile_budget_bytes);
                        }
                        sums[k].add(sample);
                        if (layers_wanted) layers[k].add(sample);
                    }
                    const int taken = s + 1;
                    // Adaptive sampling decides within the first spp samples.
                    if (threshold > 0.0f && taken <= spp && (taken & (taken - 1)) == 0) {
                        if (taken >= kMinAdaptiveSpp && packet_error_below(sums, inside, gain, threshold,
                                                                           settings.denoise || settings.denoised_later))
                            for (PixelSums& p : sums) p.done = true;
                        for (PixelSums& p : sums) p.checkpoint();
                    }
                }
                for (int k = 0; k < 16; ++k) {
                    if (!inside[k]) continue;
                    const int x = bx + k % kBlock, y = by + k / kBlock;
                    const PixelSums& p = sums[k];
                    const float inv = 1.0f / static_cast<float>(p.n);
                    if (2 * p.garment_count > p.n) ++tile_garment_pixels, tile_garment_samples += std::uint64_t(p.n);
                    float* px = result.beauty.at(x, y);
                    const V3 c = m.transparent
                                     ? (p.fg_count > 0 ? V3(p.fg / static_cast<float>(p.fg_count)) : V3::Zero())
                                     : V3(p.all * inv);
                    px[0] = c.x();
                    px[1] = c.y();
                    px[2] = c.z();
                    px[3] = m.transparent ? static_cast<float>(p.fg_count) * inv : 1.0f;
                    if (want[0]) {
                        float* a = aov_img[0].at(x, y);
                        for (int i = 0; i < 3; ++i) a[i] = p.albedo[i] * inv;
                    }
                    if (want[1]) {
                        const V3 n = p.normal.squaredNorm() > 0.0f ? V3(p.normal.normalized()) : V3::Zero();
                        float* a = aov_img[1].at(x, y);
                        for (int i = 0; i < 3; ++i) a[i] = n[i];
                    }
                    if (want[2]) *aov_img[2].at(x, y) = p.depth * inv;
                    if (want[3]) *aov_img[3].at(x, y) = p.fold * inv;
                    if (features_wanted) {
                        const std::size_t i = static_cast<std::size_t>(y) * width + x;
                        features.albedo[i] = p.albedo * inv;
                        features.normal[i] = p.shading_normal.squaredNorm() > 1e-8f
                                                 ? Vec3f(p.shading_normal.normalized())
                                                 : Vec3f::Zero();
                        features.depth[i] = p.depth * inv;
                        features.turning[i] = static_cast<float>(p.turning_count) * inv;
                        features.cloth[i] = static_cast<float>(p.garment_count) * inv;
                        features.variance[i] = p.variance_of_mean();
                    }
                    if (layers_wanted) {
                        const std::size_t i = static_cast<std::size_t>(y) * width + x;
                        const LayerSums& o = layers[k].other;
                        const int n0 = p.n - o.n;
                        features.layer_share[i] = static_cast<float>(o.n) * inv;
                        features.layer_metal[i] = layers[k].metal() ? 1 : 0;
                        const auto keep = [&](int l, const V3& all, const V3& albedo, const V3& normal, float depth,
                                              int n) {
                            const float inv_n = n > 0 ? 1.0f / static_cast<float>(n) : 0.0f;
                            features.layer_colour[l][i] = all * inv_n;
                            features.layer_albedo[l][i] = albedo * inv_n;
                            features.layer_normal[l][i] =
                                normal.squaredNorm() > 1e-8f ? Vec3f(normal.normalized()) : Vec3f::Zero();
                            features.layer_depth[l][i] = depth * inv_n;
                        };
                        keep(0, p.all - o.all, p.albedo - o.albedo, p.shading_normal - o.normal, p.depth - o.depth,
                             n0);
                        keep(1, o.all, o.albedo, o.normal, o.depth, o.n);
                    }
                    if (halves_wanted) {
                        // The two half buffers, each made as the beauty pixel is from its samples.
                        const std::size_t i = static_cast<std::size_t>(y) * width + x;
                        const PixelSums::Snapshot& a = p.first_half();
                        V3 ca = c, cb = c;
                        float share = 0.5f;
                        if (a.n > 0 && a.n < p.n) {
                            const int nb = p.n - a.n, fb = p.fg_count - a.fg_count;
                            if (!m.transparent) {
                                ca = a.all / static_cast<float>(a.n);
                                cb = (p.all - a.all) / static_cast<float>(nb);
                                share = static_cast<float>(a.n) / static_cast<float>(p.n);
                            } else if (a.fg_count > 0 && fb > 0) {
                                ca = a.fg / static_cast<float>(a.fg_count);
                                cb = (p.fg - a.fg) / static_cast<float>(fb);
                                share = static_cast<float>(a.fg_count) / static_cast<float>(p.fg_count);
                            }
                        }
                        features.half_a[i] = ca;
                        features.half_b[i] = cb;
                        features.half_share[i] = share;
                    }
                }
            }
        if (kept) *kept = std::move(fresh);
        reused_paths += tile_reused;
        total_rays += rays;
        total_samples += samples;
        garment_pixels += tile_garment_pixels;
        garment_samples += tile_garment_samples;
        const int done = ++tiles_done;
        if (progress) progress("render", static_cast<double>(done) / tile_count);
    };

    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, tile_count, 1), [&](const tbb::blocked_range<int>& r) {
            for (int t = r.begin(); t != r.end(); ++t) render_tile(t);
        });
    });
    // render() denoises stills; a turntable's frames go through denoise_traced or the
    // temporal filter.
    if (settings.denoise) denoise_beauty(result, features, settings.keep_raw, settings.threads, DenoiseBudget::still);
    if (settings.keep_features) result.features = std::move(features);

    for (int a = 0; a < 4; ++a)
        if (want[a]) result.aovs.push_back({static_cast<Aov>(a), std::move(aov_img[a])});
    result.stats.width = width;
    result.stats.height = height;
    result.stats.spp = spp;
    result.stats.mean_spp = static_cast<double>(total_samples.load()) / static_cast<double>(pixel_count);
    const auto mean = [](std::uint64_t samples, std::uint64_t pixels) {
        return pixels > 0 ? static_cast<double>(samples) / static_cast<double>(pixels) : 0.0;
    };
    result.stats.garment_mean_spp = mean(garment_samples.load(), garment_pixels.load());
    result.stats.backdrop_mean_spp =
        mean(total_samples.load() - garment_samples.load(), pixel_count - garment_pixels.load());
    result.stats.rays = total_rays.load();
    result.stats.reused_paths = reused_paths.load();
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
                        set_packet_ray(packet, k, o, d);
                    }
                    rtcIntersect16(valid, m.scene.handle(), &ctx, &packet);
                    for (int k = 0; k < 16; ++k)
                        if (valid[k] && packet.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID) ++local;
                }
            hits += local;
        });
    });
    return hits.load();
}

}  // namespace foldcast::render
