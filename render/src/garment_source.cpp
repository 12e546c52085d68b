// The scene's garment: folded by drape from inline parameters, or read from a file.
#include <algorithm>
#include <cmath>

#include "foldcast/core/error.hpp"
#include "foldcast/codec/codec.hpp"
#include "foldcast/core/mesh_io.hpp"
#include "foldcast/drape/drape.hpp"
#include "foldcast/render/render.hpp"

namespace foldcast::render {
namespace fs = std::filesystem;

std::vector<float> fold_sign_from_geometry(const Mesh& mesh) {
    const std::size_t n = mesh.positions.size();
    std::vector<float> sign(n, 0.0f);
    if (n == 0) return sign;
    // Vertex neighbours from the triangles.
    std::vector<std::vector<std::uint32_t>> nbr(n);
    for (const Triangle& t : mesh.topology.triangles)
        for (int k = 0; k < 3; ++k) {
            nbr[t[k]].push_back(t[(k + 1) % 3]);
            nbr[t[k]].push_back(t[(k + 2) % 3]);
        }
    // Smooth away the folds (uniform Laplacian, many passes) and measure each vertex's
    // offset from the smoothed surface along its normal.
    std::vector<Eigen::Vector3d> p(n), q(n);
    for (std::size_t i = 0; i < n; ++i) p[i] = mesh.positions[i].cast<double>();
    const std::vector<Eigen::Vector3d> original = p;
    for (int it = 0; it < 60; ++it) {
        for (std::size_t i = 0; i < n; ++i) {
            if (nbr[i].empty()) {
                q[i] = p[i];
                continue;
            }
            Eigen::Vector3d avg = Eigen::Vector3d::Zero();
            for (std::uint32_t j : nbr[i]) avg += p[j];
            q[i] = 0.5 * p[i] + 0.5 * avg / static_cast<double>(nbr[i].size());
        }
        std::swap(p, q);
    }
    std::vector<Vec3f> smooth(n);
    for (std::size_t i = 0; i < n; ++i) smooth[i] = p[i].cast<float>();
    const std::vector<Vec3f> normals = vertex_normals(smooth, mesh.topology.triangles);
    Vec3f mean_normal = Vec3f::Zero();
    for (const Vec3f& nn : normals) mean_normal += nn;
    const float orient = mean_normal.z() < 0.0f ? -1.0f : 1.0f;  // + = towards +z (the viewer)
    std::vector<float> offset(n);
    for (std::size_t i = 0; i < n; ++i)
        offset[i] = orient * static_cast<float>((original[i] - p[i]).dot(normals[i].cast<double>()));
    std::vector<float> mags(n);
    for (std::size_t i = 0; i < n; ++i) mags[i] = std::abs(offset[i]);
    std::nth_element(mags.begin(), mags.begin() + static_cast<long>(n * 9 / 10), mags.end());
    const float scale = std::max(1e-9f, mags[n * 9 / 10]);
    for (std::size_t i = 0; i < n; ++i) sign[i] = std::clamp(offset[i] / scale, -1.0f, 1.0f);
    return sign;
}

namespace {

GarmentData from_animation(Animation anim, double scale) {
    GarmentData g;
    for (auto& frame : anim.frames)
        for (Vec3f& v : frame) v *= static_cast<float>(scale);
    validate(anim, "garment (after garment.scale = " + std::to_string(scale) + ")");
    g.animation = std::move(anim);
    for (std::size_t f = 0; f < g.animation.frame_count(); ++f)
        g.fold_sign.push_back(fold_sign_from_geometry(g.animation.frame_mesh(f)));
    // Files carry no supports: take the two top corners (highest points at the far left and
    // right) so clips can be drawn there.
    const auto& first = g.animation.frames.front();
    if (!first.empty()) {
        const Bounds b = bounds(first);
        const float top_band = b.max.y() - 0.02f * std::max(1e-6f, b.max.y() - b.min.y());
        std::size_t left = 0, right = 0;
        bool found = false;
        for (std::size_t i = 0; i < first.size(); ++i) {
            if (first[i].y() < top_band) continue;
            if (!found || first[i].x() < first[left].x()) left = i;
            if (!found || first[i].x() > first[right].x()) right = i;
            found = true;
        }
        if (found && left != right)
            g.support_vertices = {static_cast<std::uint32_t>(left), static_cast<std::uint32_t>(right)};
    }
    return g;
}

}  // namespace

GarmentData load_garment(const SceneSpec& scene, const ProgressFn& progress) {
    const GarmentSpec& spec = scene.garment;
    switch (spec.source) {
        case GarmentSpec::Source::drape: {
            drape::ClothParams params =
                drape::cloth_from_look(scene.look.mechanics, spec.width_m, spec.height_m, spec.inset_m);
            params.supports = spec.supports;
            params.support_drop_m = spec.support_drop_m;
            drape::closure_from_name(spec.closure, params.closure);  // the scene file allows only known names
            const drape::FoldSolution solution = drape::solve_folds(params);
            const drape::GridSize grid{spec.grid_nu, spec.grid_nv};
            drape::Garment garment = drape::build_garment(params, solution, grid, spec.relax);
            GarmentData g;
            for (int v : garment.support_vertices) g.support_vertices.push_back(static_cast<std::uint32_t>(v));
            if (spec.animation_frames > 0) {
                drape::AnimationOptions options;
                options.frames = spec.animation_frames;
                options.fps = scene.turntable_fps;
                options.sway_amplitude_m = spec.sway_amplitude_m;
                options.relax = spec.relax;
                g.animation = drape::animate(params, grid, options, progress);
                for (std::size_t f = 0; f < g.animation.frame_count(); ++f)
                    g.fold_sign.push_back(fold_sign_from_geometry(g.animation.frame_mesh(f)));
            } else {
                g.animation.topology = garment.mesh.topology;
                g.animation.frames.push_back(garment.mesh.positions);
                g.fold_sign.push_back(garment.fold_sign);
            }
            return g;
        }
        case GarmentSpec::Source::obj: {
            const Mesh mesh = read_obj(spec.path);
            Animation anim;
            anim.topology = mesh.topology;
            anim.frames.push_back(mesh.positions);
            return from_animation(std::move(anim), spec.scale);
        }
        case GarmentSpec::Source::pc2: {
            fs::path topo = spec.topology;
            if (topo.empty()) topo = fs::path(spec.path).replace_extension(".obj");
            if (!fs::exists(topo))
                throw InputError("garment.path " + spec.path.string() + ": a .pc2 needs its topology: " +
                                 topo.string() + " does not exist (set garment.topology)");
            return from_animation(read_pc2_animation(spec.path, topo, scene.turntable_fps), spec.scale);
        }
        case GarmentSpec::Source::fca:
            return from_animation(codec::decode(codec::read_fca(spec.path), spec.path.string()), spec.scale);
    }
    throw InputError("garment.source: unknown");
}

}  // namespace foldcast::render
