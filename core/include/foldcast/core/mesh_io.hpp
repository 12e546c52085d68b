#pragma once
// Mesh and animation files other tools understand: Wavefront OBJ, binary PLY and
// Blender's PC2 point cache.  Writers are atomic (temporary file + rename); readers
// validate and throw InputError naming the file and what is wrong.
#include <filesystem>
#include <ostream>

#include "foldcast/core/mesh.hpp"

namespace foldcast {

// OBJ with v / vt / vn and triangles.  Reading triangulates polygons as fans and keeps one
// UV per vertex (the first one a face gives it): fixed-topology animation needs per-vertex
// attributes, so UV seams are not preserved.
void write_obj(const std::filesystem::path& path, const Mesh& mesh);
void write_obj(std::ostream& out, const Mesh& mesh);  // no validation: for staged outputs
Mesh read_obj(const std::filesystem::path& path);

// Binary little-endian PLY with x y z nx ny nz s t and triangle faces.
void write_ply(const std::filesystem::path& path, const Mesh& mesh);

// PC2: "POINTCACHE2\0", int32 version 1, int32 vertex count, float start frame,
// float sampling (frames per sample), int32 sample count, then float32 xyz.
struct Pc2Info {
    float start_frame = 0.0f;
    float sampling = 1.0f;
};
void write_pc2(const std::filesystem::path& path, const std::vector<std::vector<Vec3f>>& frames, Pc2Info info = {});
void write_pc2(std::ostream& out, const std::vector<std::vector<Vec3f>>& frames, Pc2Info info = {});
// Frames only: PC2 carries no topology.  Rejects files whose header disagrees with their size.
std::vector<std::vector<Vec3f>> read_pc2(const std::filesystem::path& path, Pc2Info* info = nullptr);

// PC2 frames + topology from an OBJ with the same vertex order.
Animation read_pc2_animation(const std::filesystem::path& pc2, const std::filesystem::path& obj, double fps = 30.0);
// Writes `path` (.pc2) and the topology (first frame) as the .obj of the same stem beside it,
// both or neither (one OutputTransaction).
void write_pc2_animation(const std::filesystem::path& pc2, const Animation& anim);

}  // namespace foldcast
