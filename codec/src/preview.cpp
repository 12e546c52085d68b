#include "preview.hpp"

#include <algorithm>
#include <cmath>

#include "byte_io.hpp"
#include "predictive_profile.hpp"
#include "zstd_block.hpp"

namespace foldcast::codec {
namespace {
double preview_step(const Header& h, std::uint16_t levels) {
    const float extent = (h.bounds.max - h.bounds.min).maxCoeff();
    return double(extent) / double(levels);
}

std::int64_t preview_prediction(const SpatialReference& s, const std::vector<std::int32_t>& g, std::size_t c) {
    if (s.a < 0) return 0;
    const auto at = [&](std::int32_t v) { return std::int64_t(g[3 * static_cast<std::size_t>(v) + c]); };
    return s.c < 0 ? at(s.a) : at(s.a) + at(s.b) - at(s.c);
}
}  // namespace

std::string preview_payload(const std::vector<Vec3f>& frame0, const Header& header, std::uint16_t levels) {
    const std::size_t n = frame0.size();
    const double step = preview_step(header, levels);
    std::vector<std::int32_t> g(3 * n);
    for (std::size_t v = 0; v < n; ++v)
        for (std::size_t c = 0; c < 3; ++c) {
            const double at = step > 0.0 ? std::round((double(frame0[v][int(c)]) - header.bounds.min[int(c)]) / step) : 0.0;
            g[3 * v + c] = static_cast<std::int32_t>(std::clamp(at, 0.0, double(levels)));
        }
    // Byte planes (all low bytes, then all high bytes), coordinate by coordinate: the high
    // bytes are almost all 0x00 or 0xff, which zstd codes in next to nothing.
    const auto refs = spatial_references(n, header.topology.triangles);
    std::string raw(6 * n, '\0');
    for (std::size_t c = 0; c < 3; ++c)
        for (std::size_t v = 0; v < n; ++v) {
            const auto r = static_cast<std::uint16_t>(static_cast<std::int16_t>(g[3 * v + c] - preview_prediction(refs[v], g, c)));
            raw[c * n + v] = static_cast<char>(r & 0xff);
            raw[3 * n + c * n + v] = static_cast<char>(r >> 8);
        }
    ByteWriter w;
    w.put<std::uint16_t>(levels);
    w.put_bytes(zstd_pack(raw));
    return std::move(w.bytes());
}

std::vector<Vec3f> parse_preview(std::string_view payload, const Header& header, const std::string& what) {
    ByteReader r(payload, what);
    const auto levels = r.get<std::uint16_t>("preview levels");
    if (levels == 0 || levels > kMaxPreviewLevels)
        r.fail("preview levels " + std::to_string(levels) + " (allowed 1.." + std::to_string(kMaxPreviewLevels) + ")");
    const std::size_t n = header.vertices;
    const std::string raw = zstd_unpack(r.get_bytes(r.remaining(), "preview"), 6 * std::uint64_t(n), r, "preview block");
    const auto refs = spatial_references(n, header.topology.triangles);
    std::vector<std::int32_t> g(3 * n);
    for (std::size_t v = 0; v < n; ++v)
        for (std::size_t c = 0; c < 3; ++c) {
            const auto low = static_cast<std::uint8_t>(raw[c * n + v]);
            const auto high = static_cast<std::uint8_t>(raw[3 * n + c * n + v]);
            const auto residual = static_cast<std::int16_t>(static_cast<std::uint16_t>(low | (high << 8)));
            const std::int64_t value = preview_prediction(refs[v], g, c) + residual;
            if (value < 0 || value > levels)
                r.fail("preview vertex " + std::to_string(v) + " lies off its grid (" + std::to_string(value) +
                       ", allowed 0.." + std::to_string(levels) + ")");
            g[3 * v + c] = static_cast<std::int32_t>(value);
        }
    const double step = preview_step(header, levels);
    std::vector<Vec3f> frame(n);
    for (std::size_t v = 0; v < n; ++v)
        for (int c = 0; c < 3; ++c)
            frame[v][c] = static_cast<float>(double(header.bounds.min[c]) + step * double(g[3 * v + std::size_t(c)]));
    return frame;
}

}  // namespace foldcast::codec
