// foldcast decode IN.fca -o OUT.pc2|OUT.glb: decompress to a PC2 cache plus the OBJ topology,
// or to a glTF 2.0 binary with the frames as morph targets (docs/gltf.md).
// A truncated file decodes to the best animation its prefix allows (with a warning).
#include <charconv>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>

#include "commands.hpp"
#include "foldcast/codec/codec.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/mesh_io.hpp"
#include "foldcast/core/resources.hpp"
#include "foldcast/export/gltf.hpp"
#include "foldcast/looks/looks.hpp"
#include "gltf_report.hpp"

namespace foldcast::app {
namespace {
// "A:B" -> frames [A, B); either side may be empty.
std::pair<std::size_t, std::size_t> parse_frames(const std::string& text, std::size_t count) {
    const auto colon = text.find(':');
    auto number = [&](std::string_view s, std::size_t fallback) {
        if (s.empty()) return fallback;
        std::size_t v = 0;
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (ec != std::errc() || end != s.data() + s.size())
            throw InputError("--frames '" + text + "': expected A:B with whole numbers (frames A..B-1)");
        return v;
    };
    if (colon == std::string::npos) throw InputError("--frames '" + text + "': expected A:B (frames A..B-1)");
    const std::size_t a = number(std::string_view(text).substr(0, colon), 0);
    const std::size_t b = number(std::string_view(text).substr(colon + 1), count);
    if (a >= b || b > count)
        throw InputError("--frames '" + text + "': the file has frames 0.." + std::to_string(count - 1) +
                         " (need A < B <= " + std::to_string(count) + ")");
    return {a, b};
}
}  // namespace

Command decode_command(CLI::App& app) {
    auto* sub = app.add_subcommand(
        "decode", "Decompress an .fca file to a PC2 cache (+ OBJ topology beside it) or a glTF 2.0 binary (.glb)");
    struct Options {
        std::string look;  // .glb only: the material, its --uncompressed and --max-error-m
        bool uncompressed = false;
        double max_error_m = 0.0;
        std::string input, output, frames;
        bool json = false, force = false, quiet = false;
    };
    auto o = std::make_shared<Options>();
    sub->add_option("input", o->input, "an .fca file (a truncated one decodes to a coarser animation)")->required();
    sub->add_option("-o,--output", o->output,
                    "output .pc2 (the .obj of the same name is written too) or .glb (morph-target animation)")
        ->required();
    sub->add_option("--look", o->look, ".glb: the material, a look's name (see `foldcast looks`) or a look .toml file");
    sub->add_flag("--uncompressed", o->uncompressed,
                  ".glb: float attributes, without KHR_mesh_quantization / EXT_meshopt_compression");
    sub->add_option("--max-error-m", o->max_error_m,
                    ".glb: the largest position error the quantization may add (m; default: the finest, 15 bits "
                    "over the largest side)")
        ->check(finite_in(0.0, 1.0))
        ->excludes("--uncompressed");
    sub->add_option("--frames", o->frames, "A:B: only frames A..B-1");
    sub->add_flag("--json", o->json, "print a JSON report on stdout");
    sub->add_flag("-q,--quiet", o->quiet, "print nothing on success (warnings and errors still go to stderr)");
    sub->add_flag("--force", o->force, "decode even when the estimated memory exceeds what this process can use");

    return {sub, [o]() {
                const bool glb = is_glb(o->output);
                if (std::filesystem::path(o->output).extension() != ".pc2" && !glb)
                    throw InputError("-o '" + o->output + "' must end in .pc2 or .glb");
                if (!o->look.empty() && !glb)
                    throw InputError("--look: only for -o OUT.glb (a PC2 cache has no material)");
                check_not_input(o->output, o->input, "-o");
                gltf::GlbOptions glb_options;
                if (!o->look.empty()) glb_options.look = looks::Library::load_default().find(o->look);
                glb_options.compress = !o->uncompressed;
                glb_options.max_position_error_m = o->max_error_m;
                if (o->max_error_m > 0.0 && !glb) throw InputError("--max-error-m: only for -o OUT.glb");
                const std::string bytes = codec::read_fca(o->input);
                codec::StreamingDecoder decoder(o->input, bytes.size());
                decoder.feed(bytes);
                const codec::StreamStatus status = decoder.status();
                if (!status.header_ready)
                    throw InputError(o->input + ": truncated inside its header (" + std::to_string(bytes.size()) +
                                     " bytes)");
                // Frames made from the header alone (or its coarse preview) would not be the
                // animation: every vertex at one point, or frame 0 held still.
                if (!status.frame_ready || status.preview_only)
                    throw InputError(o->input + ": truncated: its " + std::to_string(bytes.size()) +
                                     " bytes hold " + (status.preview_only ? "only a coarse preview of frame 0" : "no frame") +
                                     "; the first frame needs " +
                                     (status.first_frame_bytes ? std::to_string(status.first_frame_bytes) + " bytes"
                                                               : "the first data packet, which has not begun"));
                // The frames and a copy of them (--frames, the PC2 writer's buffer), and the decoder's
                // state (about 100 bytes per vertex), before any frame is made.
                const std::uint64_t vertex_frames = std::uint64_t(decoder.vertex_count()) * decoder.frame_count();
                require_memory(vertex_frames * sizeof(Vec3f) * 2 + std::uint64_t(decoder.vertex_count()) * 100,
                               o->input + ": decoding " + std::to_string(decoder.vertex_count()) + " vertices x " +
                                   std::to_string(decoder.frame_count()) + " frames",
                               "--force to try anyway", o->force);
                Animation anim = decoder.animation();
                if (!o->frames.empty()) {
                    const auto [a, b] = parse_frames(o->frames, anim.frame_count());
                    anim.frames = std::vector<std::vector<Vec3f>>(anim.frames.begin() + static_cast<std::ptrdiff_t>(a),
                                                                  anim.frames.begin() + static_cast<std::ptrdiff_t>(b));
                }
                if (!status.complete && status.playable_frames > 0)
                    std::fprintf(
                        stderr,
                        "foldcast: warning: '%s' is truncated: frames 0..%zu are final, later frames are coarser\n",
                        o->input.c_str(), status.playable_frames - 1);
                else if (!status.complete)
                    std::fprintf(stderr,
                                 "foldcast: warning: '%s' is truncated: no frame is final yet (interpolated "
                                 "between keyframes)\n",
                                 o->input.c_str());
                std::optional<gltf::GlbSummary> summary;
                if (glb)
                    summary = gltf::write_glb(o->output, anim, glb_options);
                else
                    write_pc2_animation(o->output, anim);
                if (summary && !o->json && !o->quiet) print_glb_summary(o->output, *summary, false, o->look);
                if (o->json) {
                    nlohmann::json j{{"output", o->output},
                                     {"frames", anim.frame_count()},
                                     {"vertices", anim.vertex_count()},
                                     {"fps", anim.fps},
                                     {"profile", codec::profile_name(decoder.profile())},
                                     {"bytes", bytes.size()},
                                     {"complete", status.complete},
                                     {"playable_frames", status.playable_frames},
                                     {"metadata", nlohmann::json::object()}};
                    for (const auto& [key, value] : decoder.metadata()) j["metadata"][key] = value;
                    if (summary)
                        j["glb"] = {{"bytes", summary->bytes},
                                    {"morph_targets", summary->morph_targets},
                                    {"compressed", summary->compressed},
                                    {"max_position_error_m", summary->max_position_error_m}};
                    std::printf("%s\n", j.dump().c_str());
                }
                return 0;
            }};
}

}  // namespace foldcast::app
