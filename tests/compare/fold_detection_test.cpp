// Fold detection on synthetic ridges of known position, and the cloth mask on a real photo.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "foldcast/core/math.hpp"
#include "foldcast/core/colour.hpp"

#include "test_paths.hpp"
#include "compare_test_util.hpp"
#include "foldcast/compare/folds.hpp"

using namespace foldcast;
using foldcast::test::constant_image;

namespace {

// Grey picture 0.5 + sum of Gaussian line profiles: amplitude > 0 bright crest, < 0 valley.
// `distance(x, y)` gives the signed distance to each line (pixels); lines fade out near
// their ends so that the ends are not artificial edges.
struct SyntheticLine {
    double amplitude;
    double width_px;
    std::function<double(double, double)> distance;
    double y_from, y_to;
};

compare::Image draw(int w, int h, const std::vector<SyntheticLine>& lines, double noise = 0.0) {
    compare::Image img = constant_image(w, h, 3, 0.5f);
    unsigned state = 12345u;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double v = 0.5;
            for (const auto& l : lines) {
                if (y < l.y_from || y > l.y_to) continue;
                const double d = l.distance(x, y);
                v += l.amplitude * std::exp(-d * d / (2 * l.width_px * l.width_px));
            }
            state = state * 1664525u + 1013904223u;
            v += noise * ((state >> 8) / 16777216.0 - 0.5) * 2.0;
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = static_cast<float>(v);
        }
    return img;
}

}  // namespace

TEST(FoldDetection, StraightCrestAndValleyFoundWithinOnePixel) {
    const double crest_x = 60.3, valley_x = 110.7;
    const auto img = draw(160, 120,
                          {{0.25, 2.5, [&](double x, double) { return x - crest_x; }, 10, 110},
                           {-0.25, 3.0, [&](double x, double) { return x - valley_x; }, 10, 110}},
                          0.01);
    const auto det = compare::detect_folds(img, constant_image(160, 120, 1, 1.0f));
    int crests = 0, valleys = 0;
    for (const auto& f : det.folds) {
        const double target = f.sign > 0 ? crest_x : valley_x;
        (f.sign > 0 ? crests : valleys)++;
        EXPECT_GT(f.length_px(), 60.0);
        for (const auto& p : f.points_px) ASSERT_NEAR(p.x(), target, 1.0) << "sign " << f.sign << " at y " << p.y();
    }
    EXPECT_EQ(crests, 1);
    EXPECT_EQ(valleys, 1);
}

TEST(FoldDetection, ValleyWithALighterFloorAndUnequalWallsFoundAtItsCentre) {
    // A valley band whose half-depth edges are x = 49 and x = 68 (centre 58.5): a gentle left
    // wall (0.7 to 0.3 over 6 px), a steep right wall (0.3 to 0.7 over 2 px), and a floor lit
    // in its middle (0.42 at x = 58, 0.3 at both feet).  The extremum and the ridge response
    // are pulled off the middle (the previous detector put the line at x = 60.8, towards the
    // steeper wall); the band's half-depth crossings are not.
    const double centre_x = 58.5;
    auto brightness = [](double x) {
        const double knots_x[] = {46, 52, 58, 67, 69}, knots_v[] = {0.7, 0.3, 0.42, 0.3, 0.7};
        if (x <= knots_x[0]) return knots_v[0];
        for (int k = 0; k < 4; ++k)
            if (x <= knots_x[k + 1])
                return knots_v[k] + (knots_v[k + 1] - knots_v[k]) * (x - knots_x[k]) / (knots_x[k + 1] - knots_x[k]);
        return knots_v[4];
    };
    compare::Image img = constant_image(120, 80, 3, 0.5f);
    for (int y = 0; y < 80; ++y)
        for (int x = 0; x < 120; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = static_cast<float>(brightness(x));
    const auto det = compare::detect_folds(img, constant_image(120, 80, 1, 1.0f));
    double valley_length = 0.0;
    for (const auto& f : det.folds) {
        if (f.sign > 0) continue;
        valley_length += f.length_px();
        for (const auto& p : f.points_px) EXPECT_NEAR(p.x(), centre_x, 1.0) << "at y " << p.y();
    }
    EXPECT_GT(valley_length, 40.0);
}

TEST(FoldDetection, CurvedFoldLineFollowedWithinOneAndAHalfPixels) {
    // A sagging fold line like drape's: y = 40 + 30 cos(pi (x - 100) / 160) for x in [30, 170].
    auto curve_y = [](double x) { return 40.0 + 30.0 * std::cos(kPi * (x - 100.0) / 160.0); };
    auto distance = [&](double x, double y) {
        // Vertical offset scaled by the curve's slope gives the normal distance to first order.
        const double slope = -30.0 * kPi / 160.0 * std::sin(kPi * (x - 100.0) / 160.0);
        return (y - curve_y(x)) / std::sqrt(1.0 + slope * slope);
    };
    const auto img = draw(200, 100, {{-0.3, 2.0, distance, 0, 99}}, 0.01);
    compare::Image mask = constant_image(200, 100, 1, 0.0f);
    for (int y = 0; y < 100; ++y)
        for (int x = 30; x <= 170; ++x) mask.at(x, y, 0) = 1.0f;
    const auto det = compare::detect_folds(img, mask);
    ASSERT_EQ(det.folds.size(), 1u);
    const auto& f = det.folds[0];
    EXPECT_EQ(f.sign, -1);
    EXPECT_GT(f.length_px(), 100.0);  // most of the 140 px wide band (minus the border margin)
    for (const auto& p : f.points_px) ASSERT_NEAR(distance(p.x(), p.y()), 0.0, 1.5) << "at x " << p.x();
}

TEST(FoldDetection, FlatNoisyClothHasNoFoldsAndMaskIsRespected) {
    const auto flat = draw(120, 90, {}, 0.02);
    EXPECT_TRUE(compare::detect_folds(flat, constant_image(120, 90, 1, 1.0f)).folds.empty());
    // A strong crest outside the mask is ignored.
    const auto img = draw(120, 90, {{0.3, 2.0, [](double x, double) { return x - 30.0; }, 5, 85}});
    compare::Image right_half = constant_image(120, 90, 1, 0.0f);
    for (int y = 0; y < 90; ++y)
        for (int x = 60; x < 120; ++x) right_half.at(x, y, 0) = 1.0f;
    EXPECT_TRUE(compare::detect_folds(img, right_half).folds.empty());
    EXPECT_EQ(compare::detect_folds(img, constant_image(120, 90, 1, 1.0f)).folds.size(), 1u);
}

TEST(FoldDetection, ShortLinesAreDropped) {
    const auto img = draw(120, 90, {{0.3, 2.0, [](double x, double) { return x - 60.0; }, 40, 50}});
    compare::FoldDetectionOptions options;
    options.min_length_px = 30.0;
    EXPECT_TRUE(compare::detect_folds(img, constant_image(120, 90, 1, 1.0f), options).folds.empty());
}

TEST(ClothMask, GrabCutSeparatesTheShirtFromTableAndRobot) {
    // Half-size copy of two_point_shirt_s5.jpg (tests/data/photos/SOURCES.md).
    const auto photo = compare::read_image(test::test_data("photos/two_point_shirt_s5_half.jpg"));
    const compare::SupportPixels supports{{197.5, 50.0}, {357.5, 48.5}};
    const auto mask = compare::estimate_cloth_mask(photo, supports);
    EXPECT_EQ(mask.at(280, 100, 0), 1.0f);  // shirt, below the supports' midpoint
    EXPECT_EQ(mask.at(230, 150, 0), 1.0f);  // shirt, lower left
    EXPECT_EQ(mask.at(280, 260, 0), 0.0f);  // wooden table
    EXPECT_EQ(mask.at(180, 160, 0), 0.0f);  // robot arm
    EXPECT_EQ(mask.at(40, 40, 0), 0.0f);    // wall
    double covered = 0;
    for (float v : mask.values) covered += v;
    EXPECT_GT(covered, 0.10 * photo.width * photo.height);
    EXPECT_LT(covered, 0.30 * photo.width * photo.height);
}

// A cloth held at two points with a deep swag between them, hung in front of a light wall
// under a wooden rail that runs just above the supports (as in a workshop): between the
// supports, below their line, the wall shows down to the swag.  The seed must be the cloth
// below the swag, not that wall (which differs from the rail above the line as the cloth
// does); a seed on the wall made the mask the wall between the supports.  Returns the mask's
// IoU with the cloth, after checking a point of each.
double swag_under_rail_iou(const float cloth_colour[3]) {
    const int w = 240, h = 200;
    const float rail[3] = {0.35f, 0.22f, 0.12f}, wall[3] = {0.70f, 0.70f, 0.68f};
    const auto cloth = [](double x, double y) {
        if (y < 40 || y > 190) return false;
        const double left = 80 - 20 * (y - 40) / 150, right = 160 + 20 * (y - 40) / 150;  // the sides
        const double swag = 40 + 50 * (1 - std::abs(x - 120) / 40);                       // the top edge's V
        return x >= left && x <= right && y >= swag;
    };
    compare::Image img(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float* c = cloth(x, y) ? cloth_colour : (y < 30 ? rail : wall);
            const float shade = cloth(x, y) ? float(0.8 + 0.2 * std::cos((x - 120) / 12.0)) : 1.0f;
            for (int k = 0; k < 3; ++k) img.at(x, y, k) = linear_to_srgb(c[k] * shade);
        }
    const auto mask = compare::estimate_cloth_mask(img, compare::SupportPixels{{80, 40}, {160, 40}});
    EXPECT_EQ(mask.at(120, 60, 0), 0.0f);   // wall between the supports, above the swag
    EXPECT_EQ(mask.at(120, 150, 0), 1.0f);  // cloth below the swag
    double both = 0, either = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool truth = cloth(x, y), got = mask.at(x, y, 0) > 0.5f;
            both += truth && got, either += truth || got;
        }
    return both / either;
}

TEST(ClothMask, ADeepSwagUnderARailSeedsOnTheClothNotTheWallBetweenTheSupports) {
    const float red[3] = {0.50f, 0.05f, 0.04f};
    EXPECT_GT(swag_under_rail_iou(red), 0.85);
}

// The same with a grey cloth, which differs from the white wall by lightness alone.
TEST(ClothMask, ADeepSwagOfGreyClothUnderARailSeedsOnTheCloth) {
    const float grey[3] = {0.20f, 0.20f, 0.21f};
    EXPECT_GT(swag_under_rail_iou(grey), 0.85);
}

TEST(ClothMask, SupportsOutsideOnTopOfEachOtherOrNotFiniteAreRejected) {
    const auto photo = constant_image(50, 40, 3, 0.5f);
    EXPECT_THROW(compare::estimate_cloth_mask(photo, compare::SupportPixels{{10, 10}, {60, 10}}), InputError);
    EXPECT_THROW(compare::validate_supports({{10, 10}, {10.5, 10}}, 50, 40), InputError);
    EXPECT_THROW(compare::validate_supports({{10, 10}, {NAN, 10}}, 50, 40), InputError);
    EXPECT_NO_THROW(compare::validate_supports({{10, 10}, {40, 10}}, 50, 40));
    try {
        compare::validate_supports({{10, 10}, {10, 10}}, 50, 40);
        FAIL();
    } catch (const InputError& e) {
        // The library names its own parameter, not a command-line flag.
        EXPECT_EQ(std::string(e.what()).rfind("supports:", 0), 0u) << e.what();
    }
}

TEST(FoldDetection, EmptyMaskAndInvalidOptionsAreRejected) {
    const auto img = draw(60, 40, {});
    EXPECT_THROW(compare::detect_folds(img, constant_image(60, 40, 1, 0.0f)), InputError);
    EXPECT_THROW(compare::detect_folds(img, constant_image(61, 40, 1, 1.0f)), InputError);
    for (double bad : {-1.0, double(NAN), double(INFINITY)}) {
        compare::FoldDetectionOptions o;
        o.min_length_px = bad;
        EXPECT_THROW(compare::detect_folds(img, constant_image(60, 40, 1, 1.0f), o), InputError) << bad;
    }
}

// Navy cloth (linear RGB 0.03, 0.04, 0.25) shaded by one horizontal crest, with a printed
// block letter "E" in white and a yellow disc: prints change the colour, the fold only the
// brightness.
compare::Image printed_cloth(double crest_y, bool with_print) {
    const int w = 200, h = 160;
    compare::Image img(w, h, 3);
    const float navy[3] = {0.03f, 0.04f, 0.25f}, white[3] = {0.8f, 0.8f, 0.8f}, yellow[3] = {0.8f, 0.75f, 0.05f};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double d = y - crest_y;
            const double shade = 0.7 + 0.5 * std::exp(-d * d / (2 * 3.0 * 3.0));
            const float* albedo = navy;
            if (with_print) {
                const bool stem = x >= 30 && x < 40 && y >= 20 && y < 130;
                const bool bars =
                    x >= 30 && x < 80 && ((y >= 20 && y < 30) || (y >= 70 && y < 80) || (y >= 120 && y < 130));
                if (stem || bars) albedo = white;
                if (std::hypot(x - 140, y - 100) < 25) albedo = yellow;
            }
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = linear_to_srgb(std::min(1.0f, float(albedo[c] * shade)));
        }
    return img;
}

TEST(FoldDetection, PrintsAreNotFoldsButTheFoldIsFound) {
    const double crest_y = 50.3;
    const auto img = printed_cloth(crest_y, true);
    const auto mask = constant_image(img.width, img.height, 1, 1.0f);
    const auto det = compare::detect_folds(img, mask);
    // On the print: inside a letter or the disc, or within 3 px of their outlines.
    auto on_print = [](const Eigen::Vector2d& p) {
        auto inside = [](double x, double y) {
            const bool stem = x >= 30 && x < 40 && y >= 20 && y < 130;
            const bool bars =
                x >= 30 && x < 80 && ((y >= 20 && y < 30) || (y >= 70 && y < 80) || (y >= 120 && y < 130));
            return stem || bars || std::hypot(x - 140, y - 100) < 25;
        };
        for (double dy = -3; dy <= 3; dy += 1)
            for (double dx = -3; dx <= 3; dx += 1)
                if (inside(p.x() + dx, p.y() + dy)) return true;
        return false;
    };
    double crest_length = 0.0;
    for (const auto& f : det.folds)
        for (size_t i = 0; i < f.points_px.size(); ++i) {
            // Every point on the fold (the only one); where it passes beside the letter's stem
            // it is still the fold, anywhere else on the print it would be a print's line.
            const auto& p = f.points_px[i];
            EXPECT_NEAR(p.y(), crest_y, 2.0) << "line point off the fold at " << p.transpose();
            if (i > 0 && f.sign > 0) crest_length += (p - f.points_px[i - 1]).norm();
        }
    EXPECT_GT(crest_length, 100.0);  // the crest is found beside and between the prints
    // The print mask covers the letter and the disc, not the plain cloth.
    EXPECT_EQ(det.print_mask.at(35, 100, 0), 1.0f);
    EXPECT_EQ(det.print_mask.at(140, 100, 0), 1.0f);
    EXPECT_EQ(det.print_mask.at(110, 140, 0), 0.0f);
    // Without the separation the letter's strokes come back as lines: the check can fail.
    compare::FoldDetectionOptions keep;
    keep.exclude_prints = false;
    int on_edges = 0;
    for (const auto& f : compare::detect_folds(img, mask, keep).folds)
        for (const auto& p : f.points_px) on_edges += on_print(p) && std::abs(p.y() - crest_y) > 2.0;
    EXPECT_GT(on_edges, 50);
}

// Sheen against a pale print of the same colour.  Navy cloth with one crest whose top carries
// a highlight: the light's white added to the cloth's colour, fading over ~6 px either side as
// velvet's or satin's sheen does; or, with `print`, a band of the highlight's peak colour with
// sharp edges where the highlight would be.  Both lie on the segment from the cloth's
// chromaticity to white; only the print's colour jumps at its outline.
compare::Image sheen_or_print(double crest_y, bool print) {
    const int w = 200, h = 120;
    compare::Image img(w, h, 3);
    const float navy[3] = {0.03f, 0.04f, 0.25f};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double d = y - crest_y;
            const double shade = 0.7 + 0.5 * std::exp(-d * d / (2 * 3.0 * 3.0));
            const double white = print ? (std::abs(d) < 8.0 ? 0.3 : 0.0) : 0.3 * std::exp(-d * d / (2 * 6.0 * 6.0));
            for (int c = 0; c < 3; ++c)
                img.at(x, y, c) = linear_to_srgb(std::min(1.0f, float(navy[c] * shade + white)));
        }
    return img;
}

TEST(FoldDetection, SheenIsShadingNotPrintButAPaleBandWithSharpEdgesIsPrint) {
    const double crest_y = 60.3;
    const auto mask = constant_image(200, 120, 1, 1.0f);
    const auto sheen = compare::detect_folds(sheen_or_print(crest_y, false), mask);
    EXPECT_EQ(sheen.print_mask.at(100, 60, 0), 0.0f);
    double crest_length = 0.0;
    for (const auto& f : sheen.folds)
        for (size_t i = 1; i < f.points_px.size(); ++i)
            if (f.sign > 0 && std::abs(f.points_px[i].y() - crest_y) < 2.0)
                crest_length += (f.points_px[i] - f.points_px[i - 1]).norm();
    EXPECT_GT(crest_length, 100.0);  // the highlit crest is read as the fold it is
    const auto band = compare::detect_folds(sheen_or_print(crest_y, true), mask);
    EXPECT_EQ(band.print_mask.at(100, 60, 0), 1.0f);
}

// A fold that crosses a print shades the print too: the crest through the yellow disc (and
// past the letter's stem) is found inside the disc, where the print of one colour is
// scaled to the cloth's brightness, and the disc's outline is still no line.  (Before, the
// whole print was filled in and left out: no point inside the disc.)
TEST(FoldDetection, AFoldThroughAPrintIsFoundInsideIt) {
    const double crest_y = 100.3;  // through the disc's centre (140, 100), radius 25
    const auto img = printed_cloth(crest_y, true);
    const auto mask = constant_image(img.width, img.height, 1, 1.0f);
    const auto det = compare::detect_folds(img, mask);
    double inside_disc = 0.0;
    for (const auto& f : det.folds)
        for (size_t i = 0; i < f.points_px.size(); ++i) {
            const auto& p = f.points_px[i];
            EXPECT_NEAR(p.y(), crest_y, 2.0) << "line point off the fold at " << p.transpose();
            if (i > 0 && f.sign > 0 && std::hypot(p.x() - 140, p.y() - 100) < 20)
                inside_disc += (p - f.points_px[i - 1]).norm();
        }
    EXPECT_GT(inside_disc, 25.0);
    // The print is still known as print, and its outline is what cannot be read.
    EXPECT_EQ(det.print_mask.at(140, 100, 0), 1.0f);
    EXPECT_EQ(det.print_outline.at(140, 100, 0), 0.0f);
    EXPECT_EQ(det.print_outline.at(140, 75, 0), 1.0f);
    EXPECT_EQ(det.print_outline.at(110, 140, 0), 0.0f);
}

// A print of two colours: a white vertical bar across the middle of a large yellow disc on
// navy, and a valley through both.  Each colour is scaled on its own; the valley is found
// in the yellow on both sides of the bar, every point within 2 px of it (nothing along the
// bar's or the disc's outlines, which run across the valley); only where the colours meet
// is the shading not read.
TEST(FoldDetection, AFoldThroughATwoColourPrintIsFoundOnBothSidesOfTheInnerPrint) {
    const int w = 240, h = 200;
    const double valley_y = 99.6;
    compare::Image img(w, h, 3);
    const float navy[3] = {0.03f, 0.04f, 0.25f}, white[3] = {0.8f, 0.8f, 0.8f}, yellow[3] = {0.8f, 0.75f, 0.05f};
    auto albedo_at = [&](double x, double y) {
        if (std::hypot(x - 120, y - 100) >= 70) return navy;
        return std::abs(x - 120) < 8 ? white : yellow;
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double d = y - valley_y;
            const double shade = 0.9 - 0.4 * std::exp(-d * d / (2 * 3.0 * 3.0));
            const float* albedo = albedo_at(x, y);
            for (int c = 0; c < 3; ++c) img.at(x, y, c) = linear_to_srgb(std::min(1.0f, float(albedo[c] * shade)));
        }
    const auto det = compare::detect_folds(img, constant_image(w, h, 1, 1.0f));
    double left = 0.0, right = 0.0;
    for (const auto& f : det.folds)
        for (size_t i = 0; i < f.points_px.size(); ++i) {
            const auto& p = f.points_px[i];
            EXPECT_NEAR(p.y(), valley_y, 2.0) << "line point off the valley at " << p.transpose();
            if (i == 0 || f.sign > 0) continue;
            const double step = (p - f.points_px[i - 1]).norm();
            if (p.x() > 60 && p.x() < 105) left += step;
            if (p.x() > 135 && p.x() < 180) right += step;
        }
    EXPECT_GT(left, 20.0);
    EXPECT_GT(right, 20.0);
    EXPECT_EQ(det.print_outline.at(90, 100, 0), 0.0f);   // yellow: readable
    EXPECT_EQ(det.print_outline.at(120, 100, 0), 0.0f);  // the white bar's middle (16 px wide): readable
    EXPECT_EQ(det.print_outline.at(112, 100, 0), 1.0f);  // where white meets yellow: not
}
