#pragma once
// cpp-httplib's Stream over a connected socket whose first bytes were already read (by the
// gate): reads return those bytes first, then what the socket has, never more than asked
// for, so what is left of the buffer after a request is the start of the next one.
#include <httplib.h>
#include <poll.h>
#include <sys/socket.h>

#include <chrono>
#include <string>

namespace foldcast::serve {

class FdStream final : public httplib::Stream {
public:
    FdStream(int fd, std::string buffered, std::chrono::milliseconds read_timeout, std::chrono::milliseconds write_timeout)
        : fd_(fd), buffered_(std::move(buffered)), read_timeout_(read_timeout), write_timeout_(write_timeout) {}

    bool is_readable() const override { return at_ < buffered_.size() || wait(POLLIN, read_timeout_); }
    bool is_writable() const override { return wait(POLLOUT, write_timeout_); }
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
    ssize_t write(const char* ptr, size_t size) override {
        if (!is_writable()) return -1;
        return ::send(fd_, ptr, size, MSG_NOSIGNAL);
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
};

}  // namespace foldcast::serve
