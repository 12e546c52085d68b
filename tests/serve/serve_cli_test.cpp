#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>

#include "http_test_client.hpp"
#include "run_command.hpp"
#include "test_paths.hpp"

namespace foldcast {
namespace {

// `foldcast serve DIR --port 0` in a child process; its first stdout line names the port.
struct ServeProcess {
    pid_t pid = -1;
    int port = 0;
    explicit ServeProcess(const std::filesystem::path& dir) {
        int out[2];
        if (::pipe(out) != 0) return;
        pid = ::fork();
        if (pid == 0) {
            ::dup2(out[1], STDOUT_FILENO);
            ::close(out[0]);
            const std::string binary = test::foldcast_binary(), root = dir.string();
            ::execl(binary.c_str(), binary.c_str(), "serve", root.c_str(), "--port", "0", "--bind", "127.0.0.1",
                    nullptr);
            ::_exit(127);
        }
        ::close(out[1]);
        FILE* f = ::fdopen(out[0], "r");
        char line[512] = {};
        if (std::fgets(line, sizeof line, f)) {
            // "... http://127.0.0.1:PORT/ ..." (no std::regex: GCC 12 warns inside it under ASan)
            const std::string text(line), prefix = "http://127.0.0.1:";
            if (const auto at = text.find(prefix); at != std::string::npos)
                port = std::atoi(text.c_str() + at + prefix.size());
        }
        std::fclose(f);
    }
    int stop_with(int signal) {
        ::kill(pid, signal);
        int status = 0;
        ::waitpid(pid, &status, 0);
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    }
};

TEST(ServeCli, ServesUntilSigintThenExitsCleanly) {
    const auto dir = test::temp_dir();
    std::ofstream(dir / "x.fca") << "bytes";
    for (int signal : {SIGINT, SIGTERM}) {
        ServeProcess serve(dir);
        ASSERT_GT(serve.port, 0);
        const auto reply = test::http_get(serve.port, "/files/x.fca");
        EXPECT_EQ(reply.status, 200);
        EXPECT_EQ(reply.body, "bytes");
        EXPECT_EQ(serve.stop_with(signal), 0) << "signal " << signal;
    }
}

TEST(ServeCli, BadArgumentsExit2NamingThem) {
    const auto dir = test::temp_dir();
    auto r = test::run_command(test::foldcast_binary() + " serve " + (dir / "missing").string() + " 2>&1");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.out.find("missing"), std::string::npos) << r.out;
    r = test::run_command(test::foldcast_binary() + " serve " + dir.string() + " --throttle-kbps 0 2>&1");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.out.find("--throttle-kbps"), std::string::npos) << r.out;
    r = test::run_command(test::foldcast_binary() + " serve " + dir.string() + " --port 70000 2>&1");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.out.find("--port"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace foldcast
