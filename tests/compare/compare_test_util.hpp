#pragma once
// Helpers shared by compare's tests: synthetic images and running the foldcast binary.
#include <array>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "foldcast/compare/image.hpp"
#include "run_command.hpp"

namespace foldcast::test {

inline compare::Image constant_image(int w, int h, int c, float v) {
    compare::Image image(w, h, c);
    std::fill(image.values.begin(), image.values.end(), v);
    return image;
}

// Single-quoted for the shell (built with append: GCC 12 warns falsely on "'" + string&&).
inline std::string quoted(const std::filesystem::path& p) {
    std::string q(1, '\'');
    q.append(p.string());
    q.push_back('\'');
    return q;
}

}  // namespace foldcast::test
