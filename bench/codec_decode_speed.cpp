// Decode speed of the `default` (or --profile cascade) profile in CPU time (CLOCK_THREAD_CPUTIME_ID: the figure
// that counts on a shared machine), plus its rate at Karni-Gotsman error 0.05 % (docs/benchmarks.md).
//   build/bench/codec_decode_speed [--cache DIR] [--runs K] [--no-rate] [--grids] [--profile default|cascade]
// Inputs: basicCloth (tests/data) and the 128x128-vertex, 240-frame drape animation
// (--grids: also 16x16, 32x32 and 64x64, speed only)
// (drape::animate, default cloth; written to DIR/drape128x128x240.{pc2,obj} once and read
// back later, since simulating it takes a while).  Speed: decode of the file encoded at
// max-error 2e-4 x diagonal, best of K runs (default 7), vertex-frames per CPU second.
// Rate: bpvf at KG 0.05 % log-interpolated between the sweep points around it.
#include <time.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "foldcast/codec/codec.hpp"
#include "foldcast/core/mesh_io.hpp"
#include "foldcast/drape/drape.hpp"

using namespace foldcast;

namespace {

double cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

std::string drape_name(int grid) { return "drape" + std::to_string(grid) + "x" + std::to_string(grid) + "x240"; }

Animation drape_animation(const std::filesystem::path& cache, int grid = 128) {
    const auto pc2 = cache / (drape_name(grid) + ".pc2"), obj = cache / (drape_name(grid) + ".obj");
    if (std::filesystem::exists(pc2) && std::filesystem::exists(obj)) return read_pc2_animation(pc2, obj);
    drape::AnimationOptions options;
    options.frames = 240;
    options.fps = 30.0;
    Animation a = drape::animate(drape::ClothParams{}, drape::GridSize{grid, grid}, options);
    std::filesystem::create_directories(cache);
    write_pc2_animation(pc2, a);          // and the .obj beside it
    return read_pc2_animation(pc2, obj);  // what later runs see (float round trip through the files)
}

codec::Profile profile = codec::Profile::predictive;  // --profile

std::string encode_at(const Animation& a, double rel) {
    codec::EncodeOptions o;
    o.profile = profile;
    o.max_error_m = rel * bounds(a).diagonal();
    return codec::encode(a, o);
}

void speed(const char* name, const Animation& a, int runs) {
    const std::string bytes = encode_at(a, 2e-4);
    double best = 1e30;
    Animation back;
    for (int r = 0; r < runs; ++r) {
        const double t0 = cpu_seconds();
        back = codec::decode(bytes);
        best = std::min(best, cpu_seconds() - t0);
        if (r + 1 < runs) back = Animation{};  // free, so each run allocates its output like a one-off caller
    }
    const double vf = double(a.frame_count()) * double(a.vertex_count());
    std::printf("%s: decode %.2f ms CPU (best of %d), %.1f M vertex-frames/s per core, %zu bytes\n", name, best * 1e3,
                runs, vf / best * 1e-6, bytes.size());

    // Decoding into the frame buffers of the previous result, as a player or converter
    // decoding clip after clip does: the difference to the above is the kernel mapping and
    // zeroing fresh pages for the output.
    Animation reused = codec::decode(bytes);
    double best_reused = 1e30;
    for (int r = 0; r < runs; ++r) {
        const double t0 = cpu_seconds();
        codec::decode(bytes, reused);
        best_reused = std::min(best_reused, cpu_seconds() - t0);
    }
    if (reused.frames != back.frames) {
        std::fprintf(stderr, "%s: decoding into reused buffers gave other frames\n", name);
        std::exit(1);
    }
    std::printf(
        "%s: decode into the previous animation's buffers %.2f ms CPU (best of %d), %.1f M vertex-frames/s per core\n",
        name, best_reused * 1e3, runs, vf / best_reused * 1e-6);

    // A player's access: the whole file fed to a streaming decoder, then every frame alone
    // into one reused buffer.
    double best_playback = 1e30;
    for (int r = 0; r < runs; ++r) {
        const double t0 = cpu_seconds();
        codec::StreamingDecoder decoder(name, bytes.size());
        decoder.feed(bytes);
        std::vector<Vec3f> frame;  // one buffer, reused: what a player holds
        for (std::size_t t = 0; t < decoder.frame_count(); ++t) {
            decoder.frame(t, frame);
            if (frame.size() != a.vertex_count()) std::abort();
        }
        best_playback = std::min(best_playback, cpu_seconds() - t0);
    }
    std::printf("%s: feed + frame(t) for every t %.2f ms CPU (best of %d), %.1f M vertex-frames/s per core\n", name,
                best_playback * 1e3, runs, vf / best_playback * 1e-6);
}

void rate(const char* name, const Animation& a) {
    double prev_kg = 0, prev_bpvf = 0;
    for (double rel : {1.0e-4, 1.5e-4, 2.0e-4, 2.5e-4, 3.0e-4, 4.0e-4}) {
        const std::string bytes = encode_at(a, rel);
        const codec::Metrics m = codec::measure(a, codec::decode(bytes), bytes.size());
        std::printf("%s: max-error %.1e diag: %.4f bpvf, KG %.4f %%\n", name, rel, m.bpvf, m.kg_error);
        if (prev_kg > 0 && prev_kg < 0.05 && m.kg_error >= 0.05) {
            const double w = (std::log(0.05) - std::log(prev_kg)) / (std::log(m.kg_error) - std::log(prev_kg));
            std::printf("%s: at KG 0.05 %%: %.3f bpvf\n", name,
                        std::exp((1 - w) * std::log(prev_bpvf) + w * std::log(m.bpvf)));
            return;
        }
        prev_kg = m.kg_error;
        prev_bpvf = m.bpvf;
    }
}

}  // namespace

int main(int argc, char** argv) {
    std::filesystem::path cache = std::filesystem::temp_directory_path() / "foldcast-bench";
    int runs = 7;
    bool do_rate = true, grids = false;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--cache") == 0 && i + 1 < argc)
            cache = argv[++i];
        else if (std::strcmp(argv[i], "--runs") == 0 && i + 1 < argc)
            runs = std::max(1, std::atoi(argv[++i]));
        else if (std::strcmp(argv[i], "--no-rate") == 0)
            do_rate = false;
        else if (std::strcmp(argv[i], "--grids") == 0)
            grids = true;
        else if (std::strcmp(argv[i], "--profile") == 0 && i + 1 < argc &&
                 (std::strcmp(argv[i + 1], "default") == 0 || std::strcmp(argv[i + 1], "cascade") == 0))
            profile = codec::parse_profile(argv[++i]);
        else {
            std::fprintf(stderr,
                         "usage: codec_decode_speed [--cache DIR] [--runs K] [--no-rate] [--grids] "
                         "[--profile default|cascade]\n");
            return 2;
        }
    }
    const Animation cloth =
        read_pc2_animation(std::string(FOLDCAST_SOURCE_DIR) + "/tests/data/animations/basicCloth.pc2",
                           std::string(FOLDCAST_SOURCE_DIR) + "/tests/data/animations/basicCloth.obj");
    const Animation drape = drape_animation(cache);
    speed("drape128x128x240", drape, runs);
    speed("basicCloth", cloth, runs * 20);
    if (grids)
        for (int grid : {16, 32, 64})
            speed(drape_name(grid).c_str(), drape_animation(cache, grid), runs * 128 * 128 / (grid * grid));
    if (do_rate) {
        rate("drape128x128x240", drape);
        rate("basicCloth", cloth);
    }
    return 0;
}
