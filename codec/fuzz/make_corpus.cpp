// Writes the seed corpus of fuzz_fca_decode (codec/fuzz/corpus) from a tiny synthetic
// animation: the seeds are tied to the .fca format version, so rerun this whenever the
// bitstream changes:  fuzz_make_corpus codec/fuzz/corpus
// (The v3_*.bin seeds were written by it in format version 3, v5_bending_cascade.bin in
// format 5 (one escape table); both are still read.)
// Each seed is one split byte (where the fuzz target cuts the input into two feeds)
// followed by an .fca file, or a prefix of one.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "foldcast/codec/codec.hpp"

using namespace foldcast;

namespace {
// Two triangles per quad of a cols x rows vertex sheet, row by row.
std::vector<Triangle> sheet_triangles(int cols, int rows) {
    std::vector<Triangle> triangles;
    for (int r = 0; r + 1 < rows; ++r)
        for (int c = 0; c + 1 < cols; ++c) {
            const auto v = static_cast<std::uint32_t>(r * cols + c), down = static_cast<std::uint32_t>(cols);
            triangles.push_back({v, v + 1, v + down});
            triangles.push_back({v + 1, v + down + 1, v + down});
        }
    return triangles;
}

// A 3 x 4 vertex sheet waving for 20 frames, with a jump halfway (a new fold appears).
Animation tiny_animation() {
    Animation a;
    constexpr int kCols = 3, kRows = 4, kFrames = 20;
    a.topology.triangles = sheet_triangles(kCols, kRows);
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

// A 9 x 7 vertex sheet rolled round cylinders of erratically changing radius, 24 frames:
// where profile cascade codes frames isometrically and with weights of their own.
Animation bending_animation() {
    Animation a;
    constexpr int kCols = 9, kRows = 7, kFrames = 24;
    a.topology.triangles = sheet_triangles(kCols, kRows);
    for (int t = 0; t < kFrames; ++t) {
        const float curvature = 0.5f + 6.0f * std::fmod(0.618034f * float(t), 1.0f);  // per metre
        std::vector<Vec3f> frame;
        for (int r = 0; r < kRows; ++r)
            for (int c = 0; c < kCols; ++c) {
                const float arc = 0.08f * float(c) + 0.06f * float(r), along = -0.06f * float(c) + 0.08f * float(r);
                const float bent = std::sin(arc * curvature) / curvature;
                frame.emplace_back(0.8f * bent - 0.6f * along, 0.6f * bent + 0.8f * along,
                                   (1.0f - std::cos(arc * curvature)) / curvature);
            }
        a.frames.push_back(std::move(frame));
    }
    return a;
}

// A seed of fuzz_fca_paper: N - 1, T - 2 (u16), then each data packet's profile payload as
// a u16 length and its bytes (the packet framing, sequence numbers and CRCs left out).
void write_paper_seed(const std::filesystem::path& dir, const std::string& name, const std::string& fca,
                      std::size_t vertices, std::size_t frames) {
    std::string seed;
    seed += static_cast<char>(vertices - 1);
    seed += static_cast<char>((frames - 2) & 0xff);
    seed += static_cast<char>((frames - 2) >> 8);
    std::size_t at = 8;  // after the magic
    while (at + 9 <= fca.size()) {
        std::uint32_t length = 0;
        std::memcpy(&length, fca.data() + at, 4);
        if (fca[at + 4] == 2 && length >= 4) {  // a data packet: its payload after the sequence number
            const std::string payload = fca.substr(at + 5 + 4, length - 4);
            seed += static_cast<char>(payload.size() & 0xff);
            seed += static_cast<char>(payload.size() >> 8);
            seed += payload;
        }
        at += 9 + length;
    }
    std::ofstream(dir / name, std::ios::binary) << seed;
}

// Bytes from the file's start to the end of packet k (0 = the header).
std::size_t end_of_packet(const std::string& fca, int k) {
    std::size_t at = 8;
    for (int i = 0; i <= k && at + 9 <= fca.size(); ++i) {
        std::uint32_t length = 0;
        std::memcpy(&length, fca.data() + at, 4);
        at += 9 + length;
    }
    return at;
}

void write_seed(const std::filesystem::path& dir, const std::string& name, const std::string& fca,
                std::size_t keep_bytes) {
    std::ofstream out(dir / name, std::ios::binary);
    out.put('\x40');
    out.write(fca.data(), static_cast<std::streamsize>(std::min(keep_bytes, fca.size())));
}
}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: fuzz_make_corpus DIR PAPER_DIR\n");
        return 2;
    }
    const std::filesystem::path dir = argv[1], paper_dir = argv[2];
    std::filesystem::create_directories(dir);
    std::filesystem::create_directories(paper_dir);
    const Animation a = tiny_animation();
    codec::EncodeOptions bounded;
    bounded.max_error_m = 1e-3;
    bounded.metadata = {{"look", "denim"}};
    const std::string def = codec::encode(a, bounded);
    bounded.metadata.clear();
    write_seed(dir, "tiny_default.bin", def, def.size());
    write_seed(dir, "tiny_default_truncated.bin", def, def.size() / 2);
    write_seed(dir, "tiny_default_preview_truncated.bin", def, end_of_packet(def, 1));
    bounded.profile = codec::Profile::cascade;
    const std::string cascade = codec::encode(a, bounded);
    write_seed(dir, "tiny_cascade.bin", cascade, cascade.size());
    write_seed(dir, "tiny_cascade_truncated.bin", cascade, cascade.size() / 2);
    const std::string bending = codec::encode(bending_animation(), bounded);
    write_seed(dir, "bending_cascade.bin", bending, bending.size());
    write_seed(dir, "bending_cascade_truncated.bin", bending, bending.size() * 2 / 3);
    bounded.profile = codec::Profile::paper;
    const std::string paper = codec::encode(a, bounded);
    write_seed(dir, "tiny_paper.bin", paper, paper.size());
    write_seed(dir, "tiny_paper_truncated.bin", paper, paper.size() / 2);
    codec::EncodeOptions keep;
    keep.profile = codec::Profile::paper;
    keep.keep_fraction = 0.5;
    const std::string kept = codec::encode(a, keep);
    write_seed(dir, "tiny_paper_keep.bin", kept, std::string::npos);
    write_paper_seed(paper_dir, "tiny_paper.bin", paper, a.vertex_count(), a.frame_count());
    write_paper_seed(paper_dir, "tiny_paper_keep.bin", kept, a.vertex_count(), a.frame_count());
    return 0;
}
