#pragma once
// Outputs are written to a temporary file beside the target and renamed into place, so an
// interrupted or failed run never leaves a half-written file under the final name.
#include <filesystem>
#include <fstream>
#include <string_view>

namespace foldcast {

class AtomicFile {
public:
    // Opens a temporary file in the target's directory; throws InputError naming `path`
    // if it cannot be created (missing directory, no permission).
    explicit AtomicFile(std::filesystem::path path);
    ~AtomicFile();  // removes the temporary file unless commit() succeeded
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    std::ofstream& stream() { return out_; }
    // Flushes, checks for write errors and renames over the target.
    void commit();

private:
    std::filesystem::path path_;
    std::filesystem::path temp_;
    std::ofstream out_;
    bool committed_ = false;
};

void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

// Throws InputError unless `path` could be created: its directory exists and is writable
// and it is not itself a directory.  For checking outputs before long work starts.
void check_writable(const std::filesystem::path& path);

}  // namespace foldcast
