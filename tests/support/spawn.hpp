#pragma once
// Running the built foldcast as a child process that a test can interrupt or cap: fork +
// exec, optional CPU-time and address-space limits, stdout and stderr to files.
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

namespace foldcast::test {

// The foldcast these tests run: FOLDCAST_BINARY when set (to show that a test fails on
// another build, e.g. one from before a fix), else the one of this build tree.
inline std::string foldcast_under_test() {
    const char* chosen = std::getenv("FOLDCAST_BINARY");
    return chosen != nullptr && *chosen != '\0' ? std::string(chosen) : std::string(FOLDCAST_BINARY_DIR) + "/foldcast";
}

struct Limits {
    int cpu_seconds = 0;                  // RLIMIT_CPU: SIGXCPU past it; 0 = none
    unsigned long long memory_bytes = 0;  // RLIMIT_AS; 0 = none (ignored under sanitizers)
};

// The sanitizers reserve terabytes of address space: RLIMIT_AS would stop them, not us.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
#else
inline constexpr bool kSanitized = false;
#endif

struct Child {
    pid_t pid = -1;
    std::filesystem::path stderr_path;
};

// Starts `argv` (argv[0] a path) with stdout to /dev/null and stderr to `stderr_path`.
inline Child spawn(const std::vector<std::string>& argv, const std::filesystem::path& stderr_path, Limits limits = {}) {
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        const int null = ::open("/dev/null", O_WRONLY);
        const int err = ::open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        // As a user's shell would: a test started in the background has SIGINT ignored,
        // which the child would inherit (and foldcast keeps an ignored signal ignored).
        for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::signal(sig, SIG_DFL);
        if (null >= 0) ::dup2(null, 1);
        if (err >= 0) ::dup2(err, 2);
        if (limits.cpu_seconds > 0) {
            const rlimit cpu{rlim_t(limits.cpu_seconds), rlim_t(limits.cpu_seconds + 1)};
            ::setrlimit(RLIMIT_CPU, &cpu);
        }
        if (limits.memory_bytes > 0 && !kSanitized) {
            const rlimit as{limits.memory_bytes, limits.memory_bytes};
            ::setrlimit(RLIMIT_AS, &as);
        }
        ::execv(args[0], args.data());
        ::_exit(127);
    }
    return {pid, stderr_path};
}

struct Outcome {
    bool exited = false;
    int exit_code = -1;  // when exited
    int signal = 0;      // when killed by a signal
    std::string err;     // what it wrote to stderr
    double seconds = 0;  // wall time, for messages only
};

inline Outcome wait_for(const Child& child,
                        std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now()) {
    int status = 0;
    ::waitpid(child.pid, &status, 0);
    Outcome o;
    o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    o.exited = WIFEXITED(status);
    o.exit_code = o.exited ? WEXITSTATUS(status) : -1;
    o.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
    std::ifstream in(child.stderr_path);
    o.err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return o;
}

// Runs to completion.
inline Outcome run_child(const std::vector<std::string>& argv, const std::filesystem::path& stderr_path,
                         Limits limits = {}) {
    const auto start = std::chrono::steady_clock::now();
    return wait_for(spawn(argv, stderr_path, limits), start);
}

// Starts, sends `sig` after `delay`, waits.
inline Outcome interrupt_after(const std::vector<std::string>& argv, const std::filesystem::path& stderr_path,
                               std::chrono::microseconds delay, int sig) {
    const auto start = std::chrono::steady_clock::now();
    const Child child = spawn(argv, stderr_path);
    std::this_thread::sleep_for(delay);
    ::kill(child.pid, sig);
    return wait_for(child, start);
}

}  // namespace foldcast::test
