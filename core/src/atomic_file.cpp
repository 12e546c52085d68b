#include "foldcast/core/atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <string>
#include <system_error>

#include "foldcast/core/error.hpp"

namespace foldcast {
namespace fs = std::filesystem;

namespace {
fs::path temporary_beside(const fs::path& path) {
    static std::atomic<unsigned> counter{0};
    fs::path temp = path;
    temp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    return temp;
}
}  // namespace

AtomicFile::AtomicFile(fs::path path) : path_(std::move(path)), temp_(temporary_beside(path_)) {
    check_writable(path_);
    out_.open(temp_, std::ios::binary | std::ios::trunc);
    if (!out_) throw InputError("cannot write '" + path_.string() + "': cannot create a file there");
}

AtomicFile::~AtomicFile() {
    if (committed_) return;
    out_.close();
    std::error_code ignored;
    fs::remove(temp_, ignored);
}

void AtomicFile::commit() {
    out_.flush();
    const bool ok = static_cast<bool>(out_);
    out_.close();
    if (!ok || out_.fail()) throw std::runtime_error("writing '" + path_.string() + "' failed (disk full?)");
    std::error_code ec;
    fs::rename(temp_, path_, ec);
    if (ec) throw std::runtime_error("cannot rename into '" + path_.string() + "': " + ec.message());
    committed_ = true;
}

void write_file_atomically(const fs::path& path, std::string_view bytes) {
    AtomicFile file(path);
    file.stream().write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    file.commit();
}

void check_writable(const fs::path& path) {
    if (path.empty()) throw InputError("output path is empty");
    std::error_code ec;
    if (fs::is_directory(path, ec))
        throw InputError("cannot write '" + path.string() + "': it is a directory");
    const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
    if (!fs::is_directory(dir, ec))
        throw InputError("cannot write '" + path.string() + "': directory '" + dir.string() +
                         "' does not exist");
    if (::access(dir.c_str(), W_OK) != 0)
        throw InputError("cannot write '" + path.string() + "': directory '" + dir.string() +
                         "' is not writable");
}

}  // namespace foldcast
