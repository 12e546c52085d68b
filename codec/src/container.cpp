#include "container.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "byte_io.hpp"
#include "crc32.hpp"
#include "zstd_block.hpp"

namespace foldcast::codec {
std::string metadata_problem(const Metadata& metadata) {
    if (metadata.size() > kMaxMetadataEntries)
        return std::to_string(metadata.size()) + " metadata entries (at most " + std::to_string(kMaxMetadataEntries) + ")";
    for (std::size_t i = 0; i < metadata.size(); ++i) {
        const auto& [key, value] = metadata[i];
        if (key.empty() || key.size() > kMaxMetadataKeyBytes ||
            !std::all_of(key.begin(), key.end(), [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'; }))
            return "metadata key '" + key + "' (allowed: 1.." + std::to_string(kMaxMetadataKeyBytes) +
                   " characters a-z, 0-9, _)";
        for (std::size_t j = 0; j < i; ++j)
            if (metadata[j].first == key) return "metadata key '" + key + "' given twice";
        if (value.size() > kMaxMetadataValueBytes ||
            std::any_of(value.begin(), value.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
            return "metadata value of '" + key + "' (allowed: at most " + std::to_string(kMaxMetadataValueBytes) +
                   " bytes, no control characters)";
    }
    return {};
}

std::string header_payload(const Header& h) {
    ByteWriter w;
    w.put<std::uint16_t>(h.version);
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
    if (h.version >= 4) {
        w.put<std::uint64_t>(h.first_frame_bytes);
        w.put<std::uint8_t>(static_cast<std::uint8_t>(h.metadata.size()));
        for (const auto& [key, value] : h.metadata) {
            w.put<std::uint8_t>(static_cast<std::uint8_t>(key.size()));
            w.put_bytes(key);
            w.put<std::uint16_t>(static_cast<std::uint16_t>(value.size()));
            w.put_bytes(value);
        }
    }
    // Topology: triangle corners as differences from the previous triangle's (regular
    // meshes repeat a few patterns) and the UVs, as one zstd frame.
    w.put<std::uint32_t>(static_cast<std::uint32_t>(h.topology.triangles.size()));
    w.put<std::uint8_t>(h.topology.uvs.empty() ? 0 : 1);
    ByteWriter raw;
    Triangle previous{0, 0, 0};
    for (const auto& t : h.topology.triangles) {
        for (int k = 0; k < 3; ++k)
            raw.put<std::uint32_t>(t[static_cast<std::size_t>(k)] - previous[static_cast<std::size_t>(k)]);
        previous = t;
    }
    for (const auto& uv : h.topology.uvs) {
        raw.put<float>(uv.x());
        raw.put<float>(uv.y());
    }
    w.put_bytes(zstd_pack(raw.bytes()));
    return std::move(w.bytes());
}

Header parse_header(std::string_view payload, const std::string& what, std::optional<std::uint64_t> known_total_bytes) {
    ByteReader r(payload, what + ": header");
    Header h;
    const auto version = r.get<std::uint16_t>("version");
    if (version < kOldestReadableVersion || version > kFormatVersion)
        r.fail("format version " + std::to_string(version) + " (this build reads versions " +
               std::to_string(kOldestReadableVersion) + " to " + std::to_string(kFormatVersion) + ")");
    h.version = version;
    const auto profile = r.get<std::uint8_t>("profile");
    if (profile > static_cast<std::uint8_t>(Profile::cascade))
        r.fail("unknown profile " + std::to_string(profile) + " (known: 0 paper, 1 default, 2 cascade)");
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
    if (version >= 4) {
        h.first_frame_bytes = r.get<std::uint64_t>("first frame size");
        if (h.first_frame_bytes > h.total_bytes)
            r.fail("first frame size " + std::to_string(h.first_frame_bytes) + " is past the file's size " +
                   std::to_string(h.total_bytes));
        const auto entries = r.get<std::uint8_t>("metadata count");
        for (std::size_t i = 0; i < entries; ++i) {
            std::string key(r.get_bytes(r.get<std::uint8_t>("metadata key length"), "metadata key"));
            std::string value(r.get_bytes(r.get<std::uint16_t>("metadata value length"), "metadata value"));
            h.metadata.emplace_back(std::move(key), std::move(value));
        }
        if (const std::string problem = metadata_problem(h.metadata); !problem.empty()) r.fail(problem);
    }
    if (h.vertices == 0 || h.frames == 0)
        r.fail("header says " + std::to_string(h.vertices) + " vertices and " + std::to_string(h.frames) +
               " frames (both must be > 0)");
    if (!(std::isfinite(h.fps) && h.fps > 0.0 && h.fps <= 1e6))
        r.fail("fps " + std::to_string(h.fps) + " (allowed (0, 1e6])");
    if (!(std::isfinite(h.step) && h.step > 0.0 && h.step <= 1e9)) r.fail("quantisation step must be in (0, 1e9]");
    if (!(std::isfinite(h.threshold) && h.threshold >= 0.0)) r.fail("threshold must be finite and >= 0");
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(h.bounds.min[k]) || !std::isfinite(h.bounds.max[k]) || h.bounds.min[k] > h.bounds.max[k])
            r.fail("bounds are not finite or min > max");
    // Allocation policy: what the decoder will allocate must be justified by the bytes.
    if (h.vertices > kMaxVertices || h.frames > kMaxFrames)
        r.fail("header says " + std::to_string(h.vertices) + " vertices and " + std::to_string(h.frames) +
               " frames (at most " + std::to_string(kMaxVertices) + " and " + std::to_string(kMaxFrames) + ")");
    const std::uint64_t file_bytes = known_total_bytes ? std::min(*known_total_bytes, h.total_bytes) : h.total_bytes;
    const std::uint64_t vertex_frames = std::uint64_t(h.vertices) * h.frames;
    if (vertex_frames > kMaxVertexFrames || vertex_frames > file_bytes * kMaxVertexFramesPerByte)
        r.fail(std::to_string(h.vertices) + " vertices x " + std::to_string(h.frames) + " frames is more than " +
               std::to_string(file_bytes) + " bytes can hold (limit " + std::to_string(kMaxVertexFramesPerByte) +
               " vertex-frames per byte, " + std::to_string(kMaxVertexFrames) + " in all)");
    const auto triangles = r.get<std::uint32_t>("triangle count");
    const auto has_uvs = r.get<std::uint8_t>("UV flag");
    if (has_uvs > 1) r.fail("UV flag " + std::to_string(has_uvs) + " (allowed 0 or 1)");
    if (triangles > kMaxTrianglesPerVertex * h.vertices)
        r.fail(std::to_string(triangles) + " triangles for " + std::to_string(h.vertices) + " vertices (at most " +
               std::to_string(kMaxTrianglesPerVertex) + " per vertex)");
    const std::uint64_t raw_size = std::uint64_t(triangles) * 12 + (has_uvs ? std::uint64_t(h.vertices) * 8 : 0);
    const std::string_view packed = r.get_bytes(r.remaining(), "topology");
    if (raw_size > kMaxTopologyBytesPerByte * packed.size() || raw_size > kMaxTopologyBytes)
        r.fail(std::to_string(triangles) + " triangles" + (has_uvs ? " and UVs" : "") + " (" +
               std::to_string(raw_size) + " bytes) are more than a " + std::to_string(packed.size()) +
               "-byte topology block can hold (limit " + std::to_string(kMaxTopologyBytesPerByte) + " bytes per byte)");
    const std::string raw = zstd_unpack(packed, raw_size, r, "topology block");
    ByteReader t(raw, r.what() + " topology");
    h.topology.triangles.resize(triangles);
    Triangle previous{0, 0, 0};
    for (auto& tri : h.topology.triangles) {
        for (std::size_t k = 0; k < 3; ++k) {
            tri[k] = previous[k] + t.get<std::uint32_t>("triangle");
            if (tri[k] >= h.vertices)
                r.fail("triangle index " + std::to_string(tri[k]) + " >= vertex count " + std::to_string(h.vertices));
        }
        previous = tri;
    }
    if (has_uvs) {
        h.topology.uvs.resize(h.vertices);
        for (auto& uv : h.topology.uvs) {
            uv.x() = t.get<float>("UV");
            uv.y() = t.get<float>("UV");
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
