// Top-level encoder: validates, picks the quantisation, runs a profile, frames the packets.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "container.hpp"
#include "foldcast/codec/codec.hpp"
#include "foldcast/core/error.hpp"
#include "paper_profile.hpp"
#include "preview.hpp"
#include "predictive_profile.hpp"

namespace foldcast::codec {

std::string profile_name(Profile p) {
    return p == Profile::paper ? "paper" : p == Profile::cascade ? "cascade" : "default";
}

Profile parse_profile(const std::string& name) {
    if (name == "paper") return Profile::paper;
    if (name == "default") return Profile::predictive;
    if (name == "cascade") return Profile::cascade;
    throw InputError("codec profile '" + name + "' is unknown (allowed: paper, default, cascade)");
}

namespace {
// Paper: the largest step (threshold = step, a dead-zone quantiser) whose decoded max
// error meets the bound, by bisection in log space.
double paper_step_for_error(const PaperEncoder& enc, double max_error_m, double diagonal, const ProgressFn& progress) {
    double lo = enc.min_step(), hi = std::max(lo * 2.0, diagonal * 64.0);
    if (enc.max_error_m(lo, lo) > max_error_m) return lo;  // bound below float precision: best possible
    for (int i = 0; i < 40 && hi / lo > 1.01; ++i) {
        const double mid = std::sqrt(lo * hi);
        (enc.max_error_m(mid, mid) <= max_error_m ? lo : hi) = mid;
        if (progress) progress("rate control", double(i + 1) / 40.0);
    }
    return lo;
}

std::string assemble(Header header, const std::vector<Vec3f>& frame0, const std::vector<std::string>& packets) {
    std::string preview;
    append_packet(preview, PacketType::preview, preview_payload(frame0, header));
    std::string body;
    for (std::size_t i = 0; i < packets.size(); ++i) {
        std::string payload(4, '\0');
        const auto seq = static_cast<std::uint32_t>(i);
        std::memcpy(payload.data(), &seq, 4);
        payload += packets[i];
        append_packet(body, PacketType::data, payload);
        if (i == 0) header.first_frame_bytes = body.size();
    }
    std::string end(4, '\0');
    const auto count = static_cast<std::uint32_t>(packets.size());
    std::memcpy(end.data(), &count, 4);
    append_packet(body, PacketType::end, end);
    header.total_bytes = 0;
    const std::size_t header_bytes = sizeof(kMagic) + kPacketOverhead + header_payload(header).size();
    header.total_bytes = header_bytes + preview.size() + body.size();
    header.first_frame_bytes += header_bytes + preview.size();
    std::string file(kMagic, sizeof(kMagic));
    append_packet(file, PacketType::header, header_payload(header));
    file += preview;
    file += body;
    return file;
}
}  // namespace

std::string encode(const Animation& anim, const EncodeOptions& options, const ProgressFn& progress) {
    validate(anim, "animation to encode");
    if (anim.frames.empty() || anim.vertex_count() == 0)
        throw InputError("animation to encode has no frames or no vertices");
    if (anim.vertex_count() > 0xffffffffu || anim.frame_count() > 0xffffffffu ||
        double(anim.vertex_count()) * double(anim.frame_count()) > double(kMaxVertexFrames))
        throw InputError("animation to encode is too large (" + std::to_string(anim.vertex_count()) + " x " +
                         std::to_string(anim.frame_count()) + " vertex-frames, limit " +
                         std::to_string(kMaxVertexFrames) + ")");
    if (anim.vertex_count() > kMaxVertices || anim.frame_count() > kMaxFrames)
        throw InputError("animation to encode has " + std::to_string(anim.vertex_count()) + " vertices and " +
                         std::to_string(anim.frame_count()) + " frames (at most " + std::to_string(kMaxVertices) +
                         " and " + std::to_string(kMaxFrames) + ")");
    if (anim.topology.triangles.size() > kMaxTrianglesPerVertex * anim.vertex_count())
        throw InputError("animation to encode has " + std::to_string(anim.topology.triangles.size()) +
                         " triangles for " + std::to_string(anim.vertex_count()) + " vertices (at most " +
                         std::to_string(kMaxTrianglesPerVertex) + " per vertex)");
    if (options.profile == Profile::paper && anim.frame_count() > kMaxPaperFrames)
        throw InputError("animation to encode has " + std::to_string(anim.frame_count()) +
                         " frames; the paper profile holds at most " + std::to_string(kMaxPaperFrames) +
                         " (use the default profile)");
    if (!(std::isfinite(anim.fps) && anim.fps > 0.0 && anim.fps <= 1e6))
        throw InputError("animation to encode has fps " + std::to_string(anim.fps) + " (allowed (0, 1e6])");
    if (options.max_error_m && options.keep_fraction)
        throw InputError("encode options: max_error_m and keep_fraction are mutually exclusive: give one");
    if (options.max_error_m && !(std::isfinite(*options.max_error_m) && *options.max_error_m > 0.0))
        throw InputError("encode options: max_error_m = " + std::to_string(*options.max_error_m) +
                         " (allowed: > 0 metres)");
    if (options.keep_fraction && !(*options.keep_fraction > 0.0 && *options.keep_fraction <= 1.0))
        throw InputError("encode options: keep_fraction = " + std::to_string(*options.keep_fraction) +
                         " (allowed: (0, 1])");
    if (options.keep_fraction && options.profile != Profile::paper)
        throw InputError(
            "encode options: keep_fraction applies to the paper profile only (the default profile is error-bounded: "
            "use max_error_m)");

    if (const std::string problem = metadata_problem(options.metadata); !problem.empty())
        throw InputError("encode options: " + problem);

    Header header;
    header.metadata = options.metadata;
    header.profile = options.profile;
    header.vertices = static_cast<std::uint32_t>(anim.vertex_count());
    header.frames = static_cast<std::uint32_t>(anim.frame_count());
    header.fps = anim.fps;
    header.bounds = bounds(anim);
    header.topology = anim.topology;
    const double diagonal = std::max(double(header.bounds.diagonal()), 1e-6);
    const double max_error = options.max_error_m.value_or(kDefaultMaxErrorRel * diagonal);

    std::vector<std::string> packets;
    if (options.profile == Profile::paper) {
        const PaperEncoder enc(anim);
        if (options.keep_fraction) {
            header.threshold = enc.threshold_for_keep(*options.keep_fraction);
            header.step = std::max(enc.min_step(), std::isfinite(header.threshold) ? header.threshold : enc.min_step());
            if (!std::isfinite(header.threshold)) header.threshold = 1e300;
        } else {
            header.step = paper_step_for_error(enc, max_error, diagonal, progress);
            header.threshold = header.step;
        }
        packets = enc.packets(header.step, header.threshold);
    } else {
        // Per-coordinate error <= Delta/2 makes the Euclidean error <= Delta * sqrt(3) / 2 =
        // max_error.  The fine grid (step d) rounds by <= d/2 and the closed-loop residual
        // quantiser (step m d) by <= m d / 2: d = Delta / (m + 1).
        const float extent = (header.bounds.max - header.bounds.min).maxCoeff();
        const std::uint32_t m = kDefaultResidualStep;
        header.threshold = m;
        header.step =
            std::max(2.0 * max_error / std::sqrt(3.0) / double(m + 1), double(extent) / double(kMaxGridValue / 2));
        header.profile_param = static_cast<std::uint32_t>(default_stride_log2(anim.frame_count(), anim.vertex_count()));
        const std::size_t n = anim.vertex_count();
        std::vector<std::int32_t> grid(anim.frame_count() * 3 * n);
        for (std::size_t t = 0; t < anim.frame_count(); ++t)
            for (std::size_t v = 0; v < n; ++v)
                for (int c = 0; c < 3; ++c)
                    grid[(t * n + v) * 3 + static_cast<std::size_t>(c)] = static_cast<std::int32_t>(
                        std::llround((double(anim.frames[t][v][c]) - double(header.bounds.min[c])) / header.step));
        const PredictiveLayout layout(anim.frame_count(), static_cast<int>(header.profile_param));
        packets =
            predictive_packets(layout, anim.topology.triangles, n, grid, m, -1, options.profile == Profile::cascade);
    }
    if (progress) progress("encode", 1.0);
    return assemble(header, anim.frames.front(), packets);
}

}  // namespace foldcast::codec
