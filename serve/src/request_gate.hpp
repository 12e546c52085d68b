#pragma once
// The gate in front of the workers: one thread holds every connection whose next request has
// not fully arrived, reading its head into a buffer of at most kMaxHeadBytes, and hands the
// connection to a worker only once the head is complete.  So a slow or flooding client costs
// a buffer here, never a worker: a head over its limits is answered 414 or 431, one that has
// not arrived by its deadline 408, and the connection closed.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace foldcast::serve {

struct GateLimits {
    std::chrono::milliseconds head_deadline{10000};  // a new connection's first head, whole
    std::chrono::milliseconds idle_deadline{5000};   // the next head on a kept-alive connection
    std::size_t max_held = 256;                      // beyond, the connection held longest is closed
};

class RequestGate {
public:
    // `ready(fd, bytes)`: a connection whose buffered `bytes` begin with a complete head; the
    // callee owns the socket from then on.
    using Ready = std::function<void(int fd, std::string bytes)>;
    RequestGate(Ready ready, GateLimits limits);
    ~RequestGate();
    RequestGate(const RequestGate&) = delete;
    RequestGate& operator=(const RequestGate&) = delete;

    // Takes ownership of `fd` (with `bytes` already read from it); `kept_alive` picks the
    // idle deadline instead of the first head's.  Closes it when the gate has stopped.
    void hold(int fd, std::string bytes, bool kept_alive);
    // Closes every held connection and ends the thread.
    void stop();

private:
    struct Held {
        int fd;
        std::string bytes;
        std::chrono::steady_clock::time_point deadline;
        std::chrono::steady_clock::time_point since;
    };
    void run();
    // Reads what `c` has; false when it is finished with (handed on, answered or closed).
    bool read_more(Held& c);

    Ready ready_;
    GateLimits limits_;
    std::mutex mutex_;
    std::vector<Held> incoming_;
    bool stopping_ = false;
    int wake_[2] = {-1, -1};
    std::thread thread_;
};

}  // namespace foldcast::serve
