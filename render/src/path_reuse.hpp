#pragma once
// Paths carried from one turntable frame to the next.  A turntable's camera, lights and
// cyclorama stand still while the garment and its supports turn, and every frame traces each
// pixel with the same sampler seed; so a camera path whose rays all missed the turning meshes
// (and none of whose shadow rays was blocked) takes, in the next frame, the very same rays
// to the very same hits, unless the turned meshes now cross one of those rays.  The tracer
// keeps such paths (their sample and their rays) and, in the next frame, tests each kept
// ray against the turning meshes alone: when none crosses, the kept sample is what tracing
// would give, to the bit, and is taken instead.  A path that touched the turning meshes, or
// whose shadow ray was blocked (by what, an occlusion query does not say), is traced again.
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "foldcast/core/math.hpp"
#include "embree_scene.hpp"
#include "path_integrator.hpp"

namespace foldcast::render {

// One ray as the path cast it: [0, tmax) along d from o (tmax: its hit's distance, or
// infinity for a ray that left the scene or a shadow ray's length).
struct KeptRay {
    float o[3], d[3];
    float tmax;
};

// The rays one path casts while it is traced, and whether it may be kept.
struct PathRecord {
    const std::vector<char>* turning = nullptr;  // per Embree geometry: turns with the garment
    std::vector<KeptRay> rays;
    bool keep = true;
    void clear() {
        rays.clear();
        keep = true;
    }
    // Rays are only collected while the path may still be kept.
    void add(const Vec3f& o, const Vec3f& d, float tmax) {
        if (keep) rays.push_back({{o.x(), o.y(), o.z()}, {d.x(), d.y(), d.z()}, tmax});
    }
    // A closest-hit query's outcome: kept as a ray up to its hit, and the path not kept
    // when that hit is on a turning mesh.
    void hit(const Vec3f& o, const Vec3f& d, bool any, float t, unsigned geometry);
    // A shadow ray's: kept when it reached its light.
    void shadow(const Vec3f& o, const Vec3f& d, float tmax, bool occluded) {
        if (occluded)
            keep = false;
        else
            add(o, d, tmax);
    }
};

inline void PathRecord::hit(const Vec3f& o, const Vec3f& d, bool any, float t, unsigned geometry) {
    if (any && (*turning)[geometry]) keep = false;
    add(o, d, any ? t : std::numeric_limits<float>::infinity());
}

// A frame's kept paths, tile by tile (each tile written by the one thread rendering it).
struct KeptTile {
    static constexpr std::uint32_t kNone = 0xffffffffu;
    struct Path {
        PathSample sample;
        std::uint32_t first_ray = 0, ray_count = 0;
    };
    // Per (4x4 packet of the tile, sample number, lane): the kept path's index, or kNone.
    std::vector<std::uint32_t> slot;
    std::vector<Path> paths;
    std::vector<KeptRay> rays;
    // The path kept for `slot`, or null.
    const Path* find(std::size_t slot_index) const {
        const std::uint32_t index = slot.empty() ? kNone : slot[slot_index];
        return index == kNone ? nullptr : &paths[index];
    }
    const KeptRay* rays_of(const Path& p) const { return rays.data() + p.first_ray; }
    // Keeps `sample` and its `count` rays for `slot`, unless the tile's paths would then pass
    // `budget_bytes`.
    void keep(std::size_t slot_index, const PathSample& sample, const KeptRay* path_rays, std::uint32_t count,
              std::size_t budget_bytes) {
        if ((paths.size() + 1) * sizeof(Path) + (rays.size() + count) * sizeof(KeptRay) > budget_bytes) return;
        slot[slot_index] = static_cast<std::uint32_t>(paths.size());
        paths.push_back({sample, static_cast<std::uint32_t>(rays.size()), count});
        rays.insert(rays.end(), path_rays, path_rays + count);
    }
};

// What the previous frame kept, and what it was rendered as: paths are only taken by a frame
// rendered alike (size, samples, seed, threshold, camera, the still meshes).
class PathReuse {
public:
    explicit PathReuse(std::size_t budget_bytes) : budget_bytes_(budget_bytes) {}
    std::size_t budget_bytes() const { return budget_bytes_; }
    // Starts a frame whose set-up hashes to `signature`: what was kept is dropped unless the
    // frame that kept it hashed the same.
    void begin_frame(std::uint64_t signature, int tile_count);
    KeptTile& tile(int index) { return tiles_[static_cast<std::size_t>(index)]; }

private:
    std::size_t budget_bytes_;
    std::uint64_t signature_ = 0;
    std::vector<KeptTile> tiles_;
};

// FNV-1a over raw bytes: what a frame that takes kept paths must share with the one that kept them.
struct Fingerprint {
    std::uint64_t h = 0xcbf29ce484222325ULL;
    void bytes(const void* p, std::size_t n) {
        const auto* b = static_cast<const unsigned char*>(p);
        for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ULL;
    }
    template <class T>
    void value(const T& v) {
        bytes(&v, sizeof(v));
    }
};

// A frame's meshes that turn with the garment (all but the backdrop): which of the frame's
// Embree geometries they are, and an Embree scene of them alone with its bounding box, for
// testing kept rays against them.
class TurningMeshes {
public:
    explicit TurningMeshes(const EmbreeScene& all);
    std::vector<char> flags;  // per geometry of `all`: turns
    // Adds the still meshes (positions, triangles, normals, materials) to f.
    void fingerprint_still(const EmbreeScene& all, Fingerprint& f) const;
    // Whether all `count` kept rays still miss the turning meshes.
    bool still_clear(const KeptRay* rays, std::uint32_t count) const;

private:
    // Slab test over [0, tmax] against the padded box: a kept ray that misses the box misses
    // the meshes, without a query (most kept rays run on the backdrop's side, away from them).
    bool crosses_box(const KeptRay& r) const;

    std::unique_ptr<EmbreeScene> scene_;
    Vec3f lo_, hi_;
};

}  // namespace foldcast::render
