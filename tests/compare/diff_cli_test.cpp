// foldcast diff as a CI gate: hand-computed counts and the heat-map, and diff's own error
// statuses (3 size mismatch, 4 unreadable).  The agreement with idiff is in
// idiff_agreement_test.cpp (label `slow`).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "compare_test_util.hpp"
#include "diff_cli_util.hpp"
#include "foldcast/compare/image.hpp"
#include "test_paths.hpp"

using namespace foldcast;
using namespace foldcast::test;
namespace fs = std::filesystem;

TEST(DiffCli, HandComputedCountsAndHeatMap) {
    const fs::path dir = temp_dir();
    const fs::path a = dir / "a.png", b = dir / "b.png", heat = dir / "heat.png";
    write_pair(a, b, 3, 0.2, 40);
    int code = -1;
    const nlohmann::json j = run_ours("--fail 0.1 -o " + quoted(heat), a, b, &code);
    EXPECT_EQ(code, 2);  // the 40/255 spike alone exceeds 0.1 (warnings aside) and 0 % are allowed
    EXPECT_EQ(j["fail_pixels"], 1);
    EXPECT_NEAR(j["max_abs_error"].get<double>(), 40.0 / 255.0, 1e-6);
    EXPECT_EQ(j["max_at"]["x"], 20);
    EXPECT_EQ(j["max_at"]["y"], 10);
    EXPECT_EQ(j["max_at"]["channel"], 1);
    const compare::Image h = compare::read_image(heat);
    EXPECT_EQ(h.width, 64);
    EXPECT_EQ(h.height, 48);
}

TEST(DiffCli, SizeMismatchExits3AndUnreadableExits4) {
    const fs::path dir = temp_dir();
    cv::imwrite((dir / "small.png").string(), cv::Mat(4, 4, CV_8UC3, cv::Scalar(10, 20, 30)));
    cv::imwrite((dir / "wide.png").string(), cv::Mat(4, 5, CV_8UC3, cv::Scalar(10, 20, 30)));
    std::ofstream(dir / "junk.png") << "not a png";
    auto code_of = [&](const std::string& args) {
        return run_command(foldcast_binary() + " diff " + args + " 2>/dev/null").exit_code;
    };
    EXPECT_EQ(code_of(quoted(dir / "small.png") + " " + quoted(dir / "wide.png")), 3);
    EXPECT_EQ(code_of(quoted(dir / "small.png") + " " + quoted(dir / "missing.png")), 4);
    EXPECT_EQ(code_of(quoted(dir / "junk.png") + " " + quoted(dir / "small.png")), 4);
    EXPECT_EQ(code_of(quoted(dir / "small.png") + " " + quoted(dir / "small.png")), 0);
    EXPECT_EQ(
        code_of(quoted(dir / "small.png") + " " + quoted(dir / "small.png") + " -o " + quoted(dir / "no/dir.png")), 4);
}
