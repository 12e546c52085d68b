#pragma once
// Running shell commands (usually the built foldcast) from tests.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace foldcast::test {

struct CommandResult {
    int exit_code = -1;
    std::string out;  // stdout only (add 2>&1 to the command for stderr)
};

inline CommandResult run_command(const std::string& command) {
    CommandResult result;
    FILE* pipe = ::popen(command.c_str(), "r");
    if (!pipe) return result;
    std::array<char, 4096> buffer{};
    size_t n = 0;
    while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.out.append(buffer.data(), n);
    const int status = ::pclose(pipe);
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

inline std::string foldcast_binary() { return std::string(FOLDCAST_BINARY_DIR) + "/foldcast"; }

}  // namespace foldcast::test
