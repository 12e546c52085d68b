#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "foldcast/core/error.hpp"
#include "foldcast/serve/serve.hpp"
#include "http_test_client.hpp"
#include "test_paths.hpp"

namespace foldcast::serve {
namespace server_test {
namespace fs = std::filesystem;
using test::http_get;

std::string random_bytes(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::string s(n, '\0');
    for (char& c : s) c = static_cast<char>(rng());
    return s;
}

void write(const fs::path& file, const std::string& bytes) {
    fs::create_directories(file.parent_path());
    std::ofstream(file, std::ios::binary) << bytes;
}

// A server on 127.0.0.1, any free port, over a tree with files inside and a secret outside.
struct Running {
    fs::path root, web, outside;
    std::string a, b;
    std::unique_ptr<Server> server;
    std::thread thread;

    explicit Running(Options options = {}) {
        const fs::path dir = test::temp_dir();
        root = dir / "root";
        web = dir / "web";
        outside = dir / "outside";
        a = random_bytes(100000, 1);
        b = random_bytes(5000, 2);
        write(root / "a.fca", a);
        write(root / "sub dir" / "b.fca", b);
        write(root / "notes.txt", "not an animation");
        write(outside / "secret.fca", "SECRET");
        write(web / "index.html", "<html>player</html>");
        fs::create_symlink(outside / "secret.fca", root / "link_out.fca");
        fs::create_directory_symlink(outside, root / "dir_out");
        options.root = root;
        options.web_dir = web;
        options.bind = "127.0.0.1";
        options.port = 0;
        server = std::make_unique<Server>(options);
        thread = std::thread([this] { server->run(); });
        // Serving once a request is answered (stop() before run() starts would be missed).
        while (http_get(port(), "/index.html").status != 200) std::this_thread::yield();
    }
    ~Running() {
        server->stop();
        thread.join();
    }
    int port() const { return server->port(); }
};

TEST(Server, ListsTheFcaFilesInsideRootOnly) {
    Running s;
    const auto reply = http_get(s.port(), "/api/files");
    ASSERT_EQ(reply.status, 200);
    EXPECT_EQ(reply.headers.at("content-type"), "application/json");
    const auto files = nlohmann::json::parse(reply.body);
    ASSERT_EQ(files.size(), 2u) << reply.body;  // not notes.txt, not the symlinks leading out
    EXPECT_EQ(files[0]["name"], "a.fca");
    EXPECT_EQ(files[0]["bytes"], s.a.size());
    EXPECT_EQ(files[1]["name"], "sub dir/b.fca");
}

TEST(Server, ServesWholeFilesAndThePlayer) {
    Running s;
    auto reply = http_get(s.port(), "/files/a.fca");
    ASSERT_EQ(reply.status, 200);
    EXPECT_EQ(reply.body, s.a);
    EXPECT_EQ(reply.headers.at("accept-ranges"), "bytes");
    reply = http_get(s.port(), "/files/sub%20dir/b.fca");
    ASSERT_EQ(reply.status, 200);
    EXPECT_EQ(reply.body, s.b);
    reply = http_get(s.port(), "/");
    ASSERT_EQ(reply.status, 200);
    EXPECT_EQ(reply.body, "<html>player</html>");
    EXPECT_EQ(reply.headers.at("content-type"), "text/html; charset=utf-8");
}

TEST(Server, RangeRequestsGiveExactlyTheBytesAsked) {
    Running s;
    auto reply = http_get(s.port(), "/files/a.fca", "Range: bytes=1000-1999\r\n");
    ASSERT_EQ(reply.status, 206);
    EXPECT_EQ(reply.body, s.a.substr(1000, 1000));
    EXPECT_EQ(reply.headers.at("content-range"), "bytes 1000-1999/100000");
    reply = http_get(s.port(), "/files/a.fca", "Range: bytes=99990-\r\n");
    ASSERT_EQ(reply.status, 206);
    EXPECT_EQ(reply.body, s.a.substr(99990));
    reply = http_get(s.port(), "/files/a.fca", "Range: bytes=-7\r\n");
    ASSERT_EQ(reply.status, 206);
    EXPECT_EQ(reply.body, s.a.substr(s.a.size() - 7));
    for (const char* bad : {"bytes=100000-", "bytes=200000-300000", "bytes=50-10"}) {
        reply = http_get(s.port(), "/files/a.fca", std::string("Range: ") + bad + "\r\n");
        EXPECT_EQ(reply.status, 416) << bad;
        EXPECT_EQ(reply.body.find(s.a.substr(0, 16)), std::string::npos);
    }
}

TEST(Server, MissingFilesAndOtherTypesAre404) {
    Running s;
    for (const char* target :
         {"/files/missing.fca", "/files/notes.txt", "/files/sub%20dir", "/files/", "/nope.js", "/api/nope"})
        EXPECT_EQ(http_get(s.port(), target).status, 404) << target;
}

// Every way out of root the issue names: .., absolute, encoded and double-encoded, symlinks.
TEST(Server, TraversalAttemptsNeverReachAFileOutsideRoot) {
    Running s;
    const std::string secret = fs::canonical(s.outside / "secret.fca").string();
    std::vector<std::string> targets = {"/files/../outside/secret.fca",
                                        "/files/%2e%2e/outside/secret.fca",
                                        "/files/%2E%2E%2Foutside%2Fsecret.fca",
                                        "/files/sub%20dir/../../outside/secret.fca",
                                        "/files/..%2f..%2foutside%2fsecret.fca",
                                        "/files/%252e%252e/outside/secret.fca",
                                        "/files/" + secret,
                                        "/files//" + secret,
                                        "/files/%2f" + secret.substr(1),
                                        "/files/link_out.fca",
                                        "/files/dir_out/secret.fca",
                                        "/files/..%5c..%5coutside%5csecret.fca",
                                        "/files/a.fca%00.fca",
                                        "/../outside/secret.fca",
                                        "/%2e%2e/outside/secret.fca",
                                        "/..%2f..%2f..%2f..%2f..%2f..%2fetc%2fpasswd",
                                        "/" + secret,
                                        "//etc/passwd",
                                        "/files/../../../../../../etc/passwd"};
    for (const auto& target : targets) {
        const auto reply = http_get(s.port(), target);
        EXPECT_TRUE(reply.status == 404 || reply.status == 400) << target << " -> " << reply.status;
        EXPECT_EQ(reply.body.find("SECRET"), std::string::npos) << target;
        EXPECT_EQ(reply.body.find("root:"), std::string::npos) << target;
    }
}

TEST(Server, OversizedAndUnexpectedRequestsAreRefused) {
    Running s;
    EXPECT_EQ(http_get(s.port(), "/files/" + std::string(20000, 'a') + ".fca").status, 414);
    std::string many;
    for (int i = 0; i < 200; ++i) many += "X-Filler-" + std::to_string(i) + ": 1\r\n";
    EXPECT_EQ(http_get(s.port(), "/files/a.fca", many).status, 431);
    const auto long_line = http_get(s.port(), "/files/a.fca", "X-Long: " + std::string(20000, 'b') + "\r\n").status;
    EXPECT_TRUE(long_line == 400 || long_line == 431 || long_line == 0)
        << long_line;  // cpp-httplib drops the line's connection
    EXPECT_EQ(test::raw_http(s.port(), "DELETE /files/a.fca HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n").status,
              405);
    EXPECT_EQ(
        test::raw_http(s.port(),
                       "POST /files/a.fca HTTP/1.1\r\nHost: x\r\nConnection: close\r\nContent-Length: 4\r\n\r\nabcd")
            .status,
        413);
    EXPECT_EQ(
        test::raw_http(s.port(),
                       "GET /files/a.fca HTTP/1.1\r\nHost: x\r\nConnection: close\r\nContent-Length: 100000000\r\n\r\n")
            .status,
        413);
    // Still serving afterwards.
    EXPECT_EQ(http_get(s.port(), "/files/a.fca").body, s.a);
}

TEST(Server, ConcurrentClientsAllGetTheirBytes) {
    Options options;
    options.workers = 3;
    options.queued = 2;  // more clients than workers + queue: the rest wait in the backlog
    Running s(options);
    constexpr int kClients = 16, kRequests = 4;
    std::vector<int> good(kClients, 0);
    std::vector<std::thread> clients;
    for (int c = 0; c < kClients; ++c)
        clients.emplace_back([&, c] {
            for (int r = 0; r < kRequests; ++r) {
                const bool ranged = (c + r) % 2 == 1;
                const auto reply = http_get(s.port(), c % 3 == 0 ? "/files/sub%20dir/b.fca" : "/files/a.fca",
                                            ranged ? "Range: bytes=100-4099\r\n" : "");
                const std::string& whole = c % 3 == 0 ? s.b : s.a;
                good[c] += reply.body == (ranged ? whole.substr(100, 4000) : whole);
            }
        });
    for (auto& t : clients) t.join();
    for (int c = 0; c < kClients; ++c) EXPECT_EQ(good[c], kRequests) << "client " << c;
}

TEST(Server, ThrottledResponsesAreComplete) {
    Options options;
    options.throttle_kbps = 20000.0;  // 2.5 MB/s: the 100 kB file crosses in ~40 ms
    Running s(options);
    const auto reply = http_get(s.port(), "/files/a.fca", "Range: bytes=10-60009\r\n");
    ASSERT_EQ(reply.status, 206);
    EXPECT_EQ(reply.body, s.a.substr(10, 60000));
}

TEST(Server, StopEndsRunEvenDuringASlowDownload) {
    Options options;
    options.throttle_kbps = 8.0;  // 1 kB/s: the 100 kB file would take 100 s
    Running s(options);
    std::thread client([&] { http_get(s.port(), "/files/a.fca"); });
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    s.server->stop();  // ~Running joins run(); the client sees its connection closed
    client.join();
}

TEST(Server, InvalidOptionsNameTheProblem) {
    Options options;
    options.root = test::temp_dir() / "missing";
    try {
        Server server(options);
        FAIL() << "accepted a missing DIR";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos);
    }
    options.root = test::temp_dir();
    options.throttle_kbps = -1.0;
    EXPECT_THROW(Server{options}, InputError);
    options.throttle_kbps.reset();
    Running busy;  // its port is taken: binding it again fails
    options.port = busy.port();
    EXPECT_THROW(Server{options}, InputError);
}

// RFC 9110 14.1.2: a last position past the end is the end; a range starting past the end is
// unsatisfiable.  A Content-Length of the range asked for (1,000,000,000 for a 100,000-byte
// file) left the client waiting for bytes that never came.
TEST(Server, RangesPastTheEndAreClampedToTheFile) {
    Running s;
    const std::string size = std::to_string(s.a.size());
    for (const std::string& asked :
         std::vector<std::string>{"bytes=0-999999999", "bytes=0-" + size, "bytes=0-9223372036854775807"}) {
        const auto reply = http_get(s.port(), "/files/a.fca", "Range: " + asked + "\r\n");
        ASSERT_EQ(reply.status, 206) << asked;
        EXPECT_EQ(reply.headers.at("content-length"), size) << asked;
        EXPECT_EQ(reply.headers.at("content-range"), "bytes 0-" + std::to_string(s.a.size() - 1) + "/" + size) << asked;
        EXPECT_EQ(reply.body, s.a) << asked;
    }
    auto reply = http_get(s.port(), "/files/a.fca", "Range: bytes=99990-99999999999\r\n");
    ASSERT_EQ(reply.status, 206);
    EXPECT_EQ(reply.body, s.a.substr(99990));
    EXPECT_EQ(reply.headers.at("content-range"), "bytes 99990-99999/" + size);
    reply = http_get(s.port(), "/files/a.fca", "Range: bytes=-999999999\r\n");  // a suffix longer than the file
    ASSERT_EQ(reply.status, 206);
    EXPECT_EQ(reply.body, s.a);
    for (const char* unsatisfiable : {"bytes=100000-100000", "bytes=9223372036854775807-", "bytes=-0"}) {
        reply = http_get(s.port(), "/files/a.fca", std::string("Range: ") + unsatisfiable + "\r\n");
        EXPECT_EQ(reply.status, 416) << unsatisfiable;
        EXPECT_EQ(reply.headers["content-range"], "bytes */" + size) << unsatisfiable;
    }
    // A number past 2^63 is not a range cpp-httplib can hold: refused, and the server lives on.
    reply = http_get(s.port(), "/files/a.fca", "Range: bytes=0-99999999999999999999999\r\n");
    EXPECT_TRUE(reply.status == 416 || reply.status == 200) << reply.status;
    EXPECT_EQ(http_get(s.port(), "/files/a.fca").body, s.a);
}

// Clients that trickle a header line now and then (here one every 2 s, under the 5 s read
// timeout) each held a worker for as long as they liked: 40 of them left no worker for
// anyone else.  They now wait in the gate, which cuts each at its 10 s head deadline (408).
TEST(Server, SlowClientsDoNotBlockOthers) {
    Running s;
    std::vector<int> slow;
    for (int i = 0; i < 40; ++i) {
        const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in addr{};
        addr.sin_family = AF_INET;
        addr.sin_port = htons(static_cast<std::uint16_t>(s.port()));
        addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        if (fd >= 0 && ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
            const std::string start = "GET /files/a.fca HTTP/1.1\r\n";
            (void)::send(fd, start.data(), start.size(), MSG_NOSIGNAL);
            slow.push_back(fd);
        }
    }
    std::atomic<bool> trickling{true};
    std::thread trickle([&] {
        while (trickling) {
            for (int fd : slow) (void)::send(fd, "X-Slow: 1\r\n", 11, MSG_NOSIGNAL);
            for (int k = 0; k < 20 && trickling; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
    });
    int served = 0;
    for (int i = 0; i < 5; ++i) served += http_get(s.port(), "/files/sub%20dir/b.fca").body == s.b;
    trickling = false;
    trickle.join();
    EXPECT_EQ(served, 5) << "normal requests were left waiting behind slow clients";
    // The slow clients' heads never complete: each is answered 408 at its deadline.
    char reply[64] = {};
    timeval timeout{15, 0};
    ::setsockopt(slow.front(), SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    const ssize_t got = ::recv(slow.front(), reply, sizeof reply - 1, 0);
    EXPECT_GT(got, 0);
    EXPECT_EQ(std::string(reply).rfind("HTTP/1.1 408", 0), 0u) << reply;
    for (int fd : slow) ::close(fd);
}

// Every readable .fca file is listed: a name that is not UTF-8 made the listing a 500 with the
// JSON library's text, and a symlink loop named like an animation hid the files after it.
TEST(Server, ListsEveryReadableFileWhateverItsName) {
    Running s;
    write(s.root / "\xff\xfe.fca", "odd name");
    fs::create_symlink(s.root / "l2.fca", s.root / "l1.fca");
    fs::create_symlink(s.root / "l1.fca", s.root / "l2.fca");
    write(s.root / "z.fca", "last");
    const auto reply = http_get(s.port(), "/api/files");
    ASSERT_EQ(reply.status, 200) << reply.body;
    EXPECT_EQ(reply.headers.count("exception_what"), 0u);
    const auto files = nlohmann::json::parse(reply.body);
    std::vector<std::string> urls;
    for (const auto& f : files) urls.push_back(f["url"]);
    EXPECT_EQ(urls, (std::vector<std::string>{"files/a.fca", "files/sub%20dir/b.fca", "files/z.fca",
                                              "files/%FF%FE.fca"}));
    EXPECT_EQ(http_get(s.port(), "/files/%FF%FE.fca").body, "odd name");
}

}  // namespace server_test
}  // namespace foldcast::serve
