#include <cmath>
#include <string>

#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/core/mesh_io.hpp"
#include "little_endian.hpp"

namespace foldcast {
namespace fs = std::filesystem;

namespace {
constexpr char kSignature[12] = {'P', 'O', 'I', 'N', 'T', 'C', 'A', 'C', 'H', 'E', '2', '\0'};
constexpr std::size_t kHeaderBytes = 12 + 4 + 4 + 4 + 4 + 4;

}  // namespace

void write_pc2(const fs::path& path, const std::vector<std::vector<Vec3f>>& frames, Pc2Info info) {
    const std::size_t n = frames.empty() ? 0 : frames.front().size();
    for (const auto& f : frames)
        if (f.size() != n) throw InputError("cannot write '" + path.string() + "': frames differ in vertex count");
    AtomicFile file(path);
    write_pc2(file.stream(), frames, info);
    file.commit();
}

void write_pc2(std::ostream& out, const std::vector<std::vector<Vec3f>>& frames, Pc2Info info) {
    const std::size_t n = frames.empty() ? 0 : frames.front().size();
    out.write(kSignature, sizeof kSignature);
    little_endian::put<std::int32_t>(out, 1);
    little_endian::put<std::int32_t>(out, static_cast<std::int32_t>(n));
    little_endian::put<float>(out, info.start_frame);
    little_endian::put<float>(out, info.sampling);
    little_endian::put<std::int32_t>(out, static_cast<std::int32_t>(frames.size()));
    for (const auto& f : frames)
        out.write(reinterpret_cast<const char*>(f.data()), static_cast<std::streamsize>(n * sizeof(Vec3f)));
}

std::vector<std::vector<Vec3f>> read_pc2(const fs::path& path, Pc2Info* info) {
    static_assert(sizeof(Vec3f) == 3 * sizeof(float));
    const std::string name = path.string();
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot read '" + name + "': no such file or not readable");
    std::error_code ec;
    const auto file_size = fs::file_size(path, ec);
    if (ec) throw InputError("cannot read '" + name + "': " + ec.message());
    char header[kHeaderBytes];
    if (file_size < kHeaderBytes || !in.read(header, kHeaderBytes))
        throw InputError("'" + name + "' is not a PC2 file: shorter than its 32-byte header");
    if (std::memcmp(header, kSignature, sizeof kSignature) != 0)
        throw InputError("'" + name + "' is not a PC2 file: it does not start with POINTCACHE2");
    const auto version = little_endian::get<std::int32_t>(header + 12);
    const auto n = little_endian::get<std::int32_t>(header + 16);
    const auto start = little_endian::get<float>(header + 20);
    const auto sampling = little_endian::get<float>(header + 24);
    const auto t = little_endian::get<std::int32_t>(header + 28);
    if (version != 1) throw InputError("'" + name + "': PC2 version " + std::to_string(version) + " (only 1 is known)");
    if (n <= 0 || t <= 0)
        throw InputError("'" + name + "': PC2 header says " + std::to_string(n) + " vertices and " + std::to_string(t) +
                         " frames (both must be > 0)");
    const std::uint64_t expected = kHeaderBytes + std::uint64_t(n) * std::uint64_t(t) * 12u;
    if (expected != file_size)
        throw InputError("'" + name + "': PC2 header promises " + std::to_string(expected) +
                         " bytes but the file has " + std::to_string(file_size));
    if (!std::isfinite(start) || !std::isfinite(sampling))
        throw InputError("'" + name + "': PC2 start frame or sampling is not finite");
    if (info) *info = Pc2Info{start, sampling};
    std::vector<std::vector<Vec3f>> frames(static_cast<std::size_t>(t),
                                           std::vector<Vec3f>(static_cast<std::size_t>(n)));
    for (auto& f : frames)
        if (!in.read(reinterpret_cast<char*>(f.data()), static_cast<std::streamsize>(f.size() * sizeof(Vec3f))))
            throw InputError("cannot read '" + name + "': read failed");
    return frames;
}

Animation read_pc2_animation(const fs::path& pc2, const fs::path& obj, double fps) {
    Animation anim;
    anim.frames = read_pc2(pc2);
    const Mesh topo = read_obj(obj);
    if (topo.positions.size() != anim.vertex_count())
        throw InputError("'" + obj.string() + "' has " + std::to_string(topo.positions.size()) + " vertices but '" +
                         pc2.string() + "' has " + std::to_string(anim.vertex_count()));
    anim.topology = topo.topology;
    anim.fps = fps;
    validate(anim, pc2.string());
    return anim;
}

void write_pc2_animation(const fs::path& pc2, const Animation& anim) {
    validate(anim, pc2.string());
    if (anim.frames.empty()) throw InputError("cannot write '" + pc2.string() + "': no frames");
    fs::path obj = pc2;
    obj.replace_extension(".obj");
    // Both or neither: a PC2 beside the OBJ of another animation cannot be read back.
    OutputTransaction outputs;
    write_pc2(outputs.stage(pc2), anim.frames);
    const Mesh topology = anim.frame_mesh(0);
    validate(topology, obj.string());
    write_obj(outputs.stage(obj), topology);
    outputs.commit();
}

}  // namespace foldcast
