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

namespace {

// One pixel packet's running sums while its samples are traced.
struct PacketSums {
    std::array<PixelSums, 16> sums{};
    std::array<PixelLayers, 16> layers{};
    std::array<bool, 16> inside{}, more{};  // more: the pixel takes most_spp samples
};

// One tile's work: its bounds, its counters (added to the frame's once it is done), and the
// paths the previous frame kept for it and this frame keeps for the next.
struct TileWork {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    std::uint64_t rays = 0, samples = 0, garment_pixels = 0, garment_samples = 0, reused = 0;
    KeptTile* kept = nullptr;
    KeptTile fresh;
    PathRecord record;
    RTCIntersectContext ctx;
};

// One frame of Tracer::render, in its steps: the output buffers the settings ask for, the
// path reuse, each tile (each 4x4 packet: its samples traced, then its pixels written) and
// the statistics.
class FrameRender {
public:
    FrameRender(const EmbreeScene& scene, const PathIntegrator& integrator, bool transparent, const Camera& camera,
                const TraceSettings& settings, const ProgressFn& progress)
        : scene_(scene),
          integrator_(integrator),
          transparent_(transparent),
          settings_(settings),
          progress_(progress),
          width_(settings.width),
          height_(settings.height),
          spp_(std::max(1, settings.spp)),
          pixel_count_(static_cast<std::size_t>(width_) * height_),
          cam_(camera, width_, height_),
          pixel_angle_(cam_.pixel_angle()),
          threshold_(static_cast<float>(settings.noise_threshold)),
          gain_(static_cast<float>(std::exp2(settings.exposure_ev))) {
        allocate_outputs();
        tiles_x_ = (width_ + kTile - 1) / kTile;
        tile_count_ = tiles_x_ * ((height_ + kTile - 1) / kTile);
        prepare_reuse();
    }

    int tile_count() const { return tile_count_; }
    void render_tile(int tile);
    // The result once every tile is done: the still denoised when asked, its statistics.
    RenderResult finish(std::chrono::steady_clock::time_point start);

private:
    void allocate_outputs();
    void prepare_reuse();
    void render_packet(TileWork& t, int bx, int by);
    bool trace_packet_sample(TileWork& t, PacketSums& b, int bx, int by, int s);
    PathSample lane_sample(TileWork& t, const RTCRayHit16& packet, int k, const Vec3f& origin, const Vec3f& dir,
                           PixelSampler& sampler, int bx, int by, int s);
    void write_pixel(TileWork& t, const PacketSums& b, int k, int x, int y);
    void write_features(std::size_t i, const PixelSums& p, float inv);
    void write_layers(std::size_t i, const PixelSums& p, const PixelLayers& layers, float inv);
    void write_halves(std::size_t i, const PixelSums& p, const V3& c);

    const EmbreeScene& scene_;
    const PathIntegrator& integrator_;
    const bool transparent_;
    const TraceSettings& settings_;
    const ProgressFn& progress_;
    const int width_, height_, spp_;
    const std::size_t pixel_count_;
    const CameraModel cam_;
    const float pixel_angle_, threshold_, gain_;

    RenderResult result_;
    bool want_[4] = {false, false, false, false};
    Image aov_img_[4];
    // First-hit features: what the denoiser is guided by, and what a turntable's temporal
    // filter matches between frames.
    bool features_wanted_ = false, halves_wanted_ = false, layers_wanted_ = false;
    PixelFeatures features_;
    int most_spp_ = 0;

    int tiles_x_ = 0, tile_count_ = 0;
    std::atomic<std::uint64_t> total_rays_{0}, total_samples_{0};
    std::atomic<std::uint64_t> garment_pixels_{0}, garment_samples_{0};
    std::atomic<int> tiles_done_{0};
    std::atomic<std::uint64_t> reused_paths_{0};

    PathReuse* reuse_ = nullptr;
    int slots_per_tile_ = 0;
    std::size_t tile_budget_bytes_ = 0;
    std::optional<TurningMeshes> turning_;
};

void FrameRender::allocate_outputs() {
    const std::size_t n = pixel_count_;
    result_.beauty = Image{width_, height_, 4, std::vector<float>(n * 4, 0.0f)};
    for (Aov a : settings_.aovs) want_[static_cast<int>(a)] = true;
    const int aov_channels[4] = {3, 3, 1, 1};
    for (int a = 0; a < 4; ++a)
        if (want_[a])
            aov_img_[a] = Image{width_, height_, aov_channels[a], std::vector<float>(n * aov_channels[a], 0.0f)};
    features_wanted_ = settings_.denoise || settings_.keep_features;
    if (features_wanted_) {
        features_.albedo.resize(n);
        features_.normal.resize(n);
        features_.depth.resize(n);
        features_.turning.resize(n);
        features_.cloth.resize(n);
        features_.variance.resize(n);
    }
    // The half buffers for the denoiser (here or after a turntable's temporal filter).
    halves_wanted_ = (settings_.denoise || (settings_.denoised_later && settings_.keep_features)) && spp_ >= 2;
    if (halves_wanted_) {
        features_.half_a.resize(n);
        features_.half_b.resize(n);
        features_.half_share.resize(n);
    }
    // A still's layers, for the denoiser's mixed pixels (pixel_layers.hpp).
    layers_wanted_ = settings_.denoise && !transparent_;
    // The pixels the layers find mixed (or on metal) take kMixedSppFactor x spp samples.
    most_spp_ = layers_wanted_ ? spp_ * kMixedSppFactor : spp_;
    if (layers_wanted_) {
        features_.layer_share.resize(n);
        features_.layer_metal.resize(n);
        for (int l = 0; l < 2; ++l) {
            features_.layer_colour[l].resize(n);
            features_.layer_albedo[l].resize(n);
            features_.layer_normal[l].resize(n);
            features_.layer_depth[l].resize(n);
        }
    }
}

// Paths kept by the previous turntable frame (path_reuse.hpp): taken only when this frame
// is rendered alike, with the same still meshes; within the reuse's memory budget, shared
// evenly by the tiles so that what is kept does not depend on the threads' order.
void FrameRender::prepare_reuse() {
    slots_per_tile_ = (kTile / kBlock) * (kTile / kBlock) * spp_ * 16;
    const std::size_t slot_bytes = std::size_t(tile_count_) * std::size_t(slots_per_tile_) * sizeof(std::uint32_t);
    // The slots are for spp samples a pixel: a frame whose mixed pixels take more keeps none.
    reuse_ = settings_.reuse && most_spp_ == spp_ && slot_bytes <= settings_.reuse->budget_bytes() / 4
                 ? settings_.reuse.get()
                 : nullptr;
    tile_budget_bytes_ = reuse_ ? (reuse_->budget_bytes() - slot_bytes) / std::size_t(tile_count_) : 0;
    if (!reuse_) return;
    turning_.emplace(scene_);
    Fingerprint f;
    f.value(width_), f.value(height_), f.value(spp_), f.value(settings_.seed), f.value(threshold_), f.value(gain_);
    f.value(settings_.denoise || settings_.denoised_later), f.value(transparent_);
    for (const float x : {0.5f, static_cast<float>(width_) - 0.5f})
        for (const float y : {0.5f, static_cast<float>(height_) - 0.5f}) {
            Vec3f o, d;
            cam_.ray(x, y, 0.25f, 0.75f, &o, &d);
            f.value(o), f.value(d);
        }
    turning_->fingerprint_still(scene_, f);
    reuse_->begin_frame(f.h, tile_count_);
}

void FrameRender::render_tile(int tile) {
    set_ftz_daz();
    TileWork t;
    t.x0 = (tile % tiles_x_) * kTile, t.y0 = (tile / tiles_x_) * kTile;
    t.x1 = std::min(width_, t.x0 + kTile), t.y1 = std::min(height_, t.y0 + kTile);
    t.kept = reuse_ ? &reuse_->tile(tile) : nullptr;
    if (turning_) t.record.turning = &turning_->flags;
    if (t.kept) {
        t.fresh.slot.assign(slots_per_tile_, KeptTile::kNone);
        // About as many as the last frame kept: no growing by copies.
        t.fresh.paths.reserve(t.kept->paths.size() + t.kept->paths.size() / 8 + 64);
        t.fresh.rays.reserve(t.kept->rays.size() + t.kept->rays.size() / 8 + 256);
    }
    rtcInitIntersectContext(&t.ctx);
    t.ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    for (int by = t.y0; by < t.y1; by += kBlock)
        for (int bx = t.x0; bx < t.x1; bx += kBlock) render_packet(t, bx, by);
    if (t.kept) *t.kept = std::move(t.fresh);
    reused_paths_ += t.reused;
    total_rays_ += t.rays;
    total_samples_ += t.samples;
    garment_pixels_ += t.garment_pixels;
    garment_samples_ += t.garment_samples;
    const int done = ++tiles_done_;
    if (progress_) progress_("render", static_cast<double>(done) / tile_count_);
}

void FrameRender::render_packet(TileWork& t, int bx, int by) {
    PacketSums b;
    for (int k = 0; k < 16; ++k) b.inside[k] = bx + k % kBlock < t.x1 && by + k / kBlock < t.y1;
    for (int s = 0; s < most_spp_; ++s) {
        if (s == spp_)
            for (int k = 0; k < 16; ++k) b.more[k] = b.layers[k].mixed() || b.layers[k].any_metal();
        if (!trace_packet_sample(t, b, bx, by, s)) break;
        const int taken = s + 1;
        // Adaptive sampling decides within the first spp samples.
        if (threshold_ > 0.0f && taken <= spp_ && (taken & (taken - 1)) == 0) {
            if (taken >= kMinAdaptiveSpp &&
                packet_error_below(b.sums, b.inside, gain_, threshold_, settings_.denoise || settings_.denoised_later))
                for (PixelSums& p : b.sums) p.done = true;
            for (PixelSums& p : b.sums) p.checkpoint();
        }
    }
    for (int k = 0; k < 16; ++k)
        if (b.inside[k]) write_pixel(t, b, k, bx + k % kBlock, by + k / kBlock);
}

// Sample s of the packet's pixels that still take samples; false when none does.
bool FrameRender::trace_packet_sample(TileWork& t, PacketSums& b, int bx, int by, int s) {
    alignas(64) RTCRayHit16 packet;
    alignas(64) int valid[16];
    std::array<Vec3f, 16> origin, dir;
    std::array<std::optional<PixelSampler>, 16> sampler;
    bool any = false;
    for (int k = 0; k < 16; ++k) {
        const int x = bx + k % kBlock, y = by + k / kBlock;
        valid[k] = b.inside[k] && !b.sums[k].done && (s < spp_ || b.more[k]) ? -1 : 0;
        Vec3f o = Vec3f::Zero(), d = Vec3f::UnitZ();
        if (valid[k]) {
            any = true;
            sampler[k].emplace(settings_.seed, static_cast<std::uint64_t>(y) * width_ + x,
                               static_cast<std::uint32_t>(s));
            const Eigen::Vector2f jitter = sampler[k]->get2d();
            Eigen::Vector2f lens(0.5f, 0.5f);  // a pinhole's: unread
            if (cam_.has_lens())
                lens = sampler[k]->get2d();
            else
                sampler[k]->skip2d();  // no hashing for a sample the pinhole ignores
            cam_.ray(static_cast<float>(x) + jitter.x(), static_cast<float>(y) + jitter.y(), lens.x(), lens.y(), &o,
                     &d);
        }
        origin[k] = o;
        dir[k] = d;
        set_packet_ray(packet, k, o, d);
    }
    if (!any) return false;
    rtcIntersect16(valid, scene_.handle(), &t.ctx, &packet);
    for (int k = 0; k < 16; ++k) {
        if (!valid[k]) continue;
        ++t.rays;
        ++t.samples;
        const PathSample sample = lane_sample(t, packet, k, origin[k], dir[k], *sampler[k], bx, by, s);
        b.sums[k].add(sample);
        if (layers_wanted_) b.layers[k].add(sample);
    }
    return true;
}

// One lane's camera path: the previous frame's where it is still clear, else traced afresh.
PathSample FrameRender::lane_sample(TileWork& t, const RTCRayHit16& packet, int k, const Vec3f& origin,
                                    const Vec3f& dir, PixelSampler& sampler, int bx, int by, int s) {
    RTCRay r;
    RTCHit h;
    unpack_lane(packet, k, &r, &h);
    std::size_t slot = 0;
    if (t.kept) {
        const int block = ((by - t.y0) / kBlock) * (kTile / kBlock) + (bx - t.x0) / kBlock;
        slot = (static_cast<std::size_t>(block) * spp_ + s) * 16 + k;
        const KeptTile::Path* const p = t.kept->find(slot);
        if (p && turning_->still_clear(t.kept->rays_of(*p), p->ray_count)) {
            ++t.reused;
            t.fresh.keep(slot, p->sample, t.kept->rays_of(*p), p->ray_count, tile_budget_bytes_);
            return p->sample;
        }
    }
    t.record.clear();
    const PathSample sample = integrator_.trace(origin, dir, h.geomID != RTC_INVALID_GEOMETRY_ID, r, h, pixel_angle_,
                                                sampler, t.rays, t.kept ? &t.record : nullptr);
    if (t.kept && t.record.keep)
        t.fresh.keep(slot, sample, t.record.rays.data(), static_cast<std::uint32_t>(t.record.rays.size()),
                     tile_budget_bytes_);
    return sample;
}

void FrameRender::write_pixel(TileWork& t, const PacketSums& b, int k, int x, int y) {
    const PixelSums& p = b.sums[k];
    const float inv = 1.0f / static_cast<float>(p.n);
    if (2 * p.garment_count > p.n) ++t.garment_pixels, t.garment_samples += std::uint64_t(p.n);
    float* px = result_.beauty.at(x, y);
    const V3 c =
        transparent_ ? (p.fg_count > 0 ? V3(p.fg / static_cast<float>(p.fg_count)) : V3::Zero()) : V3(p.all * inv);
    px[0] = c.x();
    px[1] = c.y();
    px[2] = c.z();
    px[3] = transparent_ ? static_cast<float>(p.fg_count) * inv : 1.0f;
    if (want_[0]) {
        float* a = aov_img_[0].at(x, y);
        for (int i = 0; i < 3; ++i) a[i] = p.albedo[i] * inv;
    }
    if (want_[1]) {
        const V3 n = p.normal.squaredNorm() > 0.0f ? V3(p.normal.normalized()) : V3::Zero();
        float* a = aov_img_[1].at(x, y);
        for (int i = 0; i < 3; ++i) a[i] = n[i];
    }
    if (want_[2]) *aov_img_[2].at(x, y) = p.depth * inv;
    if (want_[3]) *aov_img_[3].at(x, y) = p.fold * inv;
    const std::size_t i = static_cast<std::size_t>(y) * width_ + x;
    if (features_wanted_) write_features(i, p, inv);
    if (layers_wanted_) write_layers(i, p, b.layers[k], inv);
    if (halves_wanted_) write_halves(i, p, c);
}

void FrameRender::write_features(std::size_t i, const PixelSums& p, float inv) {
    features_.albedo[i] = p.albedo * inv;
    features_.normal[i] = p.shading_normal.squaredNorm() > 1e-8f ? Vec3f(p.shading_normal.normalized()) : Vec3f::Zero();
    features_.depth[i] = p.depth * inv;
    features_.turning[i] = static_cast<float>(p.turning_count) * inv;
    features_.cloth[i] = static_cast<float>(p.garment_count) * inv;
    features_.variance[i] = p.variance_of_mean();
}

void FrameRender::write_layers(std::size_t i, const PixelSums& p, const PixelLayers& layers, float inv) {
    const LayerSums& o = layers.other;
    const int n0 = p.n - o.n;
    features_.layer_share[i] = static_cast<float>(o.n) * inv;
    features_.layer_metal[i] = layers.metal() ? 1 : 0;
    const auto keep = [&](int l, const V3& all, const V3& albedo, const V3& normal, float depth, int n) {
        const float inv_n = n > 0 ? 1.0f / static_cast<float>(n) : 0.0f;
        features_.layer_colour[l][i] = all * inv_n;
        features_.layer_albedo[l][i] = albedo * inv_n;
        features_.layer_normal[l][i] = normal.squaredNorm() > 1e-8f ? Vec3f(normal.normalized()) : Vec3f::Zero();
        features_.layer_depth[l][i] = depth * inv_n;
    };
    keep(0, p.all - o.all, p.albedo - o.albedo, p.shading_normal - o.normal, p.depth - o.depth, n0);
    keep(1, o.all, o.albedo, o.normal, o.depth, o.n);
}

// The two half buffers, each made as the beauty pixel is from its samples.
void FrameRender::write_halves(std::size_t i, const PixelSums& p, const V3& c) {
    const PixelSums::Snapshot& a = p.first_half();
    V3 ca = c, cb = c;
    float share = 0.5f;
    if (a.n > 0 && a.n < p.n) {
        const int nb = p.n - a.n, fb = p.fg_count - a.fg_count;
        if (!transparent_) {
            ca = a.all / static_cast<float>(a.n);
            cb = (p.all - a.all) / static_cast<float>(nb);
            share = static_cast<float>(a.n) / static_cast<float>(p.n);
        } else if (a.fg_count > 0 && fb > 0) {
            ca = a.fg / static_cast<float>(a.fg_count);
            cb = (p.fg - a.fg) / static_cast<float>(fb);
            share = static_cast<float>(a.fg_count) / static_cast<float>(p.fg_count);
        }
    }
    features_.half_a[i] = ca;
    features_.half_b[i] = cb;
    features_.half_share[i] = share;
}

RenderResult FrameRender::finish(std::chrono::steady_clock::time_point start) {
    // render() denoises stills; a turntable's frames go through denoise_traced or the
    // temporal filter.
    if (settings_.denoise)
        denoise_beauty(result_, features_, settings_.keep_raw, settings_.threads, DenoiseBudget::still);
    if (settings_.keep_features) result_.features = std::move(features_);
    for (int a = 0; a < 4; ++a)
        if (want_[a]) result_.aovs.push_back({static_cast<Aov>(a), std::move(aov_img_[a])});
    RenderStats& stats = result_.stats;
    stats.width = width_;
    stats.height = height_;
    stats.spp = spp_;
    stats.mean_spp = static_cast<double>(total_samples_.load()) / static_cast<double>(pixel_count_);
    const auto mean = [](std::uint64_t samples, std::uint64_t pixels) {
        return pixels > 0 ? static_cast<double>(samples) / static_cast<double>(pixels) : 0.0;
    };
    stats.garment_mean_spp = mean(garment_samples_.load(), garment_pixels_.load());
    stats.backdrop_mean_spp =
        mean(total_samples_.load() - garment_samples_.load(), pixel_count_ - garment_pixels_.load());
    stats.rays = total_rays_.load();
    stats.reused_paths = reused_paths_.load();
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return std::move(result_);
}

}  // namespace

RenderResult Tracer::render(const Camera& camera, const TraceSettings& settings, const ProgressFn& progress) const {
    const auto start = std::chrono::steady_clock::now();
    FrameRender frame(impl_->scene, impl_->integrator, impl_->transparent, camera, settings, progress);
    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, frame.tile_count(), 1), [&](const tbb::blocked_range<int>& r) {
            for (int t = r.begin(); t != r.end(); ++t) frame.render_tile(t);
        });
    });
    return frame.finish(start);
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
