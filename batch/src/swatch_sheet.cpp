// Swatch sheet: one path-traced tile per look, all with the same drape geometry inputs,
// camera and lights, tiled with OpenCV and labelled with the look's name, its fold count and
// weight.
#include "foldcast/batch/swatches.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string_view>

#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/drape/drape.hpp"
#include "foldcast/core/math.hpp"

namespace foldcast::batch {

using render::CameraSpec;
using render::GarmentSpec;
using render::RenderOptions;
using render::RenderResult;
using render::SceneSpec;
namespace {

constexpr int kLabelHeight = 40;  // pixels under each tile for its two label lines

// One camera for every tile, fixed by the cloth size (not auto-framed per look, so tiles
// compare like for like): the cloth hangs from y = 0 down to about -height, the rod a little
// above; seen a little from the left and above, as in gallery/default.toml.
CameraSpec swatch_camera(const SwatchOptions& o, double aspect) {
    CameraSpec camera;
    camera.auto_frame = false;
    camera.fov_deg = 28.0;
    const double top_m = 0.16, bottom_m = -o.height_m - 0.03;  // rod and clips above y = 0
    const double half_height_m = 0.5 * (top_m - bottom_m) * 1.08;
    const double half_width_m = 0.5 * o.width_m * 1.15;
    const double tan_half = std::tan(0.5 * camera.fov_deg * kPi / 180.0);
    const double distance_m = std::max(half_height_m, half_width_m / aspect) / tan_half;
    const double azimuth = -18.0 * kPi / 180.0, elevation = 6.0 * kPi / 180.0;
    const Eigen::Vector3d target(0.0, 0.5 * (top_m + bottom_m), 0.0);
    const Eigen::Vector3d offset(std::sin(azimuth) * std::cos(elevation), std::sin(elevation),
                                 std::cos(azimuth) * std::cos(elevation));
    camera.target = target.cast<float>();
    camera.position = (target + distance_m * offset).cast<float>();
    return camera;
}

// Two lines under a tile; the font shrinks with narrow tiles so labels stay inside them.
void draw_label(cv::Mat& sheet, int x, int y, int tile_width, const std::string& line1, const std::string& line2) {
    const cv::Scalar ink(235, 235, 235), dim(170, 170, 170);
    const double scale = std::min(1.0, tile_width / 240.0);
    cv::putText(sheet, line1, {x + 6, y + 16}, cv::FONT_HERSHEY_SIMPLEX, 0.5 * scale, ink, 1, cv::LINE_AA);
    cv::putText(sheet, line2, {x + 6, y + 34}, cv::FONT_HERSHEY_SIMPLEX, 0.4 * scale, dim, 1, cv::LINE_AA);
}

}  // namespace

SwatchSheet render_swatch_sheet(const looks::Library& library, const SwatchOptions& options,
                                const ProgressFn& progress) {
    if (options.tile_width < 16 || options.tile_height < 16 || options.tile_width > 4096 || options.tile_height > 4096)
        throw InputError("swatch tile " + std::to_string(options.tile_width) + "x" +
                         std::to_string(options.tile_height) + ": each side must be 16 to 4096 pixels");
    if (options.spp < 1) throw InputError("swatch spp " + std::to_string(options.spp) + ": must be >= 1");
    if (!(options.noise_threshold >= 0.0) || !std::isfinite(options.noise_threshold))
        throw InputError("swatch noise threshold " + std::to_string(options.noise_threshold) +
                         ": must be a finite number >= 0");
    const std::vector<std::string> names = options.looks.empty() ? library.names() : options.looks;
    for (const auto& name : names) library.get(name);  // unknown names fail before any work
    const int count = static_cast<int>(names.size());
    int columns = options.columns;
    if (columns <= 0) {  // about twice as wide as tall, rows as full as possible: 12 -> 6 x 2
        const int rows = std::max(1, static_cast<int>(std::lround(std::sqrt(count / 2.0))));
        columns = (count + rows - 1) / rows;
    }
    columns = std::min(columns, count);
    const int rows = (count + columns - 1) / columns;

    SwatchSheet sheet;
    sheet.width = columns * options.tile_width;
    sheet.height = rows * (options.tile_height + kLabelHeight);
    cv::Mat canvas(sheet.height, sheet.width, CV_8UC3, cv::Scalar(38, 38, 38));  // BGR

    const double aspect = static_cast<double>(options.tile_width) / options.tile_height;
    for (int k = 0; k < count; ++k) {
        const looks::Look& look = library.get(names[static_cast<size_t>(k)]);
        SceneSpec scene;
        scene.look = look;
        scene.garment.source = GarmentSpec::Source::drape;
        scene.garment.width_m = options.width_m;
        scene.garment.height_m = options.height_m;
        scene.garment.inset_m = options.inset_m;
        scene.camera = swatch_camera(options, aspect);
        scene.width = options.tile_width;
        scene.height = options.tile_height;
        scene.spp = options.spp;
        scene.seed = options.seed;
        RenderOptions render_options;
        render_options.threads = options.threads;
        render_options.denoise = options.denoise;
        render_options.noise_threshold = options.noise_threshold;
        const ProgressFn tile_progress =
            progress ? ProgressFn([&, k](std::string_view, double f) { progress("swatches", (k + f) / count); })
                     : ProgressFn{};
        const RenderResult result = render::render_still(scene, render_options, tile_progress);

        const auto solution = drape::solve_folds(
            drape::cloth_from_look(look.mechanics, options.width_m, options.height_m, options.inset_m));
        sheet.tiles.push_back({look.name, solution.folds, look.mechanics.gsm});
        sheet.stats.rays += result.stats.rays;
        sheet.stats.seconds += result.stats.seconds;

        std::vector<std::uint8_t> rgb = render::to_srgb8(result.beauty, scene.exposure_ev, false);
        const cv::Mat tile_rgb(options.tile_height, options.tile_width, CV_8UC3, rgb.data());
        const int x = (k % columns) * options.tile_width;
        const int y = (k / columns) * (options.tile_height + kLabelHeight);
        cv::Mat target = canvas(cv::Rect(x, y, options.tile_width, options.tile_height));
        cv::cvtColor(tile_rgb, target, cv::COLOR_RGB2BGR);
        char detail[96];
        std::snprintf(detail, sizeof detail, "%d folds  %.0f g/m2  %s", solution.folds, look.mechanics.gsm,
                      looks::weave_name(look.appearance.weave));
        draw_label(canvas, x, y + options.tile_height, options.tile_width, look.name, detail);
    }
    sheet.stats.width = sheet.width;
    sheet.stats.height = sheet.height;
    sheet.stats.spp = options.spp;

    cv::Mat rgb;
    cv::cvtColor(canvas, rgb, cv::COLOR_BGR2RGB);
    sheet.rgb.assign(rgb.data, rgb.data + rgb.total() * rgb.elemSize());
    return sheet;
}

void write_swatch_sheet(const std::filesystem::path& png, const SwatchSheet& sheet) {
    std::string ext = png.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext != ".png") throw InputError("swatch sheet '" + png.string() + "': the file name must end in .png");
    check_writable(png);
    const cv::Mat rgb(sheet.height, sheet.width, CV_8UC3, const_cast<std::uint8_t*>(sheet.rgb.data()));
    cv::Mat bgr;
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
    std::vector<uchar> bytes;
    if (!cv::imencode(".png", bgr, bytes)) throw std::runtime_error("PNG encoding failed for " + png.string());
    write_file_atomically(png, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace foldcast::batch
