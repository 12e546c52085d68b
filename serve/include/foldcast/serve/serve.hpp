#pragma once
// serve: an HTTP server for .fca animations and the browser player (docs/player.md).
//
//   GET /                 the player (web_dir/index.html) and its assets from web_dir
//   GET /api/files        JSON listing of the .fca files under root: [{"name", "bytes"}]
//   GET /files/NAME.fca   one file, with Range requests (bytes=A-B)
//
// Only files inside root (or web_dir) are served: a path with "..", an absolute or
// encoded variant, or a symlink leading out is refused (404).  Requests are bounded
// (URI and header lines 8 KiB, 64 headers, no body), as are connections (workers +
// a bounded accept queue); throttle_kbps paces every .fca response body through one shared
// link of that many kilobits per second (the player's own assets are not paced: a browser
// keeps them cached after its first visit; docs/player.md gives their size).
#include <atomic>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace foldcast::serve {

struct Options {
    std::filesystem::path root;     // the .fca files
    std::filesystem::path web_dir;  // the built player (build/web); may be missing
    std::string bind = "127.0.0.1";
    int port = 8080;                      // 0: any free port (see Server::port())
    std::optional<double> throttle_kbps;  // kilobits per second shared by all .fca downloads
    std::size_t workers = 8;              // connections served at once
    std::size_t queued = 32;              // accepted connections waiting for a worker
    bool log = false;                     // one line per request on stderr
};

// The file `url_path` (already %-decoded, relative to root, '/'-separated) names inside
// root, or nullopt when it would leave root (.., absolute, NUL or backslash, a symlink
// whose target is outside) or is not a regular file.
std::optional<std::filesystem::path> resolve_inside(const std::filesystem::path& root, std::string_view url_path);

class Server {
public:
    // Validates the options (InputError naming the bad one) and binds; throws InputError
    // when the address cannot be bound.
    explicit Server(Options options);
    ~Server();
    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;

    int port() const;      // the bound port
    void run();            // serves until stop()
    bool running() const;  // run() is listening
    void stop();           // from any thread; a no-op unless running()
private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// run() until SIGINT or SIGTERM arrives, then stops cleanly (in-flight responses are cut,
// threads joined).  Blocks those signals in the calling thread (and the threads it starts)
// and waits for them with sigwait: no handler runs in signal context.
void run_until_signal(Server& server);

}  // namespace foldcast::serve
