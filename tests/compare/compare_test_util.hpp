#pragma once
// Helpers shared by compare's tests: synthetic images and running the foldcast binary.
#include <array>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <sys/wait.h>

#include "foldcast/compare/image.hpp"

namespace foldcast::test {

inline compare::Image constant_image(int w, int h, int c, float v) {
    compare::Image image(w, h, c);
    std::fill(image.values.begin(), image.values.end(), v);
    return image;
}

struct CommandResult {
    int exit_code = -1;
    std::string out;  // stdout only
};

// Runs a shell command, capturing stdout; stderr goes to the test log.
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

// Single-quoted for the shell (built with append: GCC 12 warns falsely on "'" + string&&).
inline std::string quoted(const std::filesystem::path& p) {
    std::string q(1, '\'');
    q.append(p.string());
    q.push_back('\'');
    return q;
}

}  // namespace foldcast::test
