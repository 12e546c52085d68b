#include <algorithm>
#include <cmath>
#include <fstream>

#include "foldcast/codec/codec.hpp"
#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/error.hpp"
#include "container.hpp"

namespace foldcast::codec {

Metrics measure(const Animation& a, const Animation& b, std::size_t bytes) {
    if (a.frame_count() != b.frame_count() || a.vertex_count() != b.vertex_count())
        throw InputError("cannot compare animations of " + std::to_string(a.frame_count()) + "x" +
                         std::to_string(a.vertex_count()) + " and " + std::to_string(b.frame_count()) + "x" +
                         std::to_string(b.vertex_count()) + " frames x vertices");
    Metrics m;
    m.frames = a.frame_count();
    m.vertices = a.vertex_count();
    m.bytes = bytes;
    const double vf = double(m.frames) * double(m.vertices);
    if (vf == 0.0) return m;
    m.bpvf = 8.0 * double(bytes) / vf;
    double err2 = 0.0, dev2 = 0.0, worst = 0.0;
    for (std::size_t t = 0; t < m.frames; ++t) {
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (const auto& p : a.frames[t]) mean += p.cast<double>();
        mean /= double(m.vertices);
        for (std::size_t v = 0; v < m.vertices; ++v) {
            const double e2 = (a.frames[t][v].cast<double>() - b.frames[t][v].cast<double>()).squaredNorm();
            err2 += e2;
            worst = std::max(worst, e2);
            dev2 += (a.frames[t][v].cast<double>() - mean).squaredNorm();
        }
    }
    const double diagonal = std::max(double(bounds(a).diagonal()), 1e-30);
    m.max_error_m = std::sqrt(worst);
    m.rms_error_rel = std::sqrt(err2 / vf) / diagonal;
    m.max_error_rel = m.max_error_m / diagonal;
    m.kg_error = dev2 > 0.0 ? 100.0 * std::sqrt(err2 / dev2) : 0.0;
    return m;
}

std::string read_fca(const std::filesystem::path& path) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) throw InputError("cannot read '" + path.string() + "': " + ec.message());
    if (size > std::uint64_t(4) * kMaxPayloadBytes)
        throw InputError("'" + path.string() + "' is larger than 4 GiB: not an .fca file this build reads");
    std::ifstream in(path, std::ios::binary);
    std::string bytes(static_cast<std::size_t>(size), '\0');
    if (!in || !in.read(bytes.data(), static_cast<std::streamsize>(size)))
        throw InputError("cannot read '" + path.string() + "'");
    return bytes;
}

void write_fca(const std::filesystem::path& path, std::string_view bytes) { write_file_atomically(path, bytes); }

}  // namespace foldcast::codec
