#include "container.hpp"

#include <cmath>

#include "byte_io.hpp"
#include "crc32.hpp"

namespace foldcast::codec {

std::string header_payload(const Header& h) {
    ByteWriter w;
    w.put<std::uint16_t>(kFormatVersion);
    w.put<std::uint8_t>(static_cast<std::uint8_t>(h.profile));
    w.put<std::uint32_t>(h.vertices);
    w.put<std::uint32_t>(h.frames);
    w.put<double>(h.fps);
    for (int k = 0; k < 3; ++k) w.put<float>(h.bounds.min[k]);
    for (int k = 0; k < 3; ++k) w.put<float>(h.bounds.max[k]);
    w.put<std::uint64_t>(h.total_bytes);
    w.put<double>(h.step);
    w.put<double>(h.threshold);
    w.put<std::uint32_t>(h.profile_param);
    w.put<std::uint32_t>(static_cast<std::uint32_t>(h.topology.triangles.size()));
    for (const auto& t : h.topology.triangles)
        for (auto i : t) w.put<std::uint32_t>(i);
    w.put<std::uint8_t>(h.topology.uvs.empty() ? 0 : 1);
    for (const auto& uv : h.topology.uvs) {
        w.put<float>(uv.x());
        w.put<float>(uv.y());
    }
    return std::move(w.bytes());
}

Header parse_header(std::string_view payload, const std::string& what, std::optional<std::uint64_t> known_total_bytes) {
    ByteReader r(payload, what + ": header");
    Header h;
    const auto version = r.get<std::uint16_t>("version");
    if (version != kFormatVersion)
        r.fail("format version " + std::to_string(version) + " (this build reads version " + std::to_string(kFormatVersion) + ")");
    const auto profile = r.get<std::uint8_t>("profile");
    if (profile > static_cast<std::uint8_t>(Profile::predictive))
        r.fail("unknown profile " + std::to_string(profile) + " (known: 0 paper, 1 default)");
    h.profile = static_cast<Profile>(profile);
    h.vertices = r.get<std::uint32_t>("vertex count");
    h.frames = r.get<std::uint32_t>("frame count");
    h.fps = r.get<double>("fps");
    for (int k = 0; k < 3; ++k) h.bounds.min[k] = r.get<float>("bounds");
    for (int k = 0; k < 3; ++k) h.bounds.max[k] = r.get<float>("bounds");
    h.total_bytes = r.get<std::uint64_t>("total size");
    h.step = r.get<double>("quantisation step");
    h.threshold = r.get<double>("threshold");
    h.profile_param = r.get<std::uint32_t>("profile parameter");
    if (h.vertices == 0 || h.frames == 0)
        r.fail("header says " + std::to_string(h.vertices) + " vertices and " + std::to_string(h.frames) + " frames (both must be > 0)");
    if (!(std::isfinite(h.fps) && h.fps > 0.0 && h.fps <= 1e6)) r.fail("fps " + std::to_string(h.fps) + " (allowed (0, 1e6])");
    if (!(std::isfinite(h.step) && h.step > 0.0 && h.step <= 1e9)) r.fail("quantisation step must be in (0, 1e9]");
    if (!(std::isfinite(h.threshold) && h.threshold >= 0.0)) r.fail("threshold must be finite and >= 0");
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(h.bounds.min[k]) || !std::isfinite(h.bounds.max[k]) || h.bounds.min[k] > h.bounds.max[k])
            r.fail("bounds are not finite or min > max");
    // Allocation policy: what the decoder will allocate must be justified by the bytes.
    const std::uint64_t file_bytes = known_total_bytes ? std::min(*known_total_bytes, h.total_bytes) : h.total_bytes;
    const std::uint64_t vertex_frames = std::uint64_t(h.vertices) * h.frames;
    if (vertex_frames > kMaxVertexFrames || vertex_frames > file_bytes * kMaxVertexFramesPerByte)
        r.fail(std::to_string(h.vertices) + " vertices x " + std::to_string(h.frames) + " frames is more than " +
               std::to_string(file_bytes) + " bytes can hold (limit " + std::to_string(kMaxVertexFramesPerByte) +
               " vertex-frames per byte, " + std::to_string(kMaxVertexFrames) + " in all)");
    const auto triangles = r.get<std::uint32_t>("triangle count");
    if (std::uint64_t(triangles) * 12 > r.remaining())
        r.fail("header promises " + std::to_string(triangles) + " triangles but holds only " + std::to_string(r.remaining()) + " more bytes");
    h.topology.triangles.resize(triangles);
    for (auto& t : h.topology.triangles)
        for (auto& i : t) {
            i = r.get<std::uint32_t>("triangle");
            if (i >= h.vertices) r.fail("triangle index " + std::to_string(i) + " >= vertex count " + std::to_string(h.vertices));
        }
    const auto has_uvs = r.get<std::uint8_t>("UV flag");
    if (has_uvs > 1) r.fail("UV flag " + std::to_string(has_uvs) + " (allowed 0 or 1)");
    if (has_uvs) {
        if (std::uint64_t(h.vertices) * 8 > r.remaining()) r.fail("header is too short for " + std::to_string(h.vertices) + " UVs");
        h.topology.uvs.resize(h.vertices);
        for (auto& uv : h.topology.uvs) {
            uv.x() = r.get<float>("UV");
            uv.y() = r.get<float>("UV");
            if (!std::isfinite(uv.x()) || !std::isfinite(uv.y())) r.fail("a UV is not finite");
        }
    }
    r.expect_end("header");
    return h;
}

void append_packet(std::string& file, PacketType type, std::string_view payload) {
    ByteWriter w;
    w.put<std::uint32_t>(static_cast<std::uint32_t>(payload.size()));
    const char type_byte = static_cast<char>(type);
    w.put<char>(type_byte);
    w.put_bytes(payload);
    const std::uint32_t crc = crc32(payload, crc32(std::string_view(&type_byte, 1)));
    w.put<std::uint32_t>(crc);
    file += w.bytes();
}

}  // namespace foldcast::codec
