#pragma once
// A simulated network link: every response body shares it, so N clients at K kbit/s each
// get K/N, as they would behind one slow connection.  Senders reserve a slot in the link's
// timeline and sleep until it ends; stop() wakes them all.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <mutex>

namespace foldcast::serve {

class Link {
public:
    explicit Link(double kbps) : bytes_per_s_(kbps * 1000.0 / 8.0) {}
    // Waits until `bytes` more can have crossed the link; false once stopped.
    bool send(std::size_t bytes) {
        using clock = std::chrono::steady_clock;
        std::unique_lock lock(mutex_);
        const auto now = clock::now();
        // An idle link starts again now; a sender that was scheduled late (a loaded machine)
        // may catch up on at most kCatchUp of missed time, as a real link's buffers allow.
        if (next_free_ < now - kCatchUp) next_free_ = now - kCatchUp;
        next_free_ +=
            std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(double(bytes) / bytes_per_s_));
        const auto until = next_free_;
        return !woken_.wait_until(lock, until, [&] { return stopped_; });
    }
    void stop() {
        {
            std::lock_guard lock(mutex_);
            stopped_ = true;
        }
        woken_.notify_all();
    }

private:
    static constexpr std::chrono::milliseconds kCatchUp{50};
    double bytes_per_s_;
    std::mutex mutex_;
    std::condition_variable woken_;
    std::chrono::steady_clock::time_point next_free_{};
    bool stopped_ = false;
};

}  // namespace foldcast::serve
