#pragma once
// Outputs are written to temporary files beside their targets and renamed into place, so an
// interrupted or failed run never leaves a half-written file under a final name, and a
// command that writes several files replaces all of them or none (OutputTransaction).
// Temporaries are removed when a write fails and when SIGINT, SIGTERM or SIGHUP arrives
// (interrupt_cleanup.hpp); an interrupt during a commit waits until every rename is done.
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <string_view>
#include <vector>

namespace foldcast {

class InterruptCleanup;

// Several outputs replaced together.  stage() each one, write it, then commit(): the files
// are renamed into place one after another with interrupts held back, so a SIGINT or SIGTERM
// leaves either every old file or every new one.  Destroyed without commit(), it removes its
// temporaries and leaves the targets as they were.
class OutputTransaction {
public:
    OutputTransaction();
    ~OutputTransaction();
    OutputTransaction(const OutputTransaction&) = delete;
    OutputTransaction& operator=(const OutputTransaction&) = delete;

    // A stream for `path`'s new contents.  Throws InputError naming `path` if it cannot be
    // created there (missing directory, no permission, a directory) or was already staged.
    std::ofstream& stage(const std::filesystem::path& path);
    // For writers that need a file name (video writers, ...): a registered temporary path
    // beside `path` with the same extension, for the caller to create.
    std::filesystem::path stage_file(const std::filesystem::path& path);
    // Where a staged target's new contents are until commit() (to read them back); empty if
    // `path` was not staged.
    std::filesystem::path staged(const std::filesystem::path& path);
    // A file that the new set replaces without a new version (an earlier, longer run's
    // extra frames): removed by commit() right after the renames, with interrupts still held
    // back, so that no interrupt leaves it beside the new files.
    void remove_on_commit(const std::filesystem::path& path);
    // Flushes and checks every stream, then renames every file into place.
    void commit();

private:
    struct Entry;
    Entry& add(const std::filesystem::path& path, bool keep_extension);
    std::vector<std::filesystem::path> keep_old_targets() const;
    void restore_old_targets(const std::vector<std::filesystem::path>& backups, std::size_t renamed) const;
    std::vector<std::unique_ptr<Entry>> entries_;
    std::vector<std::filesystem::path> removals_;
    std::mutex mutex_;
    bool committed_ = false;
};

// One output: an OutputTransaction of one file.
class AtomicFile {
public:
    // Throws InputError naming `path` if it cannot be created (missing directory, no permission).
    explicit AtomicFile(std::filesystem::path path);
    std::ofstream& stream() { return stream_; }
    // Flushes, checks for write errors and renames over the target.
    void commit() { transaction_.commit(); }

private:
    OutputTransaction transaction_;
    std::ofstream& stream_;
};

void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

// Throws InputError unless `path` could be created: its directory exists and is writable
// and it is not itself a directory.  For checking outputs before long work starts.
void check_writable(const std::filesystem::path& path);

// Throws InputError when the output `output` is the same file as the input `input` (a command
// must not replace what it reads): "<flag> 'OUT' is the input 'IN'".  Nothing if either is missing.
void check_not_input(const std::filesystem::path& output, const std::filesystem::path& input, std::string_view flag);

}  // namespace foldcast
