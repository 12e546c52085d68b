#pragma once
// The limits on a request's head (request line and headers) that docs/player.md promises,
// checked on the bytes as they arrive, before cpp-httplib parses (and stores) any of them.
#include <cstddef>
#include <string_view>

namespace foldcast::serve {

inline constexpr std::size_t kMaxRequestLineBytes = 8 * 1024;  // 414 beyond
inline constexpr std::size_t kMaxHeaderLines = 64;             // 431 beyond
inline constexpr std::size_t kMaxHeaderBytes = 16 * 1024;      // 431 beyond
// The most a complete head can hold: request line, headers, and the CRLFs around them.
inline constexpr std::size_t kMaxHeadBytes = kMaxRequestLineBytes + kMaxHeaderBytes + 4;

enum class HeadStatus { incomplete, complete, uri_too_long, headers_too_large };

// Looks at the first bytes of a connection's next request; `head_bytes` is set to the
// head's length when it is complete.
inline HeadStatus inspect_head(std::string_view bytes, std::size_t& head_bytes) {
    const std::size_t start = 0;
    const std::size_t line_end = bytes.find("\r\n", start);
    if (line_end == std::string_view::npos)
        return bytes.size() - start > kMaxRequestLineBytes ? HeadStatus::uri_too_long : HeadStatus::incomplete;
    if (line_end - start > kMaxRequestLineBytes) return HeadStatus::uri_too_long;
    std::size_t lines = 0, at = line_end + 2;
    for (;;) {
        const std::size_t end = bytes.find("\r\n", at);
        const std::size_t header_bytes = (end == std::string_view::npos ? bytes.size() : end) - (line_end + 2);
        if (header_bytes > kMaxHeaderBytes) return HeadStatus::headers_too_large;
        if (end == std::string_view::npos) return HeadStatus::incomplete;
        if (end == at) {  // the empty line that ends the head
            head_bytes = end + 2;
            return HeadStatus::complete;
        }
        if (++lines > kMaxHeaderLines) return HeadStatus::headers_too_large;
        at = end + 2;
    }
}

}  // namespace foldcast::serve
