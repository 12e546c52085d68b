#include <filesystem>
#include <system_error>

#include "foldcast/serve/serve.hpp"

namespace foldcast::serve {

std::optional<std::filesystem::path> resolve_inside(const std::filesystem::path& root, std::string_view url_path) {
    namespace fs = std::filesystem;
    // Lexical checks first: whatever the file system says, these never name a file below root.
    if (url_path.empty() || url_path.front() == '/') return std::nullopt;
    if (url_path.find('\0') != std::string_view::npos || url_path.find('\\') != std::string_view::npos)
        return std::nullopt;
    fs::path relative;
    std::size_t start = 0;
    while (start <= url_path.size()) {
        const std::size_t slash = std::min(url_path.find('/', start), url_path.size());
        const std::string_view part = url_path.substr(start, slash - start);
        if (part.empty() || part == "." || part == "..") return std::nullopt;
        relative /= std::string(part);
        start = slash + 1;
    }
    // Then the file system: symlinks resolved, the result must still lie below root.
    std::error_code ec;
    const fs::path base = fs::canonical(root, ec);
    if (ec) return std::nullopt;
    const fs::path target = fs::canonical(base / relative, ec);
    if (ec) return std::nullopt;
    auto b = base.begin();
    auto t = target.begin();
    for (; b != base.end(); ++b, ++t)
        if (t == target.end() || *t != *b) return std::nullopt;
    if (t == target.end()) return std::nullopt;  // root itself
    if (!fs::is_regular_file(target, ec)) return std::nullopt;
    return target;
}

}  // namespace foldcast::serve
