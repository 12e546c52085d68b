#pragma once
// cpp-httplib's Stream over a connected socket whose first bytes were already read (by the
// gate): reads return those bytes first, then what the socket has, never more than asked
// for, so what is left of the buffer after a request is the start of the next one.
//
// Writes wait for the client within a budget per response (start_response()): a client that
// takes its bytes slowly (a few every few seconds keeps each wait under the write timeout)
// would otherwise hold a worker for as long as the file lasts.  The time a response's writes
// spend waiting for the client may reach kClientWaitGrace plus one second per
// kMinClientBytesPerSecond the client has taken; past it the write fails and the connection
// is closed.
// Time spent waiting for the --throttle-kbps link is the server's own and does not count.
#include <httplib.h>
#include <linux/sockios.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <string>

namespace foldcast::serve {

class FdStream final : public httplib::Stream {
public:
    FdStream(int fd, std::string buffered, std::chrono::milliseconds read_timeout, std::chrono::milliseconds write_timeout)
        : fd_(fd), buffered_(std::move(buffered)), read_timeout_(read_timeout), write_timeout_(write_timeout) {}

    static constexpr std::chrono::milliseconds kClientWaitGrace{10000};
    static constexpr double kMinClientBytesPerSecond = 16 * 1024;  // 128 kbit/s on average

    bool is_readable() const override { return at_ < buffered_.size() || wait(POLLIN, read_timeout_); }
    bool is_writable() const override { return wait_for_client(); }
    ssize_t read(char* ptr, size_t size) override {
        if (at_ < buffered_.size()) {
            const std::size_t n = std::min(size, buffered_.size() - at_);
            buffered_.copy(ptr, n, at_);
            at_ += n;
            return static_cast<ssize_t>(n);
        }
        if (!wait(POLLIN, read_timeout_)) return -1;
        return ::recv(fd_, ptr, size, 0);
    }
    // Non-blocking: a blocking send() would wait, unbounded, for a slow client to make room
    // for all of `size`; cpp-httplib calls again for the rest.
    ssize_t write(const char* ptr, size_t size) override {
        if (!wait_for_client()) return -1;
        const ssize_t n = ::send(fd_, ptr, size, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return 0;
        if (n > 0) written_ += static_cast<std::size_t>(n);
        return n;
    }
    // A new response: its own budget for waiting on the client.
    void start_response() {
        waited_ = {};
        written_ = 0;
    }
    void get_remote_ip_and_port(std::string& ip, int& port) const override { address(::getpeername, ip, port); }
    void get_local_ip_and_port(std::string& ip, int& port) const override { address(::getsockname, ip, port); }
    socket_t socket() const override { return fd_; }

    // The bytes read from the socket but not by a request (the next request's start).
    std::string take_unread() {
        std::string rest = buffered_.substr(at_);
        buffered_.clear();
        at_ = 0;
        return rest;
    }
    void put_back(std::string bytes) {
        buffered_ = std::move(bytes);
        at_ = 0;
    }

private:
    // The bytes the client has taken: those handed to the socket less those still queued in
    // it (a send buffer of megabytes would otherwise count as taken the moment it fills).
    std::size_t taken() const {
        int queued = 0;
        if (::ioctl(fd_, SIOCOUTQ, &queued) != 0 || queued < 0) queued = 0;
        return written_ - std::min(written_, static_cast<std::size_t>(queued));
    }
    std::chrono::steady_clock::duration client_wait_budget() const {
        const std::chrono::duration<double> earned(double(taken()) / kMinClientBytesPerSecond);
        return kClientWaitGrace + std::chrono::duration_cast<std::chrono::steady_clock::duration>(earned) - waited_;
    }
    // Until the socket takes bytes, within the write timeout and what is left of the budget.
    bool wait_for_client() const {
        const auto left = client_wait_budget();
        if (left <= std::chrono::steady_clock::duration::zero()) return false;
        const auto start = std::chrono::steady_clock::now();
        const auto left_ms = std::chrono::ceil<std::chrono::milliseconds>(left);
        const bool ready = wait(POLLOUT, std::min(write_timeout_, left_ms));
        waited_ += std::chrono::steady_clock::now() - start;
        return ready;
    }
    bool wait(short events, std::chrono::milliseconds timeout) const {
        pollfd p{fd_, events, 0};
        return ::poll(&p, 1, static_cast<int>(timeout.count())) > 0 && (p.revents & events) != 0;
    }
    template <typename Query>
    void address(Query query, std::string& ip, int& port) const {
        sockaddr_storage addr{};
        socklen_t length = sizeof addr;
        ip.clear();
        port = 0;
        if (query(fd_, reinterpret_cast<sockaddr*>(&addr), &length) != 0) return;
        char host[NI_MAXHOST], service[NI_MAXSERV];
        if (::getnameinfo(reinterpret_cast<sockaddr*>(&addr), length, host, sizeof host, service, sizeof service,
                          NI_NUMERICHOST | NI_NUMERICSERV) == 0) {
            ip = host;
            port = std::atoi(service);
        }
    }

    int fd_;
    std::string buffered_;
    std::size_t at_ = 0;
    std::chrono::milliseconds read_timeout_, write_timeout_;
    // This response's bytes handed to the socket, and the time spent waiting for the client.
    std::size_t written_ = 0;
    mutable std::chrono::steady_clock::duration waited_{};
};

}  // namespace foldcast::serve
