// libFuzzer target for the .fca decoder: any bytes must either decode or raise InputError.
// Anything else (a crash, a sanitizer report, another exception, a huge allocation, a hang)
// is a bug.  The first byte picks where the input is split into two feeds, so the
// incremental path (partial packets waiting for more bytes) is exercised as well.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "foldcast/codec/codec.hpp"
#include "foldcast/core/error.hpp"
#include "materialise.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const std::string_view bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
    const std::size_t split = bytes.empty() ? 0 : data[0] % (bytes.size() + 1);
    try {
        foldcast::codec::StreamingDecoder decoder("fuzz input", bytes.size());
        decoder.feed(bytes.substr(0, split));
        decoder.feed(bytes.substr(split));
        if (decoder.status().header_ready) foldcast::codec::fuzz::materialise(decoder);
    } catch (const foldcast::InputError&) {
    }
    return 0;
}
