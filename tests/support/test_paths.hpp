#pragma once
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace foldcast::test {

// A fresh, empty directory per test, under the build tree.
inline std::filesystem::path temp_dir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::filesystem::path dir = std::filesystem::path(FOLDCAST_BINARY_DIR) / "test-tmp" /
                                (std::string(info->test_suite_name()) + "." + info->name());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

inline std::filesystem::path test_data(const std::string& relative) {
    return std::filesystem::path(FOLDCAST_TEST_DATA) / relative;
}

}  // namespace foldcast::test
