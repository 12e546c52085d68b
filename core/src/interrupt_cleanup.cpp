#include "foldcast/core/interrupt_cleanup.hpp"

#include <unistd.h>

#include <array>
#include <atomic>
#include <csignal>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>

namespace foldcast {
namespace {

// Everything the handler touches is a lock-free atomic or a fixed buffer, so it stays
// async-signal-safe: no allocation, no locks, only unlink(), sigaction() and raise().
enum SlotState : int { kFree, kWriting, kLive, kClaimed };
constexpr std::size_t kMaxPathBytes = 4096;

struct Slot {
    std::atomic<int> state{kFree};
    char path[kMaxPathBytes];
};
std::array<Slot, InterruptCleanup::kMaxLiveTemporaries> g_slots;
std::atomic<int> g_pending_signal{0};  // the first interrupt that arrived, 0 if none
std::atomic<int> g_deferrals{0};       // live InterruptDeferral objects
static_assert(std::atomic<int>::is_always_lock_free);

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

void remove_live_temporaries() {
    for (Slot& slot : g_slots) {
        int live = kLive;
        // Claimed slots are never reused, so the path cannot change under the unlink.
        if (slot.state.compare_exchange_strong(live, kClaimed)) ::unlink(slot.path);
    }
}

[[noreturn]] void die_of(int sig) {
    remove_live_temporaries();
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    ::sigaction(sig, &dfl, nullptr);
    sigset_t only;
    sigemptyset(&only);
    sigaddset(&only, sig);
    ::pthread_sigmask(SIG_UNBLOCK, &only, nullptr);  // inside the handler it is blocked
    ::raise(sig);
    ::_exit(128 + sig);  // not reached: the default action of these signals ends the process
}

void on_interrupt(int sig) {
    int none = 0;
    g_pending_signal.compare_exchange_strong(none, sig);
    if (g_deferrals.load() > 0) return;  // the last InterruptDeferral re-delivers it
    die_of(g_pending_signal.load());
}

void install_handlers_once() {
    static std::once_flag once;
    std::call_once(once, [] {
        for (int sig : kSignals) {
            struct sigaction old {};
            if (::sigaction(sig, nullptr, &old) != 0) continue;
            // Keep an ignored signal ignored (nohup) and a handler the host program installed.
            if ((old.sa_flags & SA_SIGINFO) != 0 || old.sa_handler != SIG_DFL) continue;
            struct sigaction ours {};
            ours.sa_handler = on_interrupt;
            ours.sa_flags = SA_RESTART;  // a deferred signal must not make a write fail with EINTR
            sigemptyset(&ours.sa_mask);
            for (int s : kSignals) sigaddset(&ours.sa_mask, s);
            ::sigaction(sig, &ours, nullptr);
        }
    });
}

}  // namespace

InterruptCleanup::InterruptCleanup(const std::filesystem::path& path) {
    install_handlers_once();
    const std::string& text = path.native();
    if (text.size() >= kMaxPathBytes)
        throw std::runtime_error("temporary path too long to register for cleanup: " + text);
    for (slot_ = 0; slot_ < g_slots.size(); ++slot_) {
        int expected = kFree;
        if (g_slots[slot_].state.compare_exchange_strong(expected, kWriting)) {
            std::memcpy(g_slots[slot_].path, text.c_str(), text.size() + 1);
            g_slots[slot_].state.store(kLive);
            return;
        }
    }
    throw std::runtime_error("more than " + std::to_string(kMaxLiveTemporaries) + " output files open at once");
}

InterruptCleanup::~InterruptCleanup() { release(); }

void InterruptCleanup::created() const {
    if (const int sig = g_pending_signal.load(); sig != 0) {
        ::unlink(g_slots[slot_].path);
        die_of(sig);
    }
}

void InterruptCleanup::release() {
    if (!live_) return;
    live_ = false;
    int live = kLive;
    g_slots[slot_].state.compare_exchange_strong(live, kFree);  // fails only while the handler ends the process
}

InterruptDeferral::InterruptDeferral() {
    install_handlers_once();  // without our handler the signal would not wait
    g_deferrals.fetch_add(1);
    if (const int sig = g_pending_signal.load(); sig != 0) die_of(sig);
}

InterruptDeferral::~InterruptDeferral() {
    if (g_deferrals.fetch_sub(1) == 1)
        if (const int sig = g_pending_signal.load(); sig != 0) die_of(sig);
}

}  // namespace foldcast
