#include "request_gate.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <system_error>

#include "request_head.hpp"

namespace foldcast::serve {
namespace {
using Clock = std::chrono::steady_clock;

// A status line and a short body, then the connection is closed: the client sent too much
// or too little to be parsed, so nothing else it sent is read.
void answer_and_close(int fd, int status, const char* reason) {
    const std::string body = std::to_string(status) + "\n";
    const std::string reply = "HTTP/1.1 " + std::to_string(status) + " " + reason + "\r\nContent-Type: text/plain\r\n" +
                              "Content-Length: " + std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body;
    (void)::send(fd, reply.data(), reply.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    ::shutdown(fd, SHUT_WR);
    ::close(fd);
}
}  // namespace

RequestGate::RequestGate(Ready ready, GateLimits limits) : ready_(std::move(ready)), limits_(limits) {
    if (::pipe2(wake_, O_CLOEXEC | O_NONBLOCK) != 0) throw std::system_error(errno, std::generic_category(), "pipe");
    // The thread starts with every signal blocked (it inherits the mask): signals are for
    // the thread that waits for them (run_until_signal), whenever the gate was made.
    sigset_t all, previous;
    sigfillset(&all);
    pthread_sigmask(SIG_BLOCK, &all, &previous);
    thread_ = std::thread([this] { run(); });
    pthread_sigmask(SIG_SETMASK, &previous, nullptr);
}

RequestGate::~RequestGate() {
    stop();
    ::close(wake_[0]);
    ::close(wake_[1]);
}

void RequestGate::hold(int fd, std::string bytes, bool kept_alive) {
    const auto now = Clock::now();
    {
        std::lock_guard lock(mutex_);
        if (!stopping_) {
            incoming_.push_back({fd, std::move(bytes), now + (kept_alive ? limits_.idle_deadline : limits_.head_deadline), now});
            fd = -1;
        }
    }
    if (fd >= 0) {
        ::close(fd);
        return;
    }
    const char byte = 1;
    (void)!::write(wake_[1], &byte, 1);  // a full pipe already wakes the thread
}

void RequestGate::stop() {
    {
        std::lock_guard lock(mutex_);
        if (stopping_) return;
        stopping_ = true;
    }
    const char byte = 1;
    (void)!::write(wake_[1], &byte, 1);
    if (thread_.joinable()) thread_.join();
}

bool RequestGate::read_more(Held& c) {
    char chunk[4096];
    const std::size_t room = std::min(sizeof chunk, kMaxHeadBytes + 1 - std::min(c.bytes.size(), kMaxHeadBytes));
    const ssize_t got = ::recv(c.fd, chunk, room, MSG_DONTWAIT);
    if (got < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return true;
    if (got <= 0) {  // closed by the client, or reset
        ::close(c.fd);
        return false;
    }
    c.bytes.append(chunk, static_cast<std::size_t>(got));
    std::size_t head_bytes = 0;
    switch (inspect_head(c.bytes, head_bytes)) {
        case HeadStatus::complete:
            ready_(c.fd, std::move(c.bytes));
            return false;
        case HeadStatus::uri_too_long:
            answer_and_close(c.fd, 414, "URI Too Long");
            return false;
        case HeadStatus::headers_too_large:
            answer_and_close(c.fd, 431, "Request Header Fields Too Large");
            return false;
        case HeadStatus::incomplete:
            return true;
    }
    return true;
}

void RequestGate::run() {
    std::vector<Held> held;
    std::vector<pollfd> polled;
    for (;;) {
        {
            std::lock_guard lock(mutex_);
            if (stopping_) break;
            for (auto& c : incoming_) held.push_back(std::move(c));
            incoming_.clear();
        }
        // Over capacity: the connections held longest go first (a slow client's, most likely).
        if (held.size() > limits_.max_held) {
            std::sort(held.begin(), held.end(), [](const Held& a, const Held& b) { return a.since < b.since; });
            const std::size_t excess = held.size() - limits_.max_held;
            for (std::size_t i = 0; i < excess; ++i) answer_and_close(held[i].fd, 503, "Service Unavailable");
            held.erase(held.begin(), held.begin() + static_cast<std::ptrdiff_t>(excess));
        }
        auto next = Clock::time_point::max();
        polled.assign(1, pollfd{wake_[0], POLLIN, 0});
        for (const auto& c : held) {
            polled.push_back(pollfd{c.fd, POLLIN, 0});
            next = std::min(next, c.deadline);
        }
        int timeout_ms = -1;
        if (next != Clock::time_point::max())
            timeout_ms = static_cast<int>(std::clamp<long long>(
                std::chrono::duration_cast<std::chrono::milliseconds>(next - Clock::now()).count() + 1, 0, 60000));
        if (::poll(polled.data(), polled.size(), timeout_ms) < 0 && errno != EINTR) break;
        if (polled[0].revents) {
            char drain[64];
            while (::read(wake_[0], drain, sizeof drain) > 0) {
            }
        }
        const auto now = Clock::now();
        std::vector<Held> kept;
        for (std::size_t i = 0; i < held.size(); ++i) {
            Held& c = held[i];
            if (polled[i + 1].revents != 0) {
                if (read_more(c)) kept.push_back(std::move(c));
            } else if (now >= c.deadline) {
                answer_and_close(c.fd, 408, "Request Timeout");
            } else {
                kept.push_back(std::move(c));
            }
        }
        held = std::move(kept);
    }
    for (auto& c : held) ::close(c.fd);
    std::lock_guard lock(mutex_);
    for (auto& c : incoming_) ::close(c.fd);
    incoming_.clear();
}

}  // namespace foldcast::serve
