// Writes the seed corpus of fuzz_fca_decode (codec/fuzz/corpus) from a tiny synthetic
// animation: the seeds are tied to the .fca format version, so rerun this whenever the
// bitstream changes:  fuzz_make_corpus codec/fuzz/corpus
// Each seed is one split byte (where the fuzz target cuts the input into two feeds)
// followed by an .fca file, or a prefix of one.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "foldcast/codec.hpp"

using namespace foldcast;

namespace {
// A 3 x 4 vertex sheet waving for 20 frames, with a jump halfway (a new fold appears).
Animation tiny_animation() {
    Animation a;
    constexpr int kCols = 3, kRows = 4, kFrames = 20;
    for (int r = 0; r + 1 < kRows; ++r)
        for (int c = 0; c + 1 < kCols; ++c) {
            const auto v = static_cast<std::uint32_t>(r * kCols + c);
            a.topology.triangles.push_back({v, v + 1, v + kCols});
            a.topology.triangles.push_back({v + 1, v + kCols + 1, v + kCols});
        }
    for (int t = 0; t < kFrames; ++t) {
        std::vector<Vec3f> frame;
        for (int r = 0; r < kRows; ++r)
            for (int c = 0; c < kCols; ++c) {
                const float wave = 0.05f * std::sin(0.4f * float(t) + float(r));
                const float fold = t >= kFrames / 2 ? 0.03f * float((r + c) % 2) : 0.0f;
                frame.emplace_back(0.1f * float(c), -0.1f * float(r), wave + fold);
            }
        a.frames.push_back(std::move(frame));
    }
    return a;
}

void write_seed(const std::filesystem::path& dir, const std::string& name, const std::string& fca, std::size_t keep_bytes) {
    std::ofstream out(dir / name, std::ios::binary);
    out.put('\x40');
    out.write(fca.data(), static_cast<std::streamsize>(std::min(keep_bytes, fca.size())));
}
}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: fuzz_make_corpus DIR\n");
        return 2;
    }
    const std::filesystem::path dir = argv[1];
    std::filesystem::create_directories(dir);
    const Animation a = tiny_animation();
    codec::EncodeOptions bounded;
    bounded.max_error_m = 1e-3;
    const std::string def = codec::encode(a, bounded);
    write_seed(dir, "tiny_default.bin", def, def.size());
    write_seed(dir, "tiny_default_truncated.bin", def, def.size() / 2);
    bounded.profile = codec::Profile::paper;
    const std::string paper = codec::encode(a, bounded);
    write_seed(dir, "tiny_paper.bin", paper, paper.size());
    write_seed(dir, "tiny_paper_truncated.bin", paper, paper.size() / 2);
    codec::EncodeOptions keep;
    keep.profile = codec::Profile::paper;
    keep.keep_fraction = 0.5;
    write_seed(dir, "tiny_paper_keep.bin", codec::encode(a, keep), std::string::npos);
    return 0;
}
