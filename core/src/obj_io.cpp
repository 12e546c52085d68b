#include <tiny_obj_loader.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/core/mesh_io.hpp"

namespace foldcast {
namespace fs = std::filesystem;

namespace {
// tinyobjloader reads a coordinate it cannot parse ("nan", "x") as 0 and one out of range as
// inf, silently: a garment would render with a vertex moved to the origin.  Each `v` line's
// x y z must be finite numbers.
void reject_unreadable_positions(const fs::path& path) {
    std::ifstream in(path);
    std::string line;
    for (std::size_t number = 1; std::getline(in, line); ++number) {
        if (line.size() < 2 || line[0] != 'v' || (line[1] != ' ' && line[1] != '\t')) continue;
        const char* at = line.c_str() + 2;
        for (int k = 0; k < 3; ++k) {
            while (*at == ' ' || *at == '\t') ++at;
            const char* begin = at;
            while (*at != '\0' && *at != ' ' && *at != '\t' && *at != '\r') ++at;
            double value = 0.0;
            const auto [end, ec] = std::from_chars(begin, at, value);
            if (begin == at || ec != std::errc() || end != at || !std::isfinite(value))
                throw InputError("'" + path.string() + "' line " + std::to_string(number) + ": vertex coordinate '" +
                                 std::string(begin, at) + "' is not a finite number");
        }
    }
}
}  // namespace

void write_obj(const fs::path& path, const Mesh& mesh) {
    validate(mesh, path.string());
    AtomicFile file(path);
    write_obj(file.stream(), mesh);
    file.commit();
}

void write_obj(std::ostream& out, const Mesh& mesh) {
    char line[160];
    out << "# foldcast mesh: " << mesh.positions.size() << " vertices, " << mesh.topology.triangles.size()
        << " triangles\n";
    for (const Vec3f& p : mesh.positions) {
        std::snprintf(line, sizeof line, "v %.7g %.7g %.7g\n", p.x(), p.y(), p.z());
        out << line;
    }
    for (const Vec2f& uv : mesh.topology.uvs) {
        std::snprintf(line, sizeof line, "vt %.7g %.7g\n", uv.x(), uv.y());
        out << line;
    }
    for (const Vec3f& n : mesh.normals) {
        std::snprintf(line, sizeof line, "vn %.6f %.6f %.6f\n", n.x(), n.y(), n.z());
        out << line;
    }
    const bool has_uv = !mesh.topology.uvs.empty();
    const bool has_n = !mesh.normals.empty();
    for (const Triangle& t : mesh.topology.triangles) {
        out << 'f';
        for (std::uint32_t v : t) {
            const unsigned i = v + 1;
            if (has_uv && has_n)
                out << ' ' << i << '/' << i << '/' << i;
            else if (has_uv)
                out << ' ' << i << '/' << i;
            else if (has_n)
                out << ' ' << i << "//" << i;
            else
                out << ' ' << i;
        }
        out << '\n';
    }
}

Mesh read_obj(const fs::path& path) {
    const std::string name = path.string();
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw InputError("cannot read '" + name + "': no such file");
    reject_unreadable_positions(path);
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    config.mtl_search_path = "";  // materials are never used; do not go looking for them
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(name, config)) throw InputError("cannot read '" + name + "': " + reader.Error());
    const tinyobj::attrib_t& attrib = reader.GetAttrib();

    Mesh mesh;
    const std::size_t n = attrib.vertices.size() / 3;
    mesh.positions.resize(n);
    for (std::size_t i = 0; i < n; ++i)
        mesh.positions[i] = Vec3f(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
    const bool has_uv = !attrib.texcoords.empty();
    std::vector<bool> uv_set(has_uv ? n : 0, false);
    if (has_uv) mesh.topology.uvs.assign(n, Vec2f::Zero());
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        const auto& idx = shape.mesh.indices;
        for (std::size_t f = 0; f + 2 < idx.size(); f += 3) {
            Triangle t{};
            for (int k = 0; k < 3; ++k) {
                const tinyobj::index_t& c = idx[f + k];
                if (c.vertex_index < 0 || static_cast<std::size_t>(c.vertex_index) >= n)
                    throw InputError("cannot read '" + name + "': a face refers to a vertex that does not exist");
                t[k] = static_cast<std::uint32_t>(c.vertex_index);
                if (has_uv && c.texcoord_index >= 0 && !uv_set[t[k]] &&
                    2 * static_cast<std::size_t>(c.texcoord_index) + 1 < attrib.texcoords.size()) {
                    mesh.topology.uvs[t[k]] =
                        Vec2f(attrib.texcoords[2 * c.texcoord_index], attrib.texcoords[2 * c.texcoord_index + 1]);
                    uv_set[t[k]] = true;
                }
            }
            mesh.topology.triangles.push_back(t);
        }
    }
    if (mesh.positions.empty()) throw InputError("cannot read '" + name + "': no vertices");
    mesh.normals = vertex_normals(mesh.positions, mesh.topology.triangles);
    validate(mesh, name);
    return mesh;
}

}  // namespace foldcast
