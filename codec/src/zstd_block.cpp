#include "zstd_block.hpp"

#include <zstd.h>

#include <algorithm>
#include <memory>
#include <new>
#include <stdexcept>

namespace foldcast::codec {
namespace {
// One zstd decompression context per thread, reused: ZSTD_decompress would allocate and
// initialise one (over 100 KB) for every header, a large part of decoding a small file.
ZSTD_DCtx& decompression_context() {
    struct Free {
        void operator()(ZSTD_DCtx* c) const { ZSTD_freeDCtx(c); }
    };
    thread_local const std::unique_ptr<ZSTD_DCtx, Free> context(ZSTD_createDCtx());
    if (!context) throw std::bad_alloc();
    return *context;
}
}  // namespace

std::string zstd_pack(std::string_view raw) {
    std::string packed(ZSTD_compressBound(raw.size()), '\0');
    const std::size_t size = ZSTD_compress(packed.data(), packed.size(), raw.data(), raw.size(), 19);
    if (ZSTD_isError(size)) throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(size));
    packed.resize(size);
    return packed;
}

std::string zstd_unpack(std::string_view packed, std::uint64_t expected, const ByteReader& r, const std::string& block) {
    const unsigned long long declared = ZSTD_getFrameContentSize(packed.data(), packed.size());
    if (declared != expected) r.fail(block + " is malformed or does not match its counts");
    ZSTD_DCtx& context = decompression_context();
    ZSTD_DCtx_reset(&context, ZSTD_reset_session_only);
    ZSTD_inBuffer in{packed.data(), packed.size(), 0};
    std::string raw;
    constexpr std::size_t kFirstChunk = 64 * 1024;
    for (;;) {
        const std::size_t have = raw.size();
        // Room for one more byte than expected, so that a frame holding more is caught.
        const std::size_t room = static_cast<std::size_t>(
            std::min<std::uint64_t>(expected + 1 - have, std::max(have, kFirstChunk)));
        raw.resize(have + room);
        ZSTD_outBuffer out{raw.data() + have, room, 0};
        const std::size_t left = ZSTD_decompressStream(&context, &out, &in);
        raw.resize(have + out.pos);
        if (ZSTD_isError(left)) r.fail(block + " is corrupt");
        if (raw.size() > expected) r.fail(block + " holds more than its counts say");
        if (left == 0) break;
        if (out.pos == 0 && in.pos == in.size) r.fail(block + " is truncated");
    }
    if (raw.size() != expected || in.pos != in.size) r.fail(block + " does not match its counts");
    return raw;
}

}  // namespace foldcast::codec
