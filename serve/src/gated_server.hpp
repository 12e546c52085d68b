#pragma once
// cpp-httplib's server with the request gate in front of it: an accepted connection goes to
// the gate, which hands it to a worker once a whole request head has arrived within the
// limits; the worker serves that request and the ones after it that have arrived too, then
// gives the connection back to the gate to wait for more.  cpp-httplib alone lets a worker
// wait on a client line by line (5 s each, without end) and stores any number of header
// lines, so a few slow or flooding clients could take every worker or all memory.
#include <httplib.h>
#include <sys/socket.h>
#include <unistd.h>

#include <functional>
#include <memory>

#include "fd_stream.hpp"
#include "request_gate.hpp"
#include "request_head.hpp"

namespace foldcast::serve {
namespace detail {
// cpp-httplib (0.11) serves a request read from a Stream in a private member, and has no
// public way to serve a connection whose first bytes were read elsewhere.  An explicit
// instantiation may name a private member ([temp.spec.general]): that is how the worker
// reaches it; the compiler checks the signature against the installed header.
using ProcessRequest = bool (httplib::Server::*)(httplib::Stream&, bool, bool&,
                                                 const std::function<void(httplib::Request&)>&);
struct ProcessRequestKey {
    friend ProcessRequest member(ProcessRequestKey);
};
template <ProcessRequest Member>
struct Expose {
    friend ProcessRequest member(ProcessRequestKey) { return Member; }
};
template struct Expose<&httplib::Server::process_request>;
}  // namespace detail

class GatedServer final : public httplib::Server {
public:
    // `enqueue` runs a job on the server's workers (its task queue).
    explicit GatedServer(GateLimits limits)
        : gate_([this](int fd, std::string bytes) { enqueue_([this, fd, b = std::move(bytes)]() mutable {
                      serve_connection(fd, std::move(b));
                  }); },
                limits) {}
    ~GatedServer() override { gate_.stop(); }

    void set_enqueue(std::function<void(std::function<void()>)> enqueue) { enqueue_ = std::move(enqueue); }
    void stop_gate() { gate_.stop(); }

private:
    bool process_and_close_socket(socket_t sock) override {
        gate_.hold(sock, {}, false);
        return true;
    }

    void serve_connection(int fd, std::string bytes) {
        FdStream stream(fd, std::move(bytes), std::chrono::milliseconds(5000), std::chrono::milliseconds(10000));
        for (std::size_t served = 1;; ++served) {
            const bool last = served >= kRequestsPerConnection || !is_running();
            bool client_closes = false;
            stream.start_response();
            const bool ok = (this->*member(detail::ProcessRequestKey{}))(stream, last, client_closes, nullptr);
            if (!ok || client_closes || last) break;
            std::string rest = stream.take_unread();
            std::size_t head_bytes = 0;
            if (inspect_head(rest, head_bytes) != HeadStatus::complete) {
                gate_.hold(fd, std::move(rest), true);  // the gate owns the connection now
                return;
            }
            stream.put_back(std::move(rest));
        }
        ::shutdown(fd, SHUT_RDWR);
        ::close(fd);
    }

    static constexpr std::size_t kRequestsPerConnection = 100;
    std::function<void(std::function<void()>)> enqueue_;
    RequestGate gate_;
};

}  // namespace foldcast::serve
