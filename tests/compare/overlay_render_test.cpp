// Overlay geometry against a path-traced render (issue 6, item 6): the "photo" is
// tests/regression/scenes/front_drape.toml, a known drape (cotton poplin, 0.6 x 0.55 m, inset
// 0.08 m, 4 folds) under a known pinhole camera, straight on.  The supports are given to
// the overlay in pixels (render::project of the support points), as a user would click them,
// and the overlay's predicted lines must lie within 2 px of the folds in the render.
//
// "The folds in the render" are measured on the rendered geometry, not on its shading: the
// depth AOV gives, per pixel, the distance to what the camera sees, hence the cloth's z (out
// of the cloth plane) along each pixel column.  A fold line is where that z is extreme along
// the vertical fibre (a crest: z maximal, a valley: minimal), so each predicted line is
// checked against the extremum of the rendered z in its column.  Shading is not used because
// under a key light from above the brightest line sits beside a crest, not on it.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>
#include <filesystem>

#include "foldcast/compare/overlay.hpp"
#include "foldcast/drape/drape.hpp"
#include "foldcast/render/render.hpp"
#include "render_photo.hpp"

namespace foldcast {
namespace {

constexpr double kTolerancePx = 2.0;

struct RenderedDrape {
    render::SceneSpec scene;
    render::Camera camera;
    render::RenderResult result;
    const render::Image* depth = nullptr;
    drape::ClothParams params;
    drape::FoldSolution solution;
    compare::SupportPixels supports;
    compare::ClothToImage map;
    std::vector<compare::PredictedLine> lines;
};

// Where the camera sees a world point, in pixel-index coordinates (pixel (i, j) covers
// [i-0.5, i+0.5] x [j-0.5, j+0.5]: the convention of image viewers and of the overlay's
// drawing); render::project puts pixel centres at i+0.5.
Eigen::Vector2d seen_at(const RenderedDrape& r, const Eigen::Vector3d& point) {
    Eigen::Vector2d pixel;
    if (!render::project(r.camera, r.scene.width, r.scene.height, point.cast<float>(), &pixel))
        throw std::runtime_error("point behind the camera");
    return pixel - Eigen::Vector2d(0.5, 0.5);
}

// The scene, camera, model and overlay; `with_render` also path-traces the scene (once per
// process: CTest runs each test in its own).
RenderedDrape make_drape(bool with_render) {
    RenderedDrape r;
    r.scene =
        render::load_scene(std::filesystem::path(FOLDCAST_SOURCE_DIR) / "tests/regression/scenes/front_drape.toml");
    if (with_render) {
        render::RenderOptions options;
        options.aovs = {render::Aov::depth};
        r.result = render::render_still(r.scene, options);
        r.depth = &r.result.aovs.at(0).image;
    }
    r.camera = render::frame_camera(r.scene.camera, {}, double(r.scene.width) / r.scene.height);
    const auto& g = r.scene.garment;
    r.params = drape::cloth_from_look(r.scene.look.mechanics, g.width_m, g.height_m, g.inset_m);
    r.solution = drape::solve_folds(r.params);
    // The supports in pixels, where the camera sees them, as a user would click them.
    const double half_span = 0.5 * r.params.support_span_m();
    r.supports.first = seen_at(r, Eigen::Vector3d(-half_span, 0, 0));
    r.supports.second = seen_at(r, Eigen::Vector3d(half_span, 0, 0));
    // What `foldcast overlay --supports ... --width-m --height-m --inset-m` draws.
    r.map = compare::similarity_from_supports(r.supports, r.params.support_span_m());
    r.lines = compare::project_fold_lines(drape::fold_lines(r.params, r.solution, 513), r.solution.folds, r.map);
    return r;
}

const RenderedDrape& model_only() {
    static const RenderedDrape drape = make_drape(false);
    return drape;
}

const RenderedDrape& rendered_drape() {
    static const RenderedDrape drape = make_drape(true);
    return drape;
}

// The cloth's z at pixel centre (column, row) from the depth AOV (distance along the
// normalised camera ray, as render's CameraModel shoots it); false where the pixel is not
// wholly cloth (background, silhouette).
bool cloth_z(const RenderedDrape& r, int column, int row, double* z) {
    if (column < 0 || row < 0 || column >= r.scene.width || row >= r.scene.height) return false;
    if (r.result.beauty.at(column, row)[3] < 0.999f) return false;
    const double distance = r.depth->at(column, row)[0];
    const auto& c = r.camera;
    const Eigen::Vector3d forward = (c.target - c.position).cast<double>().normalized();
    const Eigen::Vector3d right = forward.cross(c.up.cast<double>()).normalized();
    const Eigen::Vector3d up = right.cross(forward);
    const double tan_y = std::tan(0.5 * c.fov_deg * std::numbers::pi / 180.0);
    const double tan_x = tan_y * r.scene.width / r.scene.height;
    const double sx = (2.0 * (column + 0.5) / r.scene.width - 1.0) * tan_x;
    const double sy = (1.0 - 2.0 * (row + 0.5) / r.scene.height) * tan_y;
    const Eigen::Vector3d dir = (forward + sx * right + sy * up).normalized();
    *z = c.position.z() + distance * dir.z();
    return true;
}

// Where the polyline crosses the vertical u (pixel x); false if it does not.
bool row_at(const compare::PredictedLine& line, double u, double* v) {
    for (size_t i = 1; i < line.points_px.size(); ++i) {
        const Eigen::Vector2d a = line.points_px[i - 1], b = line.points_px[i];
        if ((a.x() - u) * (b.x() - u) <= 0.0 && a.x() != b.x()) {
            *v = a.y() + (u - a.x()) / (b.x() - a.x()) * (b.y() - a.y());
            return true;
        }
    }
    return false;
}

double distance_to(const compare::PredictedLine& line, const Eigen::Vector2d& q) {
    double d = 1e300;
    for (size_t i = 1; i < line.points_px.size(); ++i) {
        const Eigen::Vector2d a = line.points_px[i - 1], b = line.points_px[i];
        const double t = std::clamp((q - a).dot(b - a) / std::max((b - a).squaredNorm(), 1e-12), 0.0, 1.0);
        d = std::min(d, (a + t * (b - a) - q).norm());
    }
    return d;
}

TEST(OverlayOnRender, SceneHasTheExpectedFoldsAndSupportsInFrame) {
    const auto& r = model_only();
    ASSERT_EQ(r.solution.folds, 4);
    EXPECT_EQ(r.scene.width, 320);
    EXPECT_NO_THROW(compare::validate_supports(r.supports, r.scene.width, r.scene.height));
    // Front-on and level: the supports project onto one image row, ~400 px/m apart.
    EXPECT_NEAR(r.supports.first.y(), r.supports.second.y(), 1e-6);
    EXPECT_NEAR(r.map.px_per_m, 400.0, 10.0);
}

TEST(OverlayOnRender, PredictedLinesMatchThePerspectiveProjectionOfTheFoldLines) {
    // The overlay maps the cloth plane by a similarity and drops z; the camera sees z in
    // perspective.  Straight on with a long lens the two agree within the tolerance.
    const auto& r = model_only();
    const auto lines3d = drape::fold_lines(r.params, r.solution, 513);
    ASSERT_EQ(lines3d.size(), r.lines.size());
    double worst = 0.0;
    for (size_t i = 0; i < lines3d.size(); ++i)
        for (size_t k = 0; k < lines3d[i].points.size(); ++k) {
            const Eigen::Vector2d seen = seen_at(r, lines3d[i].points[k]);
            worst = std::max(worst, (seen - r.lines[i].points_px[k]).norm());
        }
    std::printf("overlay (orthographic) vs perspective projection of the fold lines: max %.2f px\n", worst);
    EXPECT_LT(worst, kTolerancePx);
    EXPECT_GT(worst, 0.05);  // the overlay really is orthographic: this is not the same projection
}

// The rendered folds measured against a set of predicted lines, column by column.
struct FoldMatch {
    int checked = 0, crests = 0, valleys = 0, lowest = 0;
    int missed = 0;        // no extremum in the search window
    int wrong_height = 0;  // an extremum whose z is far from the model's
    double max_px = 0.0, sum_px = 0.0;
    std::string worst;
};

// Lowest fold: below it the cloth hangs straight at that fold's z (drape's surface), so z
// has a plateau, not a peak; the fold is where the bulge above meets it, tangentially.
// Least-squares fit of a hinge z = P - k min(row - r0, 0)^2 over the top of the bulge and
// the plateau; returns r0, or NaN without a bulge.
double hinge_row(const std::vector<double>& signed_z, int first, int fit_first) {
    const int last = first + int(signed_z.size()) - 1;
    double best_residual = 1e300, found = std::nan("");
    for (double r0 = fit_first + 2.0; r0 <= last - 2.0; r0 += 0.05) {
        Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
        Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
        for (int row = fit_first; row <= last; ++row) {
            const double d = std::min(row - r0, 0.0);
            const Eigen::Vector2d basis(1.0, -d * d);
            normal += basis * basis.transpose();
            rhs += basis * signed_z[size_t(row - first)];
        }
        const Eigen::Vector2d pk = normal.ldlt().solve(rhs);
        double residual = 0.0;
        for (int row = fit_first; row <= last; ++row) {
            const double d = std::min(row - r0, 0.0);
            residual += std::pow(signed_z[size_t(row - first)] - pk.x() + pk.y() * d * d, 2);
        }
        if (pk.y() > 0.0 && residual < best_residual) {
            best_residual = residual;
            found = r0;
        }
    }
    return found;
}

// For every pixel column in the middle 70 % between the supports (near them the lines
// converge onto the top edge) and every predicted fold line (not the top edge, which is the
// cloth's edge), looks for the rendered fold in that column near the line: the extremum of
// the cloth's z (max for a crest, min for a valley) within 0.45 x the gap to the
// neighbouring lines, sub-pixel by a parabola (the lowest fold: hinge_row).  The error is
// the distance from that point to the predicted polyline.
FoldMatch match_rendered_folds(const RenderedDrape& r, const std::vector<compare::PredictedLine>& lines) {
    FoldMatch m;
    const double u0 = std::min(r.supports.first.x(), r.supports.second.x());
    const double u1 = std::max(r.supports.first.x(), r.supports.second.x());
    for (int column = int(std::ceil(u0)); column < int(u1); ++column) {
        const double u = column;
        if (std::abs(u - 0.5 * (u0 + u1)) > 0.35 * (u1 - u0)) continue;
        std::vector<double> rows(lines.size());
        bool crossed = true;
        for (size_t i = 0; i < lines.size(); ++i) crossed &= row_at(lines[i], u, &rows[i]);
        if (!crossed) continue;
        for (size_t i = 0; i < lines.size(); ++i) {
            const auto& line = lines[i];
            if (line.top_edge) continue;
            double gap = 1e9;
            if (i > 0) gap = std::min(gap, std::abs(rows[i] - rows[i - 1]));
            if (i + 1 < rows.size()) gap = std::min(gap, std::abs(rows[i + 1] - rows[i]));
            if (gap < 8.0) continue;  // too close to tell apart at this resolution
            const double half = 0.45 * gap;
            const int first = int(std::floor(rows[i] - half)), last = int(std::ceil(rows[i] + half));
            std::vector<double> signed_z(size_t(last - first + 1), 0.0);
            int best = -1;
            double best_value = -1e9;
            bool inside = true;
            for (int row = first; row <= last && inside; ++row) {
                double z = 0.0;
                inside = cloth_z(r, column, row, &z);
                signed_z[size_t(row - first)] = line.sign * z;
                if (inside && line.sign * z > best_value) {
                    best_value = line.sign * z;
                    best = row;
                }
            }
            if (!inside) continue;  // the window touches the silhouette
            double found = std::nan("");
            if (line.index == 0) {
                found = hinge_row(signed_z, first, std::max(first, int(std::floor(rows[i] - 0.25 * gap))));
            } else if (best > first && best < last) {
                const double zm = signed_z[size_t(best - 1 - first)], zc = signed_z[size_t(best - first)],
                             zp = signed_z[size_t(best + 1 - first)];
                const double denominator = zm - 2.0 * zc + zp;
                found = best + (denominator < 0.0 ? 0.5 * (zm - zp) / denominator : 0.0);
            }
            ++m.checked;
            (line.sign > 0 ? m.crests : m.valleys)++;
            if (line.index == 0) ++m.lowest;
            if (std::isnan(found)) {
                ++m.missed;
                continue;
            }
            // A real fold, not noise: its z is near the model's +/- zmax c.
            const double c = std::cos(std::numbers::pi * (u - 0.5 * (u0 + u1)) / (u1 - u0));
            if (std::abs(best_value - r.solution.zmax_m * c) > 0.25 * r.solution.zmax_m) ++m.wrong_height;
            const double error = distance_to(line, Eigen::Vector2d(column, found));
            m.sum_px += error;
            if (error > m.max_px) {
                m.max_px = error;
                m.worst = "column " + std::to_string(column) + ", line " + std::to_string(line.index) +
                          ": predicted row " + std::to_string(rows[i]) + ", rendered fold at row " +
                          std::to_string(found);
            }
        }
    }
    return m;
}

TEST(OverlayOnRender, PredictedLinesLieOnTheRenderedFoldsWithinTwoPixelsAndAScaleErrorDoesNot) {
    const auto& r = rendered_drape();
    const FoldMatch m = match_rendered_folds(r, r.lines);
    std::printf(
        "overlay vs render: %d column crossings (%d crest, %d valley, %d on the lowest fold), "
        "mean %.2f px, max %.2f px (%s)\n",
        m.checked, m.crests, m.valleys, m.lowest, m.checked ? m.sum_px / m.checked : 0.0, m.max_px, m.worst.c_str());
    EXPECT_GT(m.crests, 100);
    EXPECT_GT(m.valleys, 100);
    EXPECT_GT(m.lowest, 50);
    EXPECT_EQ(m.missed, 0);
    EXPECT_EQ(m.wrong_height, 0);
    EXPECT_LT(m.max_px, kTolerancePx) << m.worst;

    // The check can fail: the overlay drawn for a support span 4 % too long (as if the inset
    // were misjudged by 7 mm) misses the rendered folds by more than 2 px.
    const auto wrong_map = compare::similarity_from_supports(r.supports, 1.04 * r.params.support_span_m());
    const auto wrong =
        compare::project_fold_lines(drape::fold_lines(r.params, r.solution, 513), r.solution.folds, wrong_map);
    const FoldMatch off = match_rendered_folds(r, wrong);
    std::printf("overlay with a 4 %% span error vs render: max %.2f px, mean %.2f px\n", off.max_px,
                off.checked ? off.sum_px / off.checked : 0.0);
    EXPECT_GT(off.max_px, kTolerancePx) << off.worst;
}

TEST(OverlayOnRender, DrawnCrestsLieOnTheirPredictedPixels) {
    // The picture the user sees: draw_overlay over the render, positive folds solid black.
    const auto& r = rendered_drape();
    const compare::Image photo = test::photo_of(r.result.beauty, r.scene.exposure_ev);
    const auto overlay = compare::draw_overlay(photo, r.lines, r.supports, {"test"});
    ASSERT_EQ(overlay.width, photo.width);
    int checked = 0, black = 0;
    // The legend box: what changed farther than the line and ring widths from every line
    // and support.
    const auto near_drawing = [&](int x, int y) {
        const Eigen::Vector2d q(x, y);
        if ((q - r.supports.first).norm() < 14 || (q - r.supports.second).norm() < 14) return true;
        for (const auto& line : r.lines)
            for (const auto& p : line.points_px)
                if ((q - p).norm() < 6) return true;
        return false;
    };
    int legend_x0 = photo.width, legend_y0 = photo.height, legend_x1 = -1, legend_y1 = -1;
    for (int y = 0; y < photo.height; ++y)
        for (int x = 0; x < photo.width; ++x) {
            bool changed = false;
            for (int c = 0; c < 3; ++c) changed |= std::abs(overlay.at(x, y, c) - photo.at(x, y, c)) > 1.5f / 255;
            if (!changed || near_drawing(x, y)) continue;
            legend_x0 = std::min(legend_x0, x), legend_x1 = std::max(legend_x1, x);
            legend_y0 = std::min(legend_y0, y), legend_y1 = std::max(legend_y1, y);
        }
    // It sits against a side of the picture, where it covers the least cloth.
    ASSERT_GE(legend_x1, 0);
    EXPECT_TRUE(legend_x0 < 16 || legend_x1 > photo.width - 17) << legend_x0 << ".." << legend_x1;
    const double middle = 0.5 * (r.supports.first.x() + r.supports.second.x());
    for (const auto& line : r.lines) {
        if (line.sign < 0 || line.top_edge) continue;
        for (size_t k = 0; k < line.points_px.size(); k += 4) {
            const Eigen::Vector2d p = line.points_px[k];
            if (p.x() > legend_x0 - 3 && p.x() < legend_x1 + 3 && p.y() > legend_y0 - 3 && p.y() < legend_y1 + 3)
                continue;  // under the legend
            // The middle of the cloth, where the lines are apart (near the supports they
            // converge and their halos cover each other).
            if (std::abs(p.x() - middle) > 0.35 * r.supports.distance_px()) continue;
            ++checked;
            float darkest = 1.0f;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int x = int(std::lround(p.x())) + dx, y = int(std::lround(p.y())) + dy;
                    darkest =
                        std::min(darkest, std::max({overlay.at(x, y, 0), overlay.at(x, y, 1), overlay.at(x, y, 2)}));
                }
            if (darkest < 0.05f) ++black;
        }
    }
    ASSERT_GT(checked, 50);
    EXPECT_EQ(black, checked);
}

// The detector against a render of the same drape with a printed texture (a white block
// letter and a yellow disc on navy, one tile over the whole cloth) under a uniform sky only:
// no key light, so a fold's crest sees more of the sky than its valley and the shading has
// its bright ridges on the crests and dark lines in the valleys (ambient occlusion), as in
// the overcast or diffuse light of many photos.  The truth: the model's fold lines, which
// the test above puts within 1 px of the rendered geometry.  The print's outlines: where the
// albedo AOV changes.
struct PrintedRender {
    render::RenderResult result;
    compare::Image photo;
    std::vector<bool> print_edge;  // per pixel: within 2 px of an albedo change
};

const PrintedRender& printed_render() {
    static const PrintedRender printed = [] {
        PrintedRender out;
        const auto& r = model_only();
        const auto dir = std::filesystem::path(FOLDCAST_BINARY_DIR) / "test-tmp" / "printed_render";
        std::filesystem::create_directories(dir);
        const int n = 240;
        compare::Image texture(n, n, 3);
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const double u = double(x) / n, v = double(y) / n;  // one tile = 0.6 m of cloth
                const bool stem = u > 0.20 && u < 0.26 && v > 0.15 && v < 0.65;
                const bool bars = u > 0.20 && u < 0.45 && ((v > 0.15 && v < 0.21) || (v > 0.37 && v < 0.43));
                const bool disc = std::hypot(u - 0.68, v - 0.45) < 0.12;
                const float navy[3] = {0.10f, 0.12f, 0.45f}, white[3] = {0.9f, 0.9f, 0.9f},
                            yellow[3] = {0.9f, 0.85f, 0.1f};
                const float* c = stem || bars ? white : disc ? yellow : navy;
                for (int k = 0; k < 3; ++k) texture.at(x, y, k) = c[k];
            }
        compare::write_image(dir / "print.png", texture);
        render::SceneSpec scene = r.scene;
        scene.look.appearance.texture = dir / "print.png";
        scene.look.appearance.weave = looks::Weave::none;
        scene.look.appearance.repeat_mm = 600.0;
        scene.look.appearance.sheen_colour.setZero();
        scene.look.appearance.specular = 0.0;
        scene.studio_preset = false;
        scene.lights.clear();
        scene.environment = Vec3f::Constant(1.0f);
        scene.spp = 32;
        render::RenderOptions options;
        options.aovs = {render::Aov::albedo};
        out.result = render::render_still(scene, options);
        out.photo = test::photo_of(out.result.beauty, scene.exposure_ev);
        const render::Image& albedo = out.result.aovs.at(0).image;
        out.print_edge.assign(size_t(scene.width) * scene.height, false);
        for (int y = 1; y + 1 < scene.height; ++y)
            for (int x = 1; x + 1 < scene.width; ++x) {
                double change = 0.0;
                for (int k = 0; k < 3; ++k)
                    change = std::max({change, double(std::abs(albedo.at(x + 1, y)[k] - albedo.at(x - 1, y)[k])),
                                       double(std::abs(albedo.at(x, y + 1)[k] - albedo.at(x, y - 1)[k]))});
                const bool cloth = out.result.beauty.at(x, y)[3] > 0.999f;
                if (change > 0.2 && cloth)
                    for (int dy = -2; dy <= 2; ++dy)
                        for (int dx = -2; dx <= 2; ++dx) {
                            const int xx = std::clamp(x + dx, 0, scene.width - 1),
                                      yy = std::clamp(y + dy, 0, scene.height - 1);
                            out.print_edge[size_t(yy) * scene.width + xx] = true;
                        }
            }
        return out;
    }();
    return printed;
}

TEST(DetectorOnRender, FindsThePrintedDrapesFoldsWithinTwoPixelsAndNoneOnThePrint) {
    const auto& r = model_only();
    const auto& printed = printed_render();
    const int w = r.scene.width, h = r.scene.height;
    compare::Image mask(w, h, 1);
    int print_edge_pixels = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            mask.at(x, y, 0) = printed.result.beauty.at(x, y)[3] > 0.5f ? 1.0f : 0.0f;
            print_edge_pixels += printed.print_edge[size_t(y) * w + x];
        }
    ASSERT_GT(print_edge_pixels, 300);            // the print is in the picture
    const compare::FoldDetectionOptions options;  // the defaults `foldcast folds` uses
    const auto detection = compare::detect_folds(printed.photo, mask, options);
    auto off_fold = [&](const Eigen::Vector2d& p) {
        double d = 1e9;
        for (const auto& line : r.lines)
            if (!line.top_edge) d = std::min(d, distance_to(line, p));
        return d;
    };
    double length = 0.0, worst = 0.0;
    std::vector<double> distances;
    int points = 0, on_print_edge = 0, far = 0;
    for (const auto& f : detection.folds)
        for (size_t i = 0; i < f.points_px.size(); ++i) {
            const Eigen::Vector2d& p = f.points_px[i];
            const double d = off_fold(p);
            worst = std::max(worst, d);
            distances.push_back(d);
            far += d > kTolerancePx;
            const int x = std::clamp(int(std::lround(p.x())), 0, w - 1),
                      y = std::clamp(int(std::lround(p.y())), 0, h - 1);
            on_print_edge += printed.print_edge[size_t(y) * w + x] && d > kTolerancePx;
            ++points;
            if (i > 0) length += (p - f.points_px[i - 1]).norm();
        }
    std::sort(distances.begin(), distances.end());
    const double median = distances.empty() ? 0.0 : distances[distances.size() / 2];
    std::printf(
        "detector on the printed render: %zu lines, %.0f px long, %d points, worst %.2f px from a fold, "
        "median %.2f px, %d farther than 2 px, %d on the print's outlines\n",
        detection.folds.size(), length, points, worst, median, far, on_print_edge);
    // Under a uniform sky the folds in the middle of the cloth shade softly: the default
    // thresholds find the strongest fold (beside the right support, ~75 px), not all of them.
    EXPECT_GT(length, 50.0);
    EXPECT_EQ(on_print_edge, 0);
    // The target: every point within 2 px of a fold.  Measured: worst 0.59 px,
    // median 0.20 px (docs/compare.md).  Before the band's centre: worst 2.73 px, 23 of 112
    // points beyond 2 px; with it but without cutting lines where their profile reads the
    // print's inpainted fill: worst 2.47 px, 2 beyond 2 px (a valley's end at the disc).
    EXPECT_LE(worst, kTolerancePx);
    EXPECT_LE(median, 0.5);
    EXPECT_EQ(far, 0);
    // The same picture without the print separation: the letter and disc come back as lines
    // (so the check above can fail).
    compare::FoldDetectionOptions keep = options;
    keep.exclude_prints = false;
    int on_print_kept = 0;
    for (const auto& f : compare::detect_folds(printed.photo, mask, keep).folds)
        for (const auto& p : f.points_px) {
            const int x = std::clamp(int(std::lround(p.x())), 0, w - 1),
                      y = std::clamp(int(std::lround(p.y())), 0, h - 1);
            on_print_kept += printed.print_edge[size_t(y) * w + x] && off_fold(p) > kTolerancePx;
        }
    std::printf("without the print separation: %d points on the print's outlines\n", on_print_kept);
    EXPECT_GT(on_print_kept, 10);
}

}  // namespace
}  // namespace foldcast
