// The .fca StreamingDecoder (codec/) behind a C interface for JavaScript: the player feeds
// bytes as fetch() delivers them and reads frames straight out of WebAssembly memory.
// Errors never cross into JavaScript as exceptions: a call returns -1 and
// fca_error() says why (the codec's own InputError message).
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

#include "foldcast/codec/codec.hpp"

namespace {
struct Player {
    foldcast::codec::StreamingDecoder decoder;
    std::string error;
    std::vector<foldcast::Vec3f> frame;    // the last frame asked for
    std::vector<std::uint32_t> triangles;  // flattened, valid once the header is in
    std::vector<std::uint8_t> input;       // the caller writes the next chunk here
    double status[9] = {};
};

template <class F>
int guarded(Player* p, F&& f) {
    try {
        f();
        return 0;
    } catch (const std::exception& e) {
        p->error = e.what();
    } catch (...) {
        p->error = "unknown error";
    }
    return -1;
}
}  // namespace

extern "C" {

// total_bytes: the file size when known (Content-Length), else 0.
Player* fca_new(double total_bytes) {
    std::optional<std::uint64_t> total;
    if (total_bytes > 0) total = static_cast<std::uint64_t>(total_bytes);
    return new Player{foldcast::codec::StreamingDecoder("fca stream", total), {}, {}, {}, {}, {}};
}
void fca_delete(Player* p) { delete p; }

// A buffer of `bytes` bytes for the next fca_feed (valid until the next call of either).
std::uint8_t* fca_input(Player* p, std::uint32_t bytes) {
    p->input.resize(bytes);
    return p->input.data();
}
int fca_feed(Player* p, std::uint32_t bytes) {
    return guarded(p,
                   [&] { p->decoder.feed(std::string_view(reinterpret_cast<const char*>(p->input.data()), bytes)); });
}
const char* fca_error(Player* p) { return p->error.c_str(); }

// [header_ready, complete, playable_frames, packets, bytes_used, error bound in metres
// (-1 where the profile states none), frame_ready, preview_only, first_frame_bytes (0
// unknown)], as doubles for one typed-array view.
const double* fca_status(Player* p) {
    const auto s = p->decoder.status();
    p->status[0] = s.header_ready;
    p->status[1] = s.complete;
    p->status[2] = static_cast<double>(s.playable_frames);
    p->status[3] = static_cast<double>(s.packets);
    p->status[4] = static_cast<double>(s.bytes_used);
    const auto bound = s.header_ready ? p->decoder.max_error_m() : std::nullopt;
    p->status[5] = bound ? *bound : -1.0;
    p->status[6] = s.frame_ready;
    p->status[7] = s.preview_only;
    p->status[8] = static_cast<double>(s.first_frame_bytes);
    return p->status;
}

// Valid once the header is in (status[0] == 1).
std::uint32_t fca_vertex_count(Player* p) { return static_cast<std::uint32_t>(p->decoder.vertex_count()); }
std::uint32_t fca_frame_count(Player* p) { return static_cast<std::uint32_t>(p->decoder.frame_count()); }
double fca_fps(Player* p) { return p->decoder.fps(); }
int fca_profile(Player* p) { return static_cast<int>(p->decoder.profile()); }
std::uint32_t fca_triangle_count(Player* p) {
    return static_cast<std::uint32_t>(p->decoder.topology().triangles.size());
}
// The per-vertex UVs (u, v float32 pairs), or null when the file has none.
const float* fca_uvs(Player* p) {
    const auto& uvs = p->decoder.topology().uvs;
    static_assert(sizeof(foldcast::Vec2f) == 2 * sizeof(float));
    return uvs.empty() ? nullptr : uvs.front().data();
}

// The header's metadata entries (format version 4): key and value of entry i < count.
std::uint32_t fca_metadata_count(Player* p) { return static_cast<std::uint32_t>(p->decoder.metadata().size()); }
const char* fca_metadata_key(Player* p, std::uint32_t i) { return p->decoder.metadata().at(i).first.c_str(); }
const char* fca_metadata_value(Player* p, std::uint32_t i) { return p->decoder.metadata().at(i).second.c_str(); }
const std::uint32_t* fca_triangles(Player* p) {
    const auto& tris = p->decoder.topology().triangles;
    p->triangles.resize(tris.size() * 3);
    for (std::size_t i = 0; i < tris.size(); ++i)
        for (int k = 0; k < 3; ++k) p->triangles[3 * i + k] = tris[i][k];
    return p->triangles.data();
}

// Frame t reconstructed from what has arrived: vertex_count x (x, y, z) float32, or null
// with fca_error() set.
const float* fca_frame(Player* p, std::uint32_t t) {
    const int rc = guarded(p, [&] { p->decoder.frame(t, p->frame); });
    if (rc != 0) return nullptr;
    static_assert(sizeof(foldcast::Vec3f) == 3 * sizeof(float));
    return p->frame.empty() ? nullptr : p->frame.front().data();
}
}
