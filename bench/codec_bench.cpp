// Codec rate-distortion and speed (docs/benchmarks.md, section "codec").  A timed run, not
// Google Benchmark: each point encodes, decodes (best of a few runs) and measures.
//   build/bench/codec_bench [--quick] [--input NAME=FILE.pc2 ...] [--no-builtin] [--ratio]
// Inputs: basicCloth (tests/data) and a 128x128-vertex, 240-frame drape animation
// (drape::animate with default cloth parameters; --quick: 32x32, 60 frames), unless
// --no-builtin; --input adds a PC2 animation (triangles from the .obj beside it, e.g. from
// bench/blender_codec_animations.py).  --ratio: instead of every method, profiles default and
// cascade at max-error 3.2e-3 .. 2.5e-5 x diagonal and meshopt+zstd at 8..15 bits, then per
// input the size ratio .fca / meshopt+zstd at equal Karni-Gotsman error (both curves
// interpolated in log-log at KG 0.03, 0.065, 0.14 and 0.275 %; "-" outside either curve's
// measured range).
// Methods: the `paper` and `default` profiles swept over error bounds, and two baselines
// built from Debian libraries: 12-bit quantisation + per-frame temporal delta +
// meshoptimizer's vertex codec + zstd -19, and raw float32 + zstd -19.
#include <meshoptimizer.h>
#include <zstd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "foldcast/codec/codec.hpp"
#include "foldcast/drape/drape.hpp"
#include "foldcast/core/mesh_io.hpp"

using namespace foldcast;
using Clock = std::chrono::steady_clock;

namespace {

// foldcast's own garment: a drape animation (supports moving in, folds forming).
Animation drape_animation(int n, int frames) {
    drape::AnimationOptions options;
    options.frames = frames;
    options.fps = 30.0;
    return drape::animate(drape::ClothParams{}, drape::GridSize{n, n}, options);
}

struct Coded {
    std::size_t bytes;
    std::function<Animation()> decode;
};

std::string zstd19(const void* data, std::size_t size) {
    std::string out(ZSTD_compressBound(size), '\0');
    out.resize(ZSTD_compress(out.data(), out.size(), data, size, 19));
    return out;
}
std::string unzstd(const std::string& packed) {
    std::string raw(ZSTD_getFrameContentSize(packed.data(), packed.size()), '\0');
    ZSTD_decompress(raw.data(), raw.size(), packed.data(), packed.size());
    return raw;
}

Coded raw_zstd(const Animation& a) {
    std::vector<float> flat;
    for (const auto& f : a.frames)
        for (const auto& p : f) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
    auto packed = std::make_shared<std::string>(zstd19(flat.data(), flat.size() * 4));
    const std::size_t n = a.vertex_count();
    return {packed->size(), [packed, n, a]() {
                const std::string raw = unzstd(*packed);
                Animation b;
                b.topology = a.topology;
                const float* p = reinterpret_cast<const float*>(raw.data());
                for (std::size_t t = 0; t < a.frame_count(); ++t) {
                    std::vector<Vec3f> f(n);
                    for (std::size_t v = 0; v < n; ++v)
                        f[v] = Vec3f(p[(t * n + v) * 3], p[(t * n + v) * 3 + 1], p[(t * n + v) * 3 + 2]);
                    b.frames.push_back(std::move(f));
                }
                return b;
            }};
}

Coded meshopt_baseline(const Animation& a, int bits) {
    const Bounds box = bounds(a);
    const Vec3f extent = (box.max - box.min).cwiseMax(Vec3f::Constant(1e-12f));
    const float levels = float((1 << bits) - 1);
    const std::size_t n = a.vertex_count();
    struct V {
        std::uint16_t x, y, z, pad;
    };
    std::vector<V> prev(n, V{0, 0, 0, 0}), cur(n);
    std::string stream;
    std::vector<unsigned char> buf(meshopt_encodeVertexBufferBound(n, sizeof(V)));
    for (const auto& f : a.frames) {
        std::vector<V> delta(n);
        for (std::size_t v = 0; v < n; ++v) {
            const Vec3f q = ((f[v] - box.min).cwiseQuotient(extent) * levels).array().round();
            cur[v] = {std::uint16_t(q.x()), std::uint16_t(q.y()), std::uint16_t(q.z()), 0};
            delta[v] = {std::uint16_t(cur[v].x - prev[v].x), std::uint16_t(cur[v].y - prev[v].y),
                        std::uint16_t(cur[v].z - prev[v].z), 0};
        }
        prev = cur;
        const std::size_t size = meshopt_encodeVertexBuffer(buf.data(), buf.size(), delta.data(), n, sizeof(V));
        const auto size32 = static_cast<std::uint32_t>(size);
        stream.append(reinterpret_cast<const char*>(&size32), 4);
        stream.append(reinterpret_cast<const char*>(buf.data()), size);
    }
    auto packed = std::make_shared<std::string>(zstd19(stream.data(), stream.size()));
    return {packed->size(), [packed, n, a, box, extent, levels]() {
                const std::string raw = unzstd(*packed);
                Animation b;
                b.topology = a.topology;
                std::vector<V> acc(n, V{0, 0, 0, 0}), delta(n);
                std::size_t pos = 0;
                for (std::size_t t = 0; t < a.frame_count(); ++t) {
                    std::uint32_t size;
                    std::memcpy(&size, raw.data() + pos, 4);
                    meshopt_decodeVertexBuffer(delta.data(), n, sizeof(V),
                                               reinterpret_cast<const unsigned char*>(raw.data() + pos + 4), size);
                    pos += 4 + size;
                    std::vector<Vec3f> f(n);
                    for (std::size_t v = 0; v < n; ++v) {
                        acc[v].x = std::uint16_t(acc[v].x + delta[v].x);
                        acc[v].y = std::uint16_t(acc[v].y + delta[v].y);
                        acc[v].z = std::uint16_t(acc[v].z + delta[v].z);
                        f[v] = box.min + Vec3f(acc[v].x, acc[v].y, acc[v].z).cwiseProduct(extent) / levels;
                    }
                    b.frames.push_back(std::move(f));
                }
                return b;
            }};
}

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Point {
    double kg, bytes;
};

// Coded size at Karni-Gotsman error `kg`, log-log interpolated between the measured points
// around it; nothing outside their range.
std::optional<double> bytes_at(std::vector<Point> points, double kg) {
    std::sort(points.begin(), points.end(), [](const Point& a, const Point& b) { return a.kg < b.kg; });
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
        const Point &a = points[i], &b = points[i + 1];
        if (kg < a.kg || kg > b.kg || a.kg <= 0.0) continue;
        const double s = b.kg > a.kg ? std::log(kg / a.kg) / std::log(b.kg / a.kg) : 0.0;
        return std::exp(std::log(a.bytes) + s * std::log(b.bytes / a.bytes));
    }
    return std::nullopt;
}

Point report(const char* input, const std::string& method, const std::string& setting, const Animation& a,
             const std::function<Coded()>& encode) {
    const auto t0 = Clock::now();
    const Coded coded = encode();
    const double enc_s = seconds_since(t0);
    double dec_s = 1e30;
    Animation back;
    for (int run = 0; run < 3; ++run) {
        const auto t1 = Clock::now();
        back = coded.decode();
        dec_s = std::min(dec_s, seconds_since(t1));
    }
    const codec::Metrics m = codec::measure(a, back, coded.bytes);
    const double vf = double(m.frames) * double(m.vertices);
    std::printf("%s,%s,%s,%zu,%.4f,%.5f,%.3e,%.3e,%.3g,%.3g\n", input, method.c_str(), setting.c_str(), coded.bytes,
                m.bpvf, m.kg_error, m.rms_error_rel, m.max_error_rel, vf / enc_s, vf / dec_s);
    std::fflush(stdout);
    return {m.kg_error, double(coded.bytes)};
}

Coded fca(const Animation& a, codec::Profile p, double rel) {
    codec::EncodeOptions o;
    o.profile = p;
    o.max_error_m = rel * bounds(a).diagonal();
    auto bytes = std::make_shared<std::string>(codec::encode(a, o));
    return Coded{bytes->size(), [bytes] { return codec::decode(*bytes); }};
}

std::string setting_name(double rel) {
    char setting[64];
    std::snprintf(setting, sizeof setting, "max-error %.2g diag", rel);
    return setting;
}

// The .fca profiles against meshopt+zstd at equal KG error: the size ratio at the same mean error, the measure the
// codec's targets are set in.
void ratios(const char* name, const Animation& a, const std::vector<codec::Profile>& profiles) {
    std::vector<Point> baseline;
    for (int bits = 8; bits <= 15; ++bits)
        baseline.push_back(report(name, "meshopt+zstd19", std::to_string(bits) + "-bit", a,
                                  [&] { return meshopt_baseline(a, bits); }));
    for (const codec::Profile p : profiles) {
        std::vector<Point> points;
        for (double rel : {3.2e-3, 1.6e-3, 8e-4, 4e-4, 2e-4, 1e-4, 5e-5, 2.5e-5})
            points.push_back(
                report(name, codec::profile_name(p), setting_name(rel), a, [&] { return fca(a, p, rel); }));
        std::printf("ratio,%s,%s,%zux%zu", name, codec::profile_name(p).c_str(), a.vertex_count(), a.frame_count());
        for (double kg : {0.03, 0.065, 0.14, 0.275}) {
            const auto ours = bytes_at(points, kg), theirs = bytes_at(baseline, kg);
            if (ours && theirs)
                std::printf(",KG %.3g: %.3f", kg, *ours / *theirs);
            else
                std::printf(",KG %.3g: -", kg);
        }
        std::printf("\n");
        std::fflush(stdout);
    }
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false, builtin = true, ratio = false;
    struct Input {
        std::string name;
        Animation anim;
    };
    std::vector<Input> inputs;
    std::vector<std::pair<std::string, std::string>> files;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--quick") {
            quick = true;
        } else if (arg == "--no-builtin") {
            builtin = false;
        } else if (arg == "--ratio") {
            ratio = true;
        } else if (arg == "--input" && i + 1 < argc && std::strchr(argv[i + 1], '=') != nullptr) {
            const std::string spec = argv[++i];
            files.emplace_back(spec.substr(0, spec.find('=')), spec.substr(spec.find('=') + 1));
        } else {
            std::fprintf(stderr,
                         "usage: codec_bench [--quick] [--input NAME=FILE.pc2 ...] [--no-builtin] [--ratio]\n"
                         "unknown or incomplete argument '%s'\n",
                         arg.c_str());
            return 2;
        }
    }
    try {
        if (builtin) {
            inputs.push_back(
                {"basicCloth",
                 read_pc2_animation(std::string(FOLDCAST_SOURCE_DIR) + "/tests/data/animations/basicCloth.pc2",
                                    std::string(FOLDCAST_SOURCE_DIR) + "/tests/data/animations/basicCloth.obj")});
            inputs.push_back({quick ? "drape32x32x60" : "drape128x128x240",
                              quick ? drape_animation(32, 60) : drape_animation(128, 240)});
        }
        for (const auto& [name, pc2] : files) {
            std::filesystem::path obj = pc2;
            obj.replace_extension(".obj");
            inputs.push_back({name, read_pc2_animation(pc2, obj)});
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "codec_bench: %s\n", e.what());
        return 2;
    }
    std::printf(
        "input,method,setting,bytes,bpvf,kg_error,rms_error_rel,max_error_rel,encode_vf_per_s,decode_vf_per_s\n");
    for (const auto& in : inputs) {
        const Animation& a = in.anim;
        const char* name = in.name.c_str();
        if (ratio) {
            ratios(name, a, {codec::Profile::predictive, codec::Profile::cascade});
            continue;
        }
        report(name, "raw-float32+zstd19", "lossless", a, [&] { return raw_zstd(a); });
        for (int bits : {10, 12, 14})
            report(name, "meshopt+zstd19", std::to_string(bits) + "-bit", a, [&] { return meshopt_baseline(a, bits); });
        for (const codec::Profile p : {codec::Profile::predictive, codec::Profile::paper})
            for (double rel : {1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5})
                report(name, codec::profile_name(p), setting_name(rel), a, [&] { return fca(a, p, rel); });
    }
    return 0;
}
