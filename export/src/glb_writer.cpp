#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/export/gltf.hpp"
#include "glb_builder.hpp"
#include "material.hpp"
#include "tangents.hpp"

namespace foldcast::gltf {

namespace {
// Morph-target animations key every target at every frame: frames^2 weights.
constexpr std::size_t kMaxMorphFrames = 2000;
// Quantized positions use 15 of a short's bits so that a morph target's delta (the
// difference of two of them) still fits in a short.
constexpr int kPositionLevels = 16383;

template <class T>
std::string_view bytes_of(const std::vector<T>& v) {
    return {reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T)};
}

std::int16_t snorm16(float v) { return static_cast<std::int16_t>(std::lround(std::clamp(v, -1.0f, 1.0f) * 32767.0f)); }
std::int8_t snorm8(float v) { return static_cast<std::int8_t>(std::lround(std::clamp(v, -1.0f, 1.0f) * 127.0f)); }

// What every frame contributes: positions, unit normals and (when the material needs them)
// tangents.
struct FrameData {
    std::vector<Vec3f> positions, normals;
    std::vector<Eigen::Vector4f> tangents;
};

struct Layout {
    const Topology* topology = nullptr;
    std::vector<FrameData> frames;
    double fps = 30.0;
    bool tangents = false;
};

nlohmann::json accessor(int view, std::size_t offset, int component, std::size_t count, const char* type,
                        bool normalized = false) {
    nlohmann::json a = {{"bufferView", view}, {"componentType", component}, {"count", count}, {"type", type}};
    if (offset) a["byteOffset"] = offset;
    if (normalized) a["normalized"] = true;
    return a;
}

template <class V>
void set_bounds(nlohmann::json& a, const V& lo, const V& hi) {
    a["min"] = nlohmann::json::array();
    a["max"] = nlohmann::json::array();
    for (int i = 0; i < static_cast<int>(lo.size()); ++i) a["min"].push_back(lo[i]), a["max"].push_back(hi[i]);
}

// Float attributes throughout: the static garment, and animations written uncompressed.
void add_float_streams(GlbBuilder& glb, const Layout& L, nlohmann::json& primitive, std::size_t n) {
    const auto vec3_view = [&](const std::vector<Vec3f>& data) { return glb.add_view(bytes_of(data), kArrayBuffer); };
    const auto bounded = [&](int view, std::size_t offset, const Vec3f* p) {
        Vec3f lo = Vec3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
        for (std::size_t i = 0; i < n; ++i) lo = lo.cwiseMin(p[i]), hi = hi.cwiseMax(p[i]);
        nlohmann::json a = accessor(view, offset, kFloat, n, "VEC3");
        set_bounds(a, lo, hi);
        return glb.add("accessors", std::move(a));
    };
    const FrameData& base = L.frames.front();
    nlohmann::json& attributes = primitive["attributes"];
    attributes["POSITION"] = bounded(vec3_view(base.positions), 0, base.positions.data());
    attributes["NORMAL"] = glb.add("accessors", accessor(vec3_view(base.normals), 0, kFloat, n, "VEC3"));
    if (L.tangents)
        attributes["TANGENT"] =
            glb.add("accessors", accessor(glb.add_view(bytes_of(base.tangents), kArrayBuffer), 0, kFloat, n, "VEC4"));
    const std::size_t targets = L.frames.size() - 1;
    if (!targets) return;
    std::vector<Vec3f> dp, dn, dt;
    dp.reserve(n * targets), dn.reserve(n * targets);
    for (std::size_t f = 1; f < L.frames.size(); ++f)
        for (std::size_t i = 0; i < n; ++i) {
            dp.push_back(L.frames[f].positions[i] - base.positions[i]);
            dn.push_back(L.frames[f].normals[i] - base.normals[i]);
            if (L.tangents) dt.push_back((L.frames[f].tangents[i] - base.tangents[i]).head<3>());
        }
    // Every target's accessor is a slice of one view per attribute: a shared view needs a stride.
    const auto shared_view = [&](const std::vector<Vec3f>& data) {
        return glb.add_view(bytes_of(data), kArrayBuffer, static_cast<int>(sizeof(Vec3f)));
    };
    const int pv = shared_view(dp), nv = shared_view(dn), tv = L.tangents ? shared_view(dt) : -1;
    for (std::size_t t = 0; t < targets; ++t) {
        const std::size_t offset = t * n * sizeof(Vec3f);
        nlohmann::json target = {{"POSITION", bounded(pv, offset, dp.data() + t * n)},
                                 {"NORMAL", glb.add("accessors", accessor(nv, offset, kFloat, n, "VEC3"))}};
        if (L.tangents) target["TANGENT"] = glb.add("accessors", accessor(tv, offset, kFloat, n, "VEC3"));
        primitive["targets"].push_back(target);
    }
}

struct Quantization {
    Vec3f centre = Vec3f::Zero();
    float step = 1.0f;
    std::array<std::int16_t, 3> operator()(const Vec3f& p) const {
        const Vec3f q = (p - centre) / step;
        return {static_cast<std::int16_t>(std::lround(q.x())), static_cast<std::int16_t>(std::lround(q.y())),
                static_cast<std::int16_t>(std::lround(q.z()))};
    }
};

// KHR_mesh_quantization + EXT_meshopt_compression: positions as 15-bit integers (the node's
// scale and translation map them back to metres), normals and tangents as normalized
// shorts, morph deltas of normals and tangents as normalized bytes; every stream compressed.
double add_quantized_streams(GlbBuilder& glb, const Layout& L, nlohmann::json& primitive, nlohmann::json& node,
                             std::size_t n, double max_error_m) {
    Vec3f lo = Vec3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
    for (const FrameData& f : L.frames)
        for (const Vec3f& p : f.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    Quantization quant;
    quant.centre = 0.5f * (lo + hi);
    quant.step = std::max(1e-9f, 0.5f * (hi - lo).maxCoeff() / kPositionLevels);
    // Rounding moves a point by at most half a step per axis: sqrt(3) / 2 steps in all.
    if (max_error_m > 0.0) quant.step = std::max(quant.step, static_cast<float>(max_error_m / std::sqrt(0.75)));
    node["translation"] = {quant.centre.x(), quant.centre.y(), quant.centre.z()};
    node["scale"] = {quant.step, quant.step, quant.step};
    glb.use_extension("KHR_mesh_quantization", true);

    std::vector<std::array<std::int16_t, 3>> base_q(n);
    for (std::size_t i = 0; i < n; ++i) base_q[i] = quant(L.frames.front().positions[i]);
    double max_error = 0.0;
    const auto shorts4 = [&](std::size_t count) { return std::vector<std::int16_t>(4 * count, 0); };
    std::vector<std::int16_t> pos = shorts4(n), nor = shorts4(n), tan = shorts4(n);
    std::array<int, 3> pmin{32767, 32767, 32767}, pmax{-32767, -32767, -32767};
    const FrameData& base = L.frames.front();
    for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            pos[4 * i + c] = base_q[i][c];
            pmin[c] = std::min<int>(pmin[c], base_q[i][c]), pmax[c] = std::max<int>(pmax[c], base_q[i][c]);
            nor[4 * i + c] = snorm16(base.normals[i][c]);
            if (L.tangents) tan[4 * i + c] = snorm16(base.tangents[i][c]);
        }
    if (L.tangents)
        for (std::size_t i = 0; i < n; ++i) tan[4 * i + 3] = snorm16(base.tangents[i].w());
    nlohmann::json& attributes = primitive["attributes"];
    nlohmann::json pa =
        accessor(glb.add_compressed_view(bytes_of(pos), n, 8, kArrayBuffer, false), 0, kShort, n, "VEC3");
    set_bounds(pa, pmin, pmax);
    attributes["POSITION"] = glb.add("accessors", std::move(pa));
    attributes["NORMAL"] = glb.add(
        "accessors",
        accessor(glb.add_compressed_view(bytes_of(nor), n, 8, kArrayBuffer, false), 0, kShort, n, "VEC3", true));
    if (L.tangents)
        attributes["TANGENT"] = glb.add(
            "accessors",
            accessor(glb.add_compressed_view(bytes_of(tan), n, 8, kArrayBuffer, false), 0, kShort, n, "VEC4", true));
    for (std::size_t i = 0; i < n; ++i)
        max_error = std::max<double>(
            max_error,
            (Vec3f(base_q[i][0], base_q[i][1], base_q[i][2]) * quant.step + quant.centre - base.positions[i]).norm());

    const std::size_t targets = L.frames.size() - 1;
    if (!targets) return max_error;
    std::vector<std::int16_t> dp = shorts4(n * targets);
    std::vector<std::int8_t> dn(4 * n * targets, 0), dt(4 * n * targets, 0);
    std::vector<std::array<int, 3>> tmin(targets, {32767, 32767, 32767}), tmax(targets, {-32767, -32767, -32767});
    for (std::size_t t = 0; t < targets; ++t) {
        const FrameData& frame = L.frames[t + 1];
        for (std::size_t i = 0; i < n; ++i) {
            const auto q = quant(frame.positions[i]);
            const std::size_t k = 4 * (t * n + i);
            for (int c = 0; c < 3; ++c) {
                const int d = q[c] - base_q[i][c];
                dp[k + c] = static_cast<std::int16_t>(d);
                tmin[t][c] = std::min(tmin[t][c], d), tmax[t][c] = std::max(tmax[t][c], d);
                dn[k + c] = snorm8(frame.normals[i][c] - base.normals[i][c]);
                if (L.tangents) dt[k + c] = snorm8(frame.tangents[i][c] - base.tangents[i][c]);
            }
            max_error = std::max<double>(
                max_error, (Vec3f(q[0], q[1], q[2]) * quant.step + quant.centre - frame.positions[i]).norm());
        }
    }
    const int pv = glb.add_compressed_view(bytes_of(dp), n * targets, 8, kArrayBuffer, false);
    const int nv = glb.add_compressed_view(bytes_of(dn), n * targets, 4, kArrayBuffer, false);
    const int tv = L.tangents ? glb.add_compressed_view(bytes_of(dt), n * targets, 4, kArrayBuffer, false) : -1;
    for (std::size_t t = 0; t < targets; ++t) {
        nlohmann::json p = accessor(pv, t * n * 8, kShort, n, "VEC3");
        set_bounds(p, tmin[t], tmax[t]);
        nlohmann::json target = {{"POSITION", glb.add("accessors", std::move(p))},
                                 {"NORMAL", glb.add("accessors", accessor(nv, t * n * 4, kByte, n, "VEC3", true))}};
        if (L.tangents) target["TANGENT"] = glb.add("accessors", accessor(tv, t * n * 4, kByte, n, "VEC3", true));
        primitive["targets"].push_back(target);
    }
    return max_error;
}

// One frame after another: target t's weight is 1 at frame t + 1 and 0 elsewhere, linear
// in between, so playback blends neighbouring frames as the cache would.
void add_frame_animation(GlbBuilder& glb, std::size_t frames, double fps, bool compress) {
    const std::size_t targets = frames - 1;
    std::vector<float> times(frames), weights(frames * targets, 0.0f);
    for (std::size_t f = 0; f < frames; ++f) {
        times[f] = static_cast<float>(static_cast<double>(f) / fps);
        if (f > 0) weights[f * targets + (f - 1)] = 1.0f;
    }
    nlohmann::json input = accessor(glb.add_view(bytes_of(times), 0), 0, kFloat, frames, "SCALAR");
    input["min"] = {times.front()};
    input["max"] = {times.back()};
    const int in = glb.add("accessors", std::move(input));
    const int view = compress ? glb.add_compressed_view(bytes_of(weights), weights.size(), 4, 0, false)
                              : glb.add_view(bytes_of(weights), 0);
    const int out = glb.add("accessors", accessor(view, 0, kFloat, weights.size(), "SCALAR"));
    glb.add("animations", {{"name", "frames"},
                           {"samplers", {{{"input", in}, {"output", out}, {"interpolation", "LINEAR"}}}},
                           {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}}}});
}

void add_indices(GlbBuilder& glb, const Topology& topology, std::size_t n, bool compress, nlohmann::json& primitive) {
    const std::size_t count = 3 * topology.triangles.size();
    std::string bytes;
    int component = kUnsignedInt, stride = 4;
    if (n <= 65535) {
        std::vector<std::uint16_t> narrow;
        narrow.reserve(count);
        for (const Triangle& t : topology.triangles)
            for (const std::uint32_t i : t) narrow.push_back(static_cast<std::uint16_t>(i));
        bytes = bytes_of(narrow);
        component = kUnsignedShort, stride = 2;
    } else {
        bytes = bytes_of(topology.triangles);
    }
    const int view = compress ? glb.add_compressed_view(bytes, count, stride, kElementArrayBuffer, true)
                              : glb.add_view(bytes, kElementArrayBuffer);
    primitive["indices"] = glb.add("accessors", accessor(view, 0, component, count, "SCALAR"));
}

std::string write_layout(const Layout& L, const GlbOptions& options, bool compress, GlbSummary* summary) {
    const std::size_t n = L.frames.front().positions.size();
    GlbBuilder glb;
    const bool has_uvs = !L.topology->uvs.empty();
    // The material first: whether it needs tangents decides the attributes.
    const MaterialRef material = add_material(glb, options.look, has_uvs, options.texture_px);
    Layout layout = L;
    layout.tangents = material.needs_tangents;
    if (layout.tangents)
        for (FrameData& f : layout.frames) f.tangents = vertex_tangents(f.positions, f.normals, *L.topology);

    nlohmann::json primitive = {{"attributes", nlohmann::json::object()}, {"material", material.index}, {"mode", 4}};
    nlohmann::json node = {{"name", options.name}, {"mesh", 0}};
    double error = 0.0;
    if (compress)
        error = add_quantized_streams(glb, layout, primitive, node, n, options.max_position_error_m);
    else
        add_float_streams(glb, layout, primitive, n);
    if (has_uvs) {
        const int view = compress ? glb.add_compressed_view(bytes_of(L.topology->uvs), n, 8, kArrayBuffer, false)
                                  : glb.add_view(bytes_of(L.topology->uvs), kArrayBuffer);
        primitive["attributes"]["TEXCOORD_0"] = glb.add("accessors", accessor(view, 0, kFloat, n, "VEC2"));
    }
    add_indices(glb, *L.topology, n, compress, primitive);

    const std::size_t frames = layout.frames.size();
    nlohmann::json mesh = {{"name", options.name}, {"primitives", {primitive}}};
    if (frames > 1) {
        mesh["weights"] = std::vector<float>(frames - 1, 0.0f);
        std::vector<std::string> names;
        for (std::size_t f = 1; f < frames; ++f) names.push_back("frame " + std::to_string(f));
        mesh["extras"] = {{"targetNames", names}};
    }
    glb.add("meshes", std::move(mesh));
    glb.add("nodes", std::move(node));
    glb.add("scenes", {{"nodes", {0}}});
    glb.document()["scene"] = 0;
    if (frames > 1) add_frame_animation(glb, frames, L.fps, compress);
    std::string out = glb.finish();
    if (out.size() > std::numeric_limits<std::uint32_t>::max())
        throw InputError("glTF output: " + std::to_string(out.size()) + " bytes, more than a .glb holds (4 GiB)");
    if (summary) {
        summary->bytes = out.size();
        summary->vertices = n;
        summary->triangles = L.topology->triangles.size();
        summary->frames = frames;
        summary->morph_targets = frames - 1;
        summary->compressed = compress;
        summary->max_position_error_m = error;
    }
    return out;
}

FrameData frame_data(std::vector<Vec3f> positions, const Topology& topology, std::vector<Vec3f> normals = {}) {
    FrameData f;
    f.normals = normals.size() == positions.size() ? std::move(normals) : vertex_normals(positions, topology.triangles);
    f.positions = std::move(positions);
    return f;
}
}  // namespace

std::string glb_bytes(const Mesh& mesh, const GlbOptions& options, GlbSummary* summary) {
    validate(mesh, "glTF output");
    if (mesh.positions.empty() || mesh.topology.triangles.empty())
        throw InputError("glTF output: the garment has no triangles");
    Layout L;
    L.topology = &mesh.topology;
    L.frames.push_back(frame_data(mesh.positions, mesh.topology, mesh.normals));
    return write_layout(L, options, false, summary);
}

std::string glb_bytes(const Animation& animation, const GlbOptions& options, GlbSummary* summary) {
    validate(animation, "glTF output");
    if (animation.frames.empty() || animation.vertex_count() == 0 || animation.topology.triangles.empty())
        throw InputError("glTF output: the animation has no frames or no triangles");
    if (animation.frame_count() > kMaxMorphFrames)
        throw InputError("glTF output: " + std::to_string(animation.frame_count()) +
                         " frames; a morph-target animation holds at most " + std::to_string(kMaxMorphFrames) +
                         " (every frame keys every target)");
    if (!(options.max_position_error_m >= 0.0) || !std::isfinite(options.max_position_error_m))
        throw InputError("glTF output: position error bound " + std::to_string(options.max_position_error_m) +
                         " m must be finite and >= 0");
    if (!(animation.fps > 0.0) || !std::isfinite(animation.fps))
        throw InputError("glTF output: frame rate " + std::to_string(animation.fps) + " must be > 0");
    Layout L;
    L.topology = &animation.topology;
    L.fps = animation.fps;
    for (const auto& frame : animation.frames) L.frames.push_back(frame_data(frame, animation.topology));
    return write_layout(L, options, options.compress && animation.frame_count() > 1, summary);
}

GlbSummary write_glb(const std::filesystem::path& path, const Mesh& mesh, const GlbOptions& options) {
    GlbSummary summary;
    const std::string bytes = glb_bytes(mesh, options, &summary);
    write_file_atomically(path, bytes);
    return summary;
}

GlbSummary write_glb(const std::filesystem::path& path, const Animation& animation, const GlbOptions& options) {
    GlbSummary summary;
    const std::string bytes = glb_bytes(animation, options, &summary);
    write_file_atomically(path, bytes);
    return summary;
}

}  // namespace foldcast::gltf
