#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/mesh_io.hpp"
#include "little_endian.hpp"

namespace foldcast {

void write_ply(const std::filesystem::path& path, const Mesh& mesh) {
    validate(mesh, path.string());
    const bool has_uv = !mesh.topology.uvs.empty();
    const bool has_n = !mesh.normals.empty();
    AtomicFile file(path);
    std::ofstream& out = file.stream();
    out << "ply\nformat binary_little_endian 1.0\ncomment foldcast mesh\n"
        << "element vertex " << mesh.positions.size() << "\n"
        << "property float x\nproperty float y\nproperty float z\n";
    if (has_n) out << "property float nx\nproperty float ny\nproperty float nz\n";
    if (has_uv) out << "property float s\nproperty float t\n";
    out << "element face " << mesh.topology.triangles.size() << "\n"
        << "property list uchar uint vertex_indices\nend_header\n";
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        for (int k = 0; k < 3; ++k) little_endian::put(out, mesh.positions[i][k]);
        if (has_n)
            for (int k = 0; k < 3; ++k) little_endian::put(out, mesh.normals[i][k]);
        if (has_uv)
            for (int k = 0; k < 2; ++k) little_endian::put(out, mesh.topology.uvs[i][k]);
    }
    for (const Triangle& t : mesh.topology.triangles) {
        little_endian::put<std::uint8_t>(out, 3);
        for (std::uint32_t v : t) little_endian::put(out, v);
    }
    file.commit();
}

}  // namespace foldcast
