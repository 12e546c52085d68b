// foldcast encode IN -o OUT.fca: compress a PC2 cache (+ OBJ topology) or re-encode an .fca.
#include <chrono>
#include <limits>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "foldcast/codec/codec.hpp"
#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/core/mesh_io.hpp"
#include "progress_bar.hpp"

namespace foldcast::app {

Command encode_command(CLI::App& app) {
    auto* sub = app.add_subcommand("encode", "Compress an animation (PC2 + OBJ, or .fca) into the .fca format");
    struct Options {
        std::string input, output, topology, profile = "default";
        std::optional<double> max_error_m, keep;
        double fps = 30.0;
        bool json = false, quiet = false;
    };
    auto o = std::make_shared<Options>();
    sub->add_option("input", o->input, "a .pc2 cache (topology from the .obj beside it) or an .fca file")->required();
    sub->add_option("-o,--output", o->output, "output .fca file")->required();
    sub->add_option("--topology", o->topology, "OBJ with the triangles and UVs (default: IN with .obj)");
    sub->add_option("--profile", o->profile,
                    "default, cascade (smaller files that decode 3-4x slower: finer reference frames, "
                    "weighted and isometric prediction, docs/codec.md) or paper (reference method)")
        ->check(CLI::IsMember({"paper", "default", "cascade"}))
        ->capture_default_str();
    auto* err = sub->add_option("--max-error-m", o->max_error_m,
                                "largest vertex error in metres (default: 2e-4 x bbox diagonal)");
    auto* keep = sub->add_option("--keep", o->keep, "paper: fraction (0,1] of wavelet coefficients kept")
                     ->check(CLI::Range(std::numeric_limits<double>::min(), 1.0));
    err->excludes(keep);
    sub->add_option("--fps", o->fps, "frames per second of a PC2 input")->capture_default_str();
    sub->add_flag("--json", o->json, "print a JSON report on stdout");
    sub->add_flag("-q,--quiet", o->quiet, "no progress bar");

    return {
        sub, [o]() {
            const std::filesystem::path in = o->input;
            check_not_input(o->output, in, "-o");  // re-encoding lossily over its own input
            if (!o->topology.empty()) check_not_input(o->output, o->topology, "-o");
            Animation anim;
            codec::Metadata metadata;  // an .fca's (its look) travels to the re-encoded file
            if (in.extension() == ".fca") {
                const std::string input = codec::read_fca(in);
                codec::StreamingDecoder decoder(in.string(), input.size());
                decoder.feed(input);
                anim = decoder.take_animation();
                metadata = decoder.metadata();
            } else if (in.extension() == ".pc2") {
                std::filesystem::path obj = o->topology;
                if (obj.empty()) obj = std::filesystem::path(in).replace_extension(".obj");
                if (!std::filesystem::exists(obj))
                    throw InputError("no topology for '" + in.string() + "': '" + obj.string() +
                                     "' does not exist (give --topology FILE.obj)");
                anim = read_pc2_animation(in, obj, o->fps);
            } else {
                throw InputError("input '" + in.string() + "' must be a .pc2 or .fca file");
            }
            if (std::filesystem::path(o->output).extension() != ".fca")
                throw InputError("-o '" + o->output + "' must end in .fca");
            check_writable(o->output);
            if (o->keep && o->profile != "paper")
                throw InputError(
                    "--keep applies to --profile paper only (the default profile is error-bounded: use --max-error-m)");
            codec::EncodeOptions options;
            options.profile = codec::parse_profile(o->profile);
            options.max_error_m = o->max_error_m;
            options.keep_fraction = o->keep;
            options.metadata = metadata;
            ProgressBar bar(o->quiet || o->json);
            const auto t0 = std::chrono::steady_clock::now();
            const std::string bytes = codec::encode(anim, options, bar.callback());
            const auto t1 = std::chrono::steady_clock::now();
            const Animation back = codec::decode(bytes, o->output);
            const auto t2 = std::chrono::steady_clock::now();
            codec::write_fca(o->output, bytes);
            const codec::Metrics m = codec::measure(anim, back, bytes.size());
            const double vf = double(m.frames) * double(m.vertices);
            const double enc_s = std::chrono::duration<double>(t1 - t0).count();
            const double dec_s = std::chrono::duration<double>(t2 - t1).count();
            if (o->json) {
                nlohmann::json j{{"output", o->output},
                                 {"profile", o->profile},
                                 {"frames", m.frames},
                                 {"vertices", m.vertices},
                                 {"bytes", m.bytes},
                                 {"bpvf", m.bpvf},
                                 {"rms_error_rel", m.rms_error_rel},
                                 {"max_error_rel", m.max_error_rel},
                                 {"max_error_m", m.max_error_m},
                                 {"kg_error", m.kg_error},
                                 {"encode_vertex_frames_per_s", vf / std::max(enc_s, 1e-9)},
                                 {"decode_vertex_frames_per_s", vf / std::max(dec_s, 1e-9)}};
                std::printf("%s\n", j.dump().c_str());
            } else {
                std::printf("%s: %zu frames x %zu vertices, %zu bytes, %.3f bpvf, max error %.3g m, KG error %.4f%%\n",
                            o->output.c_str(), m.frames, m.vertices, m.bytes, m.bpvf, m.max_error_m, m.kg_error);
            }
            return 0;
        }};
}

}  // namespace foldcast::app
