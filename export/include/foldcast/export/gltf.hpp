#pragma once
// Garments and their animations as glTF 2.0 binary files (.glb): what web viewers
// (three.js, <model-viewer>), AR viewers, Blender, Unity and game engines open.  The look
// travels as a glTF material (docs/gltf.md says what maps and what only approximates).
//
// One frame: a static mesh with float positions, normals, tangents, UVs (metres of cloth,
// as foldcast's garments carry them) and indices.  Several frames: frame 0 is the mesh, the
// others are morph targets whose weights an animation keys one frame at a time; compressed,
// positions, normals and tangents are quantized (KHR_mesh_quantization) and every vertex,
// index and key stream is packed with meshoptimizer's codecs (EXT_meshopt_compression).
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

#include "foldcast/core/mesh.hpp"
#include "foldcast/looks/looks.hpp"

namespace foldcast::gltf {

struct GlbOptions {
    // The material; none: a plain grey, untextured, double-sided one.
    std::optional<looks::Look> look;
    // Animations only: quantize and meshopt-compress (off: float attributes, no extension
    // required, larger files; for importers without EXT_meshopt_compression).
    bool compress = true;
    // Compressed animations: the largest position error allowed (m).  0: the finest the
    // quantization holds (15 bits over the largest side, about 1e-5 m on a 0.7 m garment);
    // a coarser bound packs smaller (docs/gltf.md).
    double max_position_error_m = 0.0;
    // Side of the baked weave textures (colour and normal map), pixels, a power of two.
    int texture_px = 256;
    std::string name = "garment";
};

// What a written file holds, for reports.
struct GlbSummary {
    std::size_t bytes = 0;
    std::size_t vertices = 0;
    std::size_t triangles = 0;
    std::size_t frames = 0;
    std::size_t morph_targets = 0;
    bool compressed = false;
    // Largest distance between a frame's vertex and what the file stores for it (m): the
    // quantization error (0 for float attributes).
    double max_position_error_m = 0.0;
};

// The .glb bytes of a mesh (static) or an animation (morph targets when it has 2+ frames).
// Throws InputError naming `what` when the mesh is invalid (core's validate) or empty.
std::string glb_bytes(const Mesh& mesh, const GlbOptions& options, GlbSummary* summary = nullptr);
std::string glb_bytes(const Animation& animation, const GlbOptions& options, GlbSummary* summary = nullptr);

// Written atomically (core/atomic_file.hpp).
GlbSummary write_glb(const std::filesystem::path& path, const Mesh& mesh, const GlbOptions& options);
GlbSummary write_glb(const std::filesystem::path& path, const Animation& animation, const GlbOptions& options);

}  // namespace foldcast::gltf
