// foldcast diff as a CI gate: exit statuses and fail counts against OpenImageIO's idiff on
// the same image pairs, and diff's own error statuses (3 size mismatch, 4 unreadable).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <cctype>

#include "test_paths.hpp"
#include "compare_test_util.hpp"
#include "foldcast/compare/image.hpp"

using namespace foldcast;
using namespace foldcast::test;
namespace fs = std::filesystem;

namespace {

// A textured 8-bit picture and a copy with noise of +/- `noise` levels on `share` of the
// pixels and one pixel changed by `spike` levels.
void write_pair(const fs::path& a, const fs::path& b, int noise, double share, int spike) {
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

bool have_idiff() { return run_command("command -v idiff >/dev/null 2>&1").exit_code == 0; }

struct IdiffResult {
    int exit_code;
    long long warn_pixels = -1, fail_pixels = -1;
};

IdiffResult run_idiff(const std::string& args, const fs::path& a, const fs::path& b) {
    const CommandResult r = run_command("idiff -v " + args + " " + quoted(a) + " " + quoted(b) + " 2>/dev/null");
    IdiffResult out{r.exit_code};
    // "  N pixels (P%) over T" twice: warnings first, then failures.  (Parsed by hand: GCC 12
    // warns falsely inside std::regex under the sanitizer build's -O2 -Werror.)
    std::vector<long long> counts;
    const std::string marker = " pixels (";
    for (size_t at = r.out.find(marker); at != std::string::npos; at = r.out.find(marker, at + 1)) {
        size_t start = at;
        while (start > 0 && std::isdigit(static_cast<unsigned char>(r.out[start - 1]))) --start;
        if (start < at) counts.push_back(std::stoll(r.out.substr(start, at - start)));
    }
    if (counts.size() >= 2) {
        out.warn_pixels = counts[0];
        out.fail_pixels = counts[1];
    }
    return out;
}

nlohmann::json run_ours(const std::string& args, const fs::path& a, const fs::path& b, int* exit_code) {
    const CommandResult r = run_command(foldcast_binary() + " diff --json " + args + " " + quoted(a) + " " + quoted(b));
    *exit_code = r.exit_code;
    return nlohmann::json::parse(r.out);
}

}  // namespace

TEST(DiffCli, AgreesWithIdiffOnExitCodesAndFailCounts) {
    if (!have_idiff()) GTEST_SKIP() << "idiff (openimageio-tools) not installed";
    const fs::path dir = temp_dir();
    const fs::path a = dir / "a.png", b = dir / "b.png", same = dir / "same.png";
    write_pair(a, b, 3, 0.2, 40);  // noise of 3/255 on 20 % of the pixels, one spike of 40/255
    write_pair(a, same, 0, 0.0, 0);
    // Thresholds avoid ties with multiples of 1/255 (idiff compares in float).
    const std::vector<std::string> cases = {
        "",                                                        // defaults: any change fails
        "--fail 0.02",                                             // only the spike fails
        "--fail 0.02 --failpercent 1",                             // 1 of 3072 allowed
        "--fail 0.02 --failpercent 1 --warn 0.005 --warnpercent 50",  // noise warns, share allowed
        "--fail 0.02 --failpercent 1 --warn 0.005 --warnpercent 5",   // too many warnings
        "--fail 0.5 --hardfail 0.1",                               // the spike exceeds hardfail
        "--fail 0.5 --warn 0.5 --hardwarn 0.1",                    // ... or hardwarn
        "--fail 0.12 --hardfail 0.1",                              // the spike fails and is over hardfail
        "--fail 0.1 --failpercent 1 --hardfail 0.12",              // within failpercent, over hardfail
        "--fail 0.1 --failpercent 1 --hardfail 0.2",               // warning only
        "--fail 0.002 --failpercent 30 --warn 0.002 --warnpercent 30",  // all within allowances
        "--fail 0.002 --allowfailures 700",                        // idiff's allowance by count
    };
    for (const std::string& args : cases) {
        std::string idiff_args;  // idiff spells its options with one dash
        for (size_t i = 0; i < args.size(); ++i)
            if (!(args[i] == '-' && i + 1 < args.size() && args[i + 1] == '-')) idiff_args.push_back(args[i]);
        const IdiffResult reference = run_idiff(idiff_args, a, b);
        int code = -1;
        const nlohmann::json ours = run_ours(args, a, b, &code);
        EXPECT_EQ(code, reference.exit_code) << "options: " << args;
        EXPECT_EQ(ours["fail_pixels"].get<long long>(), reference.fail_pixels) << "options: " << args;
        EXPECT_EQ(ours["warn_pixels"].get<long long>(), reference.warn_pixels) << "options: " << args;
    }
    int code = -1;
    run_ours("", a, same, &code);
    EXPECT_EQ(code, 0);
    EXPECT_EQ(run_idiff("", a, same).exit_code, 0);
}

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
    EXPECT_EQ(code_of(quoted(dir / "small.png") + " " + quoted(dir / "small.png") + " -o " + quoted(dir / "no/dir.png")), 4);
}
