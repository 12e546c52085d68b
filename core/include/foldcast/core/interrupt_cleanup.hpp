#pragma once
// Interrupts (SIGINT, SIGTERM, SIGHUP) must not leave temporary files behind nor a set of
// outputs half replaced.  Temporaries are registered while they exist; the handler (installed
// on first registration, only over the default disposition) removes every registered file and
// re-raises the signal with its default action, so the exit status still says which signal
// ended the process.  While a set of outputs is being renamed into place the signal waits
// until the last rename is done.
#include <cstddef>
#include <filesystem>

namespace foldcast {

// Registers `path` for removal on an interrupt, for as long as this object lives (or until
// release()).  Register before creating the file.  Throws std::runtime_error if more than
// kMaxLiveTemporaries are registered at once or the path is longer than the registry holds.
class InterruptCleanup {
public:
    static constexpr std::size_t kMaxLiveTemporaries = 256;

    explicit InterruptCleanup(const std::filesystem::path& path);
    ~InterruptCleanup();
    InterruptCleanup(const InterruptCleanup&) = delete;
    InterruptCleanup& operator=(const InterruptCleanup&) = delete;

    // After the file was created: if an interrupt arrived meanwhile, removes it and ends the
    // process the way the handler does (the handler may have looked before the file existed).
    void created() const;
    // The file was renamed or removed: stop tracking it.
    void release();

private:
    std::size_t slot_;
    bool live_ = true;
};

// While one lives, an interrupt is held back; the last one to go re-delivers it (after the
// cleanup).  Constructing one after an interrupt arrived ends the process at once.
class InterruptDeferral {
public:
    InterruptDeferral();
    ~InterruptDeferral();
    InterruptDeferral(const InterruptDeferral&) = delete;
    InterruptDeferral& operator=(const InterruptDeferral&) = delete;
};

}  // namespace foldcast
