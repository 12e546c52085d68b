// libFuzzer target for the paper profile's packet decoder.  fuzz_fca_decode must first get a
// header and CRCs right by chance; here the target builds a valid container around the
// input (paper_container.hpp) so that every execution reaches the profile.  Any result but
// a decode or an InputError (a crash, a sanitizer report, another exception, a huge
// allocation, a hang) is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "foldcast/codec/codec.hpp"
#include "foldcast/core/error.hpp"
#include "materialise.hpp"
#include "paper_container.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 3) return 0;
    const std::string file = foldcast::codec::fuzz::paper_container(data, size);
    try {
        foldcast::codec::StreamingDecoder decoder("fuzz input", file.size());
        decoder.feed(file);
        if (decoder.status().header_ready) foldcast::codec::fuzz::materialise(decoder);
    } catch (const foldcast::InputError&) {
    }
    return 0;
}
