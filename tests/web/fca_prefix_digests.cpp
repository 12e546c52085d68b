// For the WebAssembly decoder's test (web/test/wasm_matches_native.mjs): decodes each
// prefix FILE[0, cut) natively, as the player does (size known, StreamingDecoder), and prints
// one JSON line per cut: status and the SHA-256 of every frame's float32 xyz bytes, in order.
//   fca_prefix_digests FILE CUT...
#include <openssl/evp.h>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "foldcast/codec/codec.hpp"

namespace {
std::string hex(const unsigned char* bytes, unsigned n) {
    std::string s;
    char buffer[3];
    for (unsigned i = 0; i < n; ++i) {
        std::snprintf(buffer, sizeof buffer, "%02x", bytes[i]);
        s += buffer;
    }
    return s;
}
}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: fca_prefix_digests FILE CUT...\n");
        return 2;
    }
    const std::string bytes = foldcast::codec::read_fca(argv[1]);
    for (int i = 2; i < argc; ++i) {
        const std::size_t cut = std::min<std::size_t>(std::stoull(argv[i]), bytes.size());
        foldcast::codec::StreamingDecoder decoder("fca stream", bytes.size());
        nlohmann::json line{{"cut", cut}};
        try {
            decoder.feed(std::string_view(bytes).substr(0, cut));
        } catch (const std::exception& e) {
            line["error"] = e.what();
        }
        const auto s = decoder.status();
        line["header_ready"] = s.header_ready;
        line["complete"] = s.complete;
        line["playable"] = s.playable_frames;
        line["packets"] = s.packets;
        line["frame_ready"] = s.frame_ready;
        line["preview_only"] = s.preview_only;
        line["first_frame_bytes"] = s.first_frame_bytes;
        EVP_MD_CTX* sha = EVP_MD_CTX_new();
        EVP_DigestInit_ex(sha, EVP_sha256(), nullptr);
        if (s.frame_ready) {
            std::vector<foldcast::Vec3f> frame;
            for (std::size_t t = 0; t < decoder.frame_count(); ++t) {
                decoder.frame(t, frame);
                EVP_DigestUpdate(sha, frame.data(), frame.size() * sizeof(foldcast::Vec3f));
            }
        }
        unsigned char digest[EVP_MAX_MD_SIZE];
        unsigned n = 0;
        EVP_DigestFinal_ex(sha, digest, &n);
        EVP_MD_CTX_free(sha);
        line["sha256"] = hex(digest, n);
        std::printf("%s\n", line.dump().c_str());
    }
    return 0;
}
