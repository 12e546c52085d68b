// The swatch sheet: every chosen look rendered the same way, tiled and labelled.
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "foldcast/core/error.hpp"
#include "foldcast/batch/swatches.hpp"
#include "run_command.hpp"
#include "shipped_looks.hpp"

namespace fs = std::filesystem;
using namespace foldcast;

namespace {

batch::SwatchOptions tiny(std::vector<std::string> looks) {
    batch::SwatchOptions o;
    o.looks = std::move(looks);
    o.tile_width = 40;
    o.tile_height = 48;
    o.spp = 1;
    o.columns = 2;
    return o;
}

// Mean absolute difference of two tiles of the sheet (tile pixels only, not labels).
double tile_difference(const batch::SwatchSheet& sheet, const batch::SwatchOptions& o, int a, int b) {
    const int label =
        sheet.height / ((static_cast<int>(sheet.tiles.size()) + o.columns - 1) / o.columns) - o.tile_height;
    auto origin = [&](int k) {
        return std::pair<int, int>{(k % o.columns) * o.tile_width, (k / o.columns) * (o.tile_height + label)};
    };
    const auto [ax, ay] = origin(a);
    const auto [bx, by] = origin(b);
    double sum = 0.0;
    for (int y = 0; y < o.tile_height; ++y)
        for (int x = 0; x < o.tile_width; ++x)
            for (int c = 0; c < 3; ++c)
                sum += std::abs(int(sheet.rgb[(size_t(ay + y) * sheet.width + ax + x) * 3 + c]) -
                                int(sheet.rgb[(size_t(by + y) * sheet.width + bx + x) * 3 + c]));
    return sum / (o.tile_width * o.tile_height * 3);
}

int run_status(const std::string& arguments) {
    return test::run_command(test::foldcast_binary() + " " + arguments).exit_code;
}
}  // namespace

TEST(SwatchSheet, TilesEveryChosenLookInOrderWithItsFolds) {
    const auto options = tiny({"denim", "chiffon", "satin"});
    const auto sheet = batch::render_swatch_sheet(test::shipped_looks(), options);
    ASSERT_EQ(sheet.tiles.size(), 3u);
    EXPECT_EQ(sheet.tiles[0].look, "denim");
    EXPECT_EQ(sheet.tiles[2].look, "satin");
    EXPECT_LT(sheet.tiles[0].folds, sheet.tiles[1].folds);  // denim folds less than chiffon
    EXPECT_EQ(sheet.width, 2 * options.tile_width);
    EXPECT_GT(sheet.height, 2 * options.tile_height);  // two rows plus label strips
    EXPECT_EQ(sheet.rgb.size(), size_t(sheet.width) * sheet.height * 3);
    // Different fabrics look different: indigo denim vs pink chiffon.
    EXPECT_GT(tile_difference(sheet, options, 0, 1), 5.0);
}

TEST(SwatchSheet, SameBytesWhateverTheThreadCount) {
    auto one = tiny({"velvet", "linen"});
    one.threads = 1;
    auto two = one;
    two.threads = 2;
    EXPECT_EQ(batch::render_swatch_sheet(test::shipped_looks(), one).rgb,
              batch::render_swatch_sheet(test::shipped_looks(), two).rgb);
}

TEST(SwatchSheet, BadInputsAreInputErrors) {
    EXPECT_THROW(batch::render_swatch_sheet(test::shipped_looks(), tiny({"denim", "velour"})), InputError);
    auto small = tiny({"denim"});
    small.tile_width = 4;
    EXPECT_THROW(batch::render_swatch_sheet(test::shipped_looks(), small), InputError);
    EXPECT_THROW(batch::write_swatch_sheet("/tmp/sheet.jpg", batch::SwatchSheet{}), InputError);
    auto negative = tiny({"denim"});
    negative.noise_threshold = -0.01;
    EXPECT_THROW(batch::render_swatch_sheet(test::shipped_looks(), negative), InputError);
}

// --denoise and --noise-threshold reach every tile: the denoised sheet is smoother, and an
// adaptive one with a loose threshold takes fewer samples (fewer rays) for nearly the same picture.
TEST(SwatchSheet, DenoiseAndAdaptiveSamplingReachTheTiles) {
    auto plain = tiny({"linen", "satin"});
    plain.spp = 16;
    auto denoised = plain;
    denoised.denoise = true;
    auto adaptive = denoised;
    adaptive.noise_threshold = 0.05;
    const auto a = batch::render_swatch_sheet(test::shipped_looks(), plain);
    const auto b = batch::render_swatch_sheet(test::shipped_looks(), denoised);
    const auto c = batch::render_swatch_sheet(test::shipped_looks(), adaptive);
    EXPECT_NE(a.rgb, b.rgb);
    EXPECT_LT(c.stats.rays, b.stats.rays);
}

TEST(SwatchSheet, CommandWritesThePng) {
    const fs::path out = fs::temp_directory_path() / "foldcast_swatch_cli_test.png";
    fs::remove(out);
    ASSERT_EQ(
        run_status("looks --swatches " + out.string() + " --only denim,chiffon --tile 40x48 --spp 1 --columns 2 -q"),
        0);
    const cv::Mat png = cv::imread(out.string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(png.empty());
    EXPECT_EQ(png.cols, 80);
    EXPECT_GT(png.rows, 48);
    fs::remove(out);
    EXPECT_EQ(run_status("looks --swatches " + out.string() + " --only nosuchlook -q 2>/dev/null"), 2);
    EXPECT_EQ(run_status("looks --swatches /nonexistent/dir/x.png -q 2>/dev/null"), 2);
    EXPECT_EQ(run_status("looks --swatches " + out.string() + " --tile 40by48 -q 2>/dev/null"), 2);
    EXPECT_FALSE(fs::exists(out));
}
