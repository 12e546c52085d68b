// Overlay geometry and scoring.  The synthetic photo here is drawn from the same projection
// (dark Gaussian lines along the projected fold lines), a weaker proxy than a path-traced
// render of the drape: it checks the mapping, detection and scoring chain, not shading.
#include <gtest/gtest.h>

#include <cmath>

#include "compare_test_util.hpp"
#include "foldcast/compare/overlay.hpp"
#include "test_paths.hpp"

using namespace foldcast;
using foldcast::test::constant_image;

TEST(OverlayMapping, SupportsLandOnTheirPixelsAndScaleIsSpanOverDistance) {
    const compare::SupportPixels s{{100, 50}, {300, 70}};
    const auto m = compare::similarity_from_supports(s, 0.4);
    EXPECT_LT((m(-0.2, 0) - s.first).norm(), 1e-9);
    EXPECT_LT((m(0.2, 0) - s.second).norm(), 1e-9);
    EXPECT_NEAR(m.px_per_m, std::hypot(200, 20) / 0.4, 1e-9);
    // Cloth "down" (-y) is picture down (+y) for level supports.
    const auto level = compare::similarity_from_supports({{0, 0}, {100, 0}}, 1.0);
    EXPECT_NEAR(level(0, -0.5).y(), 50.0, 1e-9);
    // A homography through four corners maps them exactly.
    const std::array<Eigen::Vector2d, 4> c{Eigen::Vector2d(100, 50), Eigen::Vector2d(300, 60),
                                           Eigen::Vector2d(290, 330), Eigen::Vector2d(110, 320)};
    const auto h = compare::homography_from_corners(c, 0.4, 0.7);
    EXPECT_LT((h(-0.2, 0) - c[0]).norm(), 1e-3);
    EXPECT_LT((h(0.2, -0.7) - c[2]).norm(), 1e-3);
    EXPECT_THROW(compare::homography_from_corners({c[0], c[0], c[2], c[3]}, 0.4, 0.7), InputError);
}

TEST(OverlayScore, LinesDrawnFromTheProjectionAreDetectedWithinTwoPixels) {
    drape::ClothParams p;
    p.width_m = 0.5;
    p.height_m = 0.5;  // 3 folds under the hem closure, the lowest 0.29 m (193 px) down
    p.inset_m = 0.1;
    p.thickness_m = 0.2e-3;
    const auto solution = drape::solve_folds(p);
    ASSERT_GT(solution.folds, 1);
    const compare::SupportPixels s{{60, 30}, {260, 30}};
    const auto map = compare::similarity_from_supports(s, p.support_span_m());
    const auto lines = compare::project_fold_lines(drape::fold_lines(p, solution), solution.folds, map);
    // Synthetic photo: valleys dark, crests bright, Gaussian profile 1.5 px.
    compare::Image photo = constant_image(320, 240, 3, 0.5f);
    for (int y = 0; y < 240; ++y)
        for (int x = 0; x < 320; ++x) {
            double v = 0.5;
            for (const auto& l : lines) {
                if (l.top_edge) continue;
                double d = 1e9;
                for (size_t i = 1; i < l.points_px.size(); ++i) {
                    const Eigen::Vector2d a = l.points_px[i - 1], b = l.points_px[i], q(x, y);
                    const double t = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
                    d = std::min(d, (a + t * (b - a) - q).norm());
                }
                v += 0.25 * l.sign * std::exp(-d * d / (2 * 1.5 * 1.5));
            }
            for (int c = 0; c < 3; ++c) photo.at(x, y, c) = static_cast<float>(v);
        }
    const auto detection = compare::detect_folds(photo, constant_image(320, 240, 1, 1.0f));
    const compare::CentreLine centre;
    const auto score = compare::score_folds(lines, detection, centre, map.px_per_m, 2.0);
    EXPECT_GT(score.recall, 0.95);    // detected points within 2 px of a predicted line
    EXPECT_GT(score.precision, 0.6);  // the folds crowd near the supports, where lines merge
    EXPECT_LT(score.chamfer_cm, 100.0 * 2.0 / map.px_per_m);
    // A wrong scale scores worse.
    const auto wrong = compare::project_fold_lines(drape::fold_lines(p, solution), solution.folds,
                                                   compare::similarity_from_supports(s, 0.8 * p.support_span_m()));
    EXPECT_LT(compare::score_folds(wrong, detection, centre, map.px_per_m, 2.0).precision, score.precision);
}

TEST(OverlayCli, DrawsSameSizeAndRejectsSupportsOutside) {
    const auto dir = test::temp_dir();
    const std::string photo = test::quoted(test::test_data("photos/two_point_shirt_s5_half.jpg"));
    const std::string out = test::quoted(dir / "o.png");
    const std::string base = test::foldcast_binary() + " overlay " + photo + " -o " + out;
    EXPECT_EQ(test::run_command(base + " --supports 197.5,50,357.5,48.5 --width-m 0.5 --height-m 0.7 --inset-m 0.1")
                  .exit_code,
              0);
    const auto img = compare::read_image(dir / "o.png");
    EXPECT_EQ(img.width, 552);
    EXPECT_EQ(img.height, 311);
    const auto r = test::run_command(base + " --supports 197.5,50,900,48.5 --width-m 0.5 --height-m 0.7 2>&1");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.out.find("outside"), std::string::npos);
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1);  // one line
    EXPECT_EQ(test::run_command(base + " --supports 1,2,3 --width-m 0.5 --height-m 0.7 2>/dev/null").exit_code, 2);
    EXPECT_EQ(test::run_command(test::foldcast_binary() + " overlay missing.jpg -o " + out +
                                " --supports 1,2,30,4 --width-m 0.5 --height-m 0.7 2>/dev/null")
                  .exit_code,
              2);
}
