#pragma once
// Shared by the diff CLI tests: a textured image pair with controlled differences, and
// `foldcast diff --json` run on it.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "compare_test_util.hpp"

namespace foldcast::test {

// A textured 8-bit picture and a copy with noise of +/- `noise` levels on `share` of the
// pixels and one pixel changed by `spike` levels.
inline void write_pair(const std::filesystem::path& a, const std::filesystem::path& b, int noise, double share,
                       int spike) {
    cv::RNG rng(1234);
    cv::Mat img(48, 64, CV_8UC3);
    for (int y = 0; y < img.rows; ++y)
        for (int x = 0; x < img.cols; ++x)
            img.at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<uchar>(40 + 3 * x), static_cast<uchar>(60 + 2 * y),
                                                static_cast<uchar>(128 + ((x / 8 + y / 8) % 2) * 60));
    cv::Mat other = img.clone();
    for (int y = 0; y < img.rows; ++y)
        for (int x = 0; x < img.cols; ++x)
            if (rng.uniform(0.0, 1.0) < share) {
                const int c = rng.uniform(0, 3);
                const int delta = rng.uniform(0, 2) ? noise : -noise;
                other.at<cv::Vec3b>(y, x)[c] = cv::saturate_cast<uchar>(other.at<cv::Vec3b>(y, x)[c] + delta);
            }
    other.at<cv::Vec3b>(10, 20)[1] = cv::saturate_cast<uchar>(other.at<cv::Vec3b>(10, 20)[1] + spike);
    ASSERT_TRUE(cv::imwrite(a.string(), img));
    ASSERT_TRUE(cv::imwrite(b.string(), other));
}

inline nlohmann::json run_ours(const std::string& args, const std::filesystem::path& a, const std::filesystem::path& b,
                               int* exit_code) {
    const CommandResult r = run_command(foldcast_binary() + " diff --json " + args + " " + quoted(a) + " " + quoted(b));
    *exit_code = r.exit_code;
    return nlohmann::json::parse(r.out);
}

}  // namespace foldcast::test
