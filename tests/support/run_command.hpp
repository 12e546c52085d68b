#pragma once
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace foldcast::test {

// Runs a shell command, returns what it printed on stdout (add 2>&1 for stderr) and sets
// *status to its exit status.
inline std::string run_command(const std::string& command, int* status) {
    std::string out;
    FILE* pipe = popen(command.c_str(), "r");
    if (pipe == nullptr) {
        *status = -1;
        return out;
    }
    char buffer[4096];
    while (std::fgets(buffer, sizeof buffer, pipe)) out += buffer;
    *status = WEXITSTATUS(pclose(pipe));
    return out;
}

inline std::string foldcast_binary() { return std::string(FOLDCAST_BINARY_DIR) + "/foldcast"; }

}  // namespace foldcast::test
