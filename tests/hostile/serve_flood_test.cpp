// `foldcast serve` against a client that never stops sending header lines: docs/player.md
// promises at most 64 header lines and 16 KiB of headers, yet every line was read and
// stored (64 MiB of 8 KB lines grew the server by 580 MB; 1.7 GiB ended it in
// std::bad_alloc).  The connection must be cut at the budget and the server keep serving.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "../serve/http_test_client.hpp"
#include "spawn.hpp"
#include "test_paths.hpp"

namespace foldcast {
namespace {
namespace fs = std::filesystem;

int connect_to(int port, int receive_buffer_bytes = 0) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    if (fd >= 0 && receive_buffer_bytes > 0)  // before connect: it sets the window offered
        ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer_bytes, sizeof receive_buffer_bytes);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (fd >= 0 && ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) return fd;
    if (fd >= 0) ::close(fd);
    return -1;
}

// A port that was free a moment ago.
int free_port() {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof addr;
    ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &length);
    ::close(fd);
    return ntohs(addr.sin_port);
}

// A connection to `foldcast serve` once it listens (it may still be starting): -1 after 10 s.
int connect_when_serving(int port) {
    for (int i = 0; i < 200; ++i) {
        const int fd = connect_to(port);
        if (fd >= 0) return fd;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return -1;
}

long resident_kib(pid_t pid) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(status, line);)
        if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
    return -1;
}

TEST(ServeFlood, HeaderLinesPastTheBudgetAreNotRead) {
    const fs::path dir = test::temp_dir();
    std::ofstream(dir / "a.fca", std::ios::binary) << std::string(1000, 'a');
    const int port = free_port();
    const test::Child child =
        test::spawn({test::foldcast_under_test(), "serve", dir.string(), "--port", std::to_string(port)},
                    dir / "stderr.txt");
    const int fd = connect_when_serving(port);
    ASSERT_GE(fd, 0) << "foldcast serve did not start";
    const long before_kib = resident_kib(child.pid);
    timeval timeout{10, 0};
    ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
    const std::string start = "GET /files/a.fca HTTP/1.1\r\nHost: x\r\n";
    (void)::send(fd, start.data(), start.size(), MSG_NOSIGNAL);
    const std::string line = "X-Flood: " + std::string(8000, 'f') + "\r\n";
    std::size_t sent = 0;
    while (sent < (64u << 20)) {
        const ssize_t n = ::send(fd, line.data(), line.size(), MSG_NOSIGNAL);
        if (n <= 0) break;  // the server closed the connection
        sent += static_cast<std::size_t>(n);
    }
    ::close(fd);
    const long after_kib = resident_kib(child.pid);
    // Socket buffers take a few megabytes before the reset reaches the sender.
    EXPECT_LT(sent, 16u << 20) << "the server read " << sent << " bytes of header lines";
    EXPECT_LT(after_kib - before_kib, 64 * 1024) << "the server grew from " << before_kib << " to " << after_kib
                                                 << " KiB";
    EXPECT_EQ(test::http_get(port, "/files/a.fca").body, std::string(1000, 'a'));
    ::kill(child.pid, SIGTERM);
    int status = 0;
    ::waitpid(child.pid, &status, 0);
}

// Clients that ask for a large file and then take its bytes slowly (6 KB/s, in bursts every
// 4 s, so that no single write waits as long as the 10 s write timeout) held a worker each
// for as long as the file lasted: ten of them left a normal request unserved.  A response's
// writes may wait for the client 10 s plus 1 s per 16 KiB it has taken (docs/player.md);
// then the connection is cut.
TEST(ServeFlood, SlowReadersAreCutAtTheirDeadline) {
    const fs::path dir = test::temp_dir();
    std::ofstream(dir / "big.fca", std::ios::binary) << std::string(32u << 20, 'b');
    std::ofstream(dir / "a.fca", std::ios::binary) << std::string(1000, 'a');
    const int port = free_port();
    const test::Child child =
        test::spawn({test::foldcast_under_test(), "serve", dir.string(), "--port", std::to_string(port)},
                    dir / "stderr.txt");
    const int probe = connect_when_serving(port);
    ASSERT_GE(probe, 0) << "foldcast serve did not start";
    ::close(probe);
    std::vector<int> slow;
    for (int i = 0; i < 10; ++i) {  // more than the 8 workers
        const int fd = connect_to(port, 4096);
        ASSERT_GE(fd, 0);
        const std::string request = "GET /files/big.fca HTTP/1.1\r\nHost: x\r\n\r\n";
        (void)::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
        slow.push_back(fd);
    }
    std::atomic<bool> reading{true};
    std::thread reader([&] {
        std::vector<char> buffer(24 * 1024);
        std::vector<bool> open(slow.size(), true);
        while (reading) {
            for (std::size_t i = 0; i < slow.size(); ++i) {
                for (std::size_t got = 0; open[i] && got < buffer.size();) {
                    const ssize_t n = ::recv(slow[i], buffer.data(), buffer.size() - got, MSG_DONTWAIT);
                    if (n > 0) {
                        got += static_cast<std::size_t>(n);
                    } else if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK)) {
                        open[i] = false;  // the server closed it
                    } else {
                        break;
                    }
                }
            }
            for (int k = 0; k < 40 && reading; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
    });
    std::this_thread::sleep_for(std::chrono::seconds(1));
    const auto start = std::chrono::steady_clock::now();
    bool served = false;
    double seconds = 0;
    while (!served && seconds < 60) {
        served = test::http_get(port, "/files/a.fca").body == std::string(1000, 'a');
        seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    reading = false;
    reader.join();
    for (int fd : slow) ::close(fd);
    EXPECT_TRUE(served) << "a normal request waited " << seconds << " s behind slow readers";
    std::printf("a normal request was served after %.1f s\n", seconds);
    ::kill(child.pid, SIGTERM);
    int status = 0;
    ::waitpid(child.pid, &status, 0);
}

}  // namespace
}  // namespace foldcast
