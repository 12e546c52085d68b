#include <httplib.h>
#include <pthread.h>
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "bounded_pool.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/serve/serve.hpp"
#include "link.hpp"
#include "gated_server.hpp"

namespace foldcast::serve {
namespace {
namespace fs = std::filesystem;

constexpr std::size_t kMaxRanges = 8;
constexpr std::size_t kMaxListed = 10000;
constexpr std::size_t kChunkBytes = 16 * 1024;
constexpr std::size_t kThrottledChunkBytes = 2 * 1024;  // 8 ms at 2 Mbit/s: smooth arrival

std::string content_type(const fs::path& file) {
    const std::string ext = file.extension().string();
    if (ext == ".html") return "text/html; charset=utf-8";
    if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
    if (ext == ".wasm") return "application/wasm";  // what WebAssembly.instantiateStreaming needs
    if (ext == ".json") return "application/json";
    if (ext == ".css") return "text/css; charset=utf-8";
    if (ext == ".png") return "image/png";
    return "application/octet-stream";
}
// RFC 9110 14.1.2: a last position at or past the end means the end, a suffix longer than
// the file is the file, and a range that starts at or past the end is unsatisfiable (416
// when none is left).  cpp-httplib applies req.ranges after the handler as they are, without
// clamping (a Content-Length of the range asked for, not of the bytes sent): the handler
// writes the clamped ranges back into the Request, cpp-httplib's own non-const local.
bool satisfiable_ranges(const httplib::Request& req, std::size_t size) {
    auto& ranges = const_cast<httplib::Request&>(req).ranges;
    if (ranges.empty()) return true;
    httplib::Ranges asked;
    asked.swap(ranges);  // out of the Request, so that a 416 has none applied to its own body
    if (asked.size() > kMaxRanges) return false;
    const auto end = static_cast<ssize_t>(size);  // a file size fits: it is an off_t
    httplib::Ranges kept;
    for (auto [first, last] : asked) {
        if (first < 0) {  // "-N": the last N bytes (cpp-httplib: first -1, last N)
            if (last <= 0 || end == 0) continue;
            first = end - std::min(last, end);
            last = end - 1;
        } else {
            if (last >= 0 && last < first) return false;  // "B-A": not a range
            if (first >= end) continue;
            last = last < 0 ? end - 1 : std::min(last, end - 1);
        }
        kept.emplace_back(first, last);
    }
    if (kept.empty()) return false;
    ranges = std::move(kept);
    return true;
}

// A URL path for a file name: unreserved bytes and '/' as they are, every other byte %XX.
std::string percent_encoded(const std::string& name) {
    static constexpr char kHex[] = "0123456789ABCDEF";
    std::string out;
    for (const unsigned char c : name) {
        if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~' || c == '/') {
            out += static_cast<char>(c);
        } else {
            out += '%';
            out += kHex[c >> 4];
            out += kHex[c & 15];
        }
    }
    return out;
}
}  // namespace

struct Server::Impl {
    Options options;
    GatedServer http{GateLimits{}};
    std::unique_ptr<Link> link;
    int port = 0;

    // Streams `file` (its ranges applied by cpp-httplib) in chunks, paced by the link when
    // `throttled`.
    void send_file(const httplib::Request& req, httplib::Response& res, const fs::path& file, bool throttled) {
        std::error_code ec;
        const auto size = static_cast<std::size_t>(fs::file_size(file, ec));
        if (ec) {
            res.status = 404;
            return;
        }
        if (!satisfiable_ranges(req, size)) {
            res.status = 416;
            res.set_header("Content-Range", "bytes */" + std::to_string(size));
            return;
        }
        auto in = std::make_shared<std::ifstream>(file, std::ios::binary);
        if (!*in) {
            res.status = 404;
            return;
        }
        res.set_header("Accept-Ranges", "bytes");
        res.set_header("X-Content-Type-Options", "nosniff");
        res.set_header("Cache-Control", "no-cache");
        Link* pace = throttled ? link.get() : nullptr;
        const std::size_t chunk = pace ? kThrottledChunkBytes : kChunkBytes;
        res.set_content_provider(size, content_type(file),
                                 [in, pace, chunk](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
                                     std::string buffer(std::min(chunk, length), '\0');
                                     in->clear();
                                     in->seekg(static_cast<std::streamoff>(offset));
                                     in->read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
                                     const auto got = static_cast<std::size_t>(in->gcount());
                                     if (got == 0) return false;
                                     if (pace && !pace->send(got)) return false;
                                     return sink.write(buffer.data(), got);
                                 });
    }

    // Every readable .fca file below root: an entry that cannot be read (a symlink loop, a
    // dangling link, no permission) is left out, never the rest of the listing.
    std::string listing() const {
        nlohmann::json files = nlohmann::json::array();
        std::error_code ec;
        std::vector<std::pair<std::string, std::uintmax_t>> found;
        fs::recursive_directory_iterator it(options.root, fs::directory_options::skip_permission_denied, ec);
        for (; !ec && it != fs::recursive_directory_iterator() && found.size() < kMaxListed; it.increment(ec)) {
            if (it->path().extension() != ".fca") continue;
            std::error_code entry_ec;
            const std::string name = it->path().lexically_relative(options.root).generic_string();
            const auto inside = resolve_inside(options.root, name);  // drops symlinks that lead out, and loops
            if (!inside) continue;
            const std::uintmax_t bytes = fs::file_size(*inside, entry_ec);
            if (!entry_ec) found.emplace_back(name, bytes);
        }
        std::sort(found.begin(), found.end());
        for (const auto& [name, bytes] : found)
            files.push_back({{"name", name}, {"url", "files/" + percent_encoded(name)}, {"bytes", bytes}});
        // A name that is not UTF-8 is shown with U+FFFD; its url still names the file's bytes.
        return files.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    }

    void routes() {
        http.set_pre_routing_handler([](const httplib::Request& req, httplib::Response& res) {
            // The head's limits were enforced by the gate before cpp-httplib read it.
            // GET and HEAD carry no body; cpp-httplib would not read one, and nor do we.
            if (req.has_header("Transfer-Encoding") || std::atoll(req.get_header_value("Content-Length").c_str()) > 0) {
                res.status = 413;
                return httplib::Server::HandlerResponse::Handled;
            }
            if (req.method != "GET" && req.method != "HEAD") {
                res.status = 405;
                res.set_header("Allow", "GET, HEAD");
                return httplib::Server::HandlerResponse::Handled;
            }
            return httplib::Server::HandlerResponse::Unhandled;
        });
        http.Get("/api/files", [this](const httplib::Request&, httplib::Response& res) {
            res.set_content(listing(), "application/json");
            res.set_header("Cache-Control", "no-cache");
        });
        http.Get(R"(/files/(.+))", [this](const httplib::Request& req, httplib::Response& res) {
            const std::string name = req.matches[1];
            const auto file = fs::path(name).extension() == ".fca" ? resolve_inside(options.root, name) : std::nullopt;
            if (!file) {
                res.status = 404;
                return;
            }
            send_file(req, res, *file, true);
        });
        http.Get(R"(/(.*))", [this](const httplib::Request& req, httplib::Response& res) {
            std::string name = req.matches[1];
            if (name.empty()) name = "index.html";
            const auto file = resolve_inside(options.web_dir, name);
            if (!file) {
                res.status = 404;
                if (name == "index.html")
                    res.set_content(
                        "the player is not built (needs emscripten and web/node_modules: docs/player.md); "
                        "the files are at /api/files and /files/NAME\n",
                        "text/plain");
                return;
            }
            send_file(req, res, *file, false);  // the player's assets: cached after a first visit, not throttled
        });
        // An exception's text would go out in cpp-httplib's EXCEPTION_WHAT header: none does.
        http.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
            res.status = 500;
        });
        http.set_error_handler([](const httplib::Request&, httplib::Response& res) {
            if (res.body.empty() && res.status >= 400) res.set_content(std::to_string(res.status) + "\n", "text/plain");
        });
        if (options.log)
            http.set_logger([](const httplib::Request& req, const httplib::Response& res) {
                std::fprintf(stderr, "%s %s %s -> %d\n", req.remote_addr.c_str(), req.method.c_str(), req.path.c_str(),
                             res.status);
            });
    }
};

Server::Server(Options options) : impl_(std::make_unique<Impl>()) {
    Impl& s = *impl_;
    if (!fs::is_directory(options.root))
        throw InputError("serve: DIR '" + options.root.string() + "' is not a directory");
    if (options.port < 0 || options.port > 65535)
        throw InputError("serve: --port " + std::to_string(options.port) + " is not in 0..65535");
    if (options.throttle_kbps && !(std::isfinite(*options.throttle_kbps) && *options.throttle_kbps > 0.0))
        throw InputError("serve: --throttle-kbps must be a positive number of kilobits per second");
    if (options.workers == 0 || options.queued == 0)
        throw InputError("serve: workers and queued connections must be at least 1");
    s.options = std::move(options);
    if (s.options.throttle_kbps) s.link = std::make_unique<Link>(*s.options.throttle_kbps);
    const std::size_t workers = s.options.workers, queued = s.options.queued;
    // The workers serve the connections the gate hands over (GatedServer), through the
    // server's own task queue.
    s.http.new_task_queue = [workers, queued, &s] {
        auto* pool = new BoundedPool(workers, queued);
        s.http.set_enqueue([pool](std::function<void()> job) { pool->enqueue(std::move(job)); });
        return pool;
    };
    s.http.set_payload_max_length(1024);  // requests carry no body
    // SO_REUSEADDR only: cpp-httplib's default adds SO_REUSEPORT, with which a second server
    // on the same port would bind silently and take half of the connections.
    s.http.set_socket_options([](socket_t sock) {
        int yes = 1;
        ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });
    s.http.set_read_timeout(5, 0);
    s.http.set_write_timeout(10, 0);
    s.http.set_keep_alive_timeout(2);
    s.routes();
    if (s.options.port == 0) {
        s.port = s.http.bind_to_any_port(s.options.bind);
        if (s.port < 0) throw InputError("serve: cannot bind " + s.options.bind + " (any port)");
    } else {
        if (!s.http.bind_to_port(s.options.bind, s.options.port))
            throw InputError("serve: cannot bind " + s.options.bind + ":" + std::to_string(s.options.port) +
                             " (in use, or not an address of this machine)");
        s.port = s.options.port;
    }
}

Server::~Server() { stop(); }

int Server::port() const { return impl_->port; }

void Server::run() { impl_->http.listen_after_bind(); }

bool Server::running() const { return impl_->http.is_running(); }

void Server::stop() {
    if (impl_->link) impl_->link->stop();
    impl_->http.stop_gate();
    impl_->http.stop();
}

void run_until_signal(Server& server) {
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);  // inherited by every thread started below
    std::atomic<bool> returned{false};
    std::thread waiter([&] {
        int got = 0;
        sigwait(&signals, &got);
        // A signal that arrives before run() is listening would find nothing to stop: wait
        // for it to listen (or to have returned).
        while (!returned) {
            if (server.running()) {
                server.stop();
                return;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    });
    server.run();
    returned = true;
    // run() also returns if listening failed: wake the waiter if it still waits.
    pthread_kill(waiter.native_handle(), SIGTERM);
    waiter.join();
}

}  // namespace foldcast::serve
