#include "foldcast/core/atomic_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "foldcast/core/error.hpp"
#include "foldcast/core/interrupt_cleanup.hpp"

namespace foldcast {
namespace fs = std::filesystem;

namespace {
// NAME.tmp-PID-N: unique per process and per output, so concurrent runs never share one.
// With keep_extension, NAME.tmp-PID-N.EXT for writers that choose a format by extension.
fs::path temporary_beside(const fs::path& path, bool keep_extension) {
    static std::atomic<unsigned> counter{0};
    fs::path temp = path;
    temp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    if (keep_extension) temp += path.extension();
    return temp;
}
}  // namespace

struct OutputTransaction::Entry {
    fs::path target, temp;
    std::unique_ptr<InterruptCleanup> cleanup;  // registered before the file exists
    std::ofstream out;
    bool is_stream = false;
};

OutputTransaction::OutputTransaction() = default;

OutputTransaction::~OutputTransaction() {
    if (committed_) return;
    for (auto& e : entries_) {
        e->out.close();
        std::error_code ignored;
        fs::remove(e->temp, ignored);
        e->cleanup->release();
    }
}

OutputTransaction::Entry& OutputTransaction::add(const fs::path& path, bool keep_extension) {
    check_writable(path);
    const std::lock_guard lock(mutex_);
    if (committed_) throw std::logic_error("OutputTransaction: stage() after commit()");
    for (const auto& e : entries_)
        if (e->target == path) throw InputError("cannot write '" + path.string() + "' twice in one command");
    auto entry = std::make_unique<Entry>();
    entry->target = path;
    entry->temp = temporary_beside(path, keep_extension);
    entry->cleanup = std::make_unique<InterruptCleanup>(entry->temp);
    entries_.push_back(std::move(entry));
    return *entries_.back();
}

std::ofstream& OutputTransaction::stage(const fs::path& path) {
    Entry& e = add(path, false);
    e.is_stream = true;
    e.out.open(e.temp, std::ios::binary | std::ios::trunc);
    e.cleanup->created();
    if (!e.out) throw InputError("cannot write '" + path.string() + "': cannot create a file there");
    return e.out;
}

fs::path OutputTransaction::stage_file(const fs::path& path) { return add(path, true).temp; }

fs::path OutputTransaction::staged(const fs::path& path) {
    const std::lock_guard lock(mutex_);
    for (const auto& e : entries_)
        if (e->target == path) {
            if (e->is_stream) e->out.flush();  // readable by name from here on
            return e->temp;
        }
    return {};
}

void OutputTransaction::remove_on_commit(const fs::path& path) {
    const std::lock_guard lock(mutex_);
    if (committed_) throw std::logic_error("OutputTransaction: remove_on_commit() after commit()");
    removals_.push_back(path);
}

void OutputTransaction::commit() {
    const std::lock_guard lock(mutex_);
    for (auto& e : entries_) {
        if (!e->is_stream) {
            std::error_code ec;
            if (!fs::is_regular_file(e->temp, ec))
                throw std::runtime_error("writing '" + e->target.string() + "' failed: nothing was written");
            e->cleanup->created();
            continue;
        }
        e->out.flush();
        const bool ok = static_cast<bool>(e->out);
        e->out.close();
        if (!ok || e->out.fail()) throw std::runtime_error("writing '" + e->target.string() + "' failed (disk full?)");
    }
    // Every file or none: an interrupt from here on waits for the last rename, and a rename
    // that fails (an immutable or vanished target) puts back the files renamed before it.
    const InterruptDeferral hold;
    const std::vector<fs::path> backups = keep_old_targets();
    for (std::size_t i = 0; i < entries_.size(); ++i) {
        std::error_code ec;
        fs::rename(entries_[i]->temp, entries_[i]->target, ec);
        if (ec) {
            restore_old_targets(backups, i);
            throw std::runtime_error("cannot rename into '" + entries_[i]->target.string() + "': " + ec.message() +
                                     (i > 0 ? " (the files renamed before it were put back)" : ""));
        }
    }
    std::error_code ignored;
    for (const fs::path& backup : backups)
        if (!backup.empty()) fs::remove(backup, ignored);
    for (const fs::path& gone : removals_) fs::remove(gone, ignored);
    for (auto& e : entries_) e->cleanup->release();
    committed_ = true;
}

// A hard link to each target that exists, beside it: the old file, for restore_old_targets.
// With a single output there is nothing to put back.
std::vector<fs::path> OutputTransaction::keep_old_targets() const {
    std::vector<fs::path> backups(entries_.size());
    if (entries_.size() < 2) return backups;
    for (std::size_t i = 0; i < entries_.size(); ++i) {
        std::error_code ec;
        if (!fs::exists(entries_[i]->target, ec)) continue;
        backups[i] = temporary_beside(entries_[i]->target, false);
        fs::create_hard_link(entries_[i]->target, backups[i], ec);
        if (ec) {
            std::error_code ignored;
            for (std::size_t j = 0; j < i; ++j)
                if (!backups[j].empty()) fs::remove(backups[j], ignored);
            throw std::runtime_error("cannot replace '" + entries_[i]->target.string() + "': " + ec.message());
        }
    }
    return backups;
}

// Undoes the first `renamed` renames: the old file back where there was one, else none.
void OutputTransaction::restore_old_targets(const std::vector<fs::path>& backups, std::size_t renamed) const {
    std::error_code ignored;
    for (std::size_t j = 0; j < backups.size(); ++j) {
        if (j < renamed) {
            if (backups[j].empty())
                fs::remove(entries_[j]->target, ignored);
            else
                fs::rename(backups[j], entries_[j]->target, ignored);
        } else if (!backups[j].empty()) {
            fs::remove(backups[j], ignored);
        }
    }
}

AtomicFile::AtomicFile(fs::path path) : stream_(transaction_.stage(path)) {}

void write_file_atomically(const fs::path& path, std::string_view bytes) {
    AtomicFile file(path);
    file.stream().write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    file.commit();
}

void check_writable(const fs::path& path) {
    if (path.empty()) throw InputError("output path is empty");
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw InputError("cannot write '" + path.string() + "': it is a directory");
    const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
    if (!fs::is_directory(dir, ec))
        throw InputError("cannot write '" + path.string() + "': directory '" + dir.string() + "' does not exist");
    if (::access(dir.c_str(), W_OK) != 0)
        throw InputError("cannot write '" + path.string() + "': directory '" + dir.string() + "' is not writable");
}

void check_not_input(const fs::path& output, const fs::path& input, std::string_view flag) {
    std::error_code ec;
    if (fs::exists(output, ec) && fs::exists(input, ec) && fs::equivalent(output, input, ec))
        throw InputError(std::string(flag) + " '" + output.string() + "' is the input '" + input.string() +
                         "': choose another output file");
}

}  // namespace foldcast
