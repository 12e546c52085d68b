#include "weave_bake.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "foldcast/core/colour.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/looks/weave.hpp"

namespace foldcast::gltf {

namespace {
// Yarns along each side of a baked tile: at least this many, so that a tile spans several
// weave repeats and the texture's pixels are a fraction of a yarn (16 px per yarn at 256 px).
constexpr int kTileYarnsAtLeast = 16;

cv::Mat read_image(const std::filesystem::path& path, const char* what) {
    cv::Mat image;
    try {
        image = cv::imread(path.string(), cv::IMREAD_COLOR);
    } catch (const cv::Exception&) {
        image.release();
    }
    if (image.empty())
        throw InputError(std::string(what) + " " + path.string() + ": cannot be read as an image (PNG, JPEG, EXR...)");
    cv::Mat f;
    image.convertTo(f, CV_32FC3, image.depth() == CV_8U ? 1.0 / 255.0 : image.depth() == CV_16U ? 1.0 / 65535.0 : 1.0);
    return f;
}

// Bilinear, wrapping; st in tiles.  Returns RGB (OpenCV holds BGR).
Eigen::Vector3f sample_tiled(const cv::Mat& img, double s, double t) {
    const double x = (s - std::floor(s)) * img.cols - 0.5, y = (t - std::floor(t)) * img.rows - 0.5;
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
    const auto texel = [&](int xi, int yi) {
        xi = ((xi % img.cols) + img.cols) % img.cols;
        yi = ((yi % img.rows) + img.rows) % img.rows;
        const cv::Vec3f& p = img.at<cv::Vec3f>(yi, xi);
        return Eigen::Vector3f(p[2], p[1], p[0]);
    };
    return (1 - fy) * ((1 - fx) * texel(x0, y0) + fx * texel(x0 + 1, y0)) +
           fy * ((1 - fx) * texel(x0, y0 + 1) + fx * texel(x0 + 1, y0 + 1));
}

std::uint8_t unorm8(float v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

std::string png(const cv::Mat& bgr) {
    std::vector<unsigned char> bytes;
    cv::imencode(".png", bgr, bytes);
    return {bytes.begin(), bytes.end()};
}
}  // namespace

bool has_pattern(const looks::Appearance& a) {
    return (a.weave != looks::Weave::none && a.repeat_mm > 0.0) || !a.texture.empty() || !a.normal_map.empty();
}

BakedWeave bake_weave(const looks::Appearance& a, int px) {
    cv::Mat texture, normal_map;
    if (!a.texture.empty()) texture = read_image(a.texture, "look texture");
    if (!a.normal_map.empty()) normal_map = read_image(a.normal_map, "look normal map");
    for (auto it = texture.begin<cv::Vec3f>(); it != texture.end<cv::Vec3f>(); ++it)
        for (int c = 0; c < 3; ++c) (*it)[c] = srgb_to_linear((*it)[c]);

    const Eigen::Vector2i period = looks::weave_period_yarns(a);
    const double pitch_m = std::max(1e-6, a.repeat_mm * 1e-3);
    const auto tile_yarns = [](int p) { return p * ((kTileYarnsAtLeast + p - 1) / p); };
    BakedWeave baked;
    baked.tile_m = {tile_yarns(period.x()) * pitch_m, tile_yarns(period.y()) * pitch_m};
    const double footprint_m = std::max(baked.tile_m.x(), baked.tile_m.y()) / px;

    cv::Mat colour(px, px, CV_8UC3), normal(px, px, CV_8UC3), anisotropy(px, px, CV_8UC3);
    for (int row = 0; row < px; ++row)
        for (int col = 0; col < px; ++col) {
            // glTF's texture coordinates start at the image's top left, v down the rows.
            const Eigen::Vector2d uv_m((col + 0.5) / px * baked.tile_m.x(), (row + 0.5) / px * baked.tile_m.y());
            Eigen::Vector3f base = a.base_colour;
            if (!texture.empty()) base = sample_tiled(texture, uv_m.x() / pitch_m, uv_m.y() / pitch_m);
            Eigen::Vector3f n(0.0f, 0.0f, 1.0f);
            if (!normal_map.empty()) {
                const Eigen::Vector3f m =
                    2.0f * sample_tiled(normal_map, uv_m.x() / pitch_m, uv_m.y() / pitch_m) - Eigen::Vector3f::Ones();
                const float bump = static_cast<float>(a.bump_strength);
                n = Eigen::Vector3f(m.x() * bump, m.y() * bump, std::max(0.05f, m.z()));
            }
            bool along_weft = a.anisotropy_axis == looks::AnisotropyAxis::weft;
            if (a.weave != looks::Weave::none) {
                const looks::WeaveSample w = looks::sample_weave(a, uv_m, footprint_m);
                base = texture.empty() ? looks::weave_albedo(a, w) : Eigen::Vector3f(base * w.albedo_scale);
                n = Eigen::Vector3f(n.x() + w.normal.x(), n.y() + w.normal.y(), n.z() * w.normal.z());
                if (w.yarn == 1) along_weft = false;
                if (w.yarn == 2) along_weft = true;
            }
            n.normalize();
            // Our tangent frame has y along +v; glTF's normal maps have +Y towards the image's
            // top, -v (the mesh's TANGENT w makes the bitangent -v to match).
            colour.at<cv::Vec3b>(row, col) = {unorm8(linear_to_srgb(base.z())), unorm8(linear_to_srgb(base.y())),
                                              unorm8(linear_to_srgb(base.x()))};
            normal.at<cv::Vec3b>(row, col) = {unorm8(0.5f * n.z() + 0.5f), unorm8(0.5f * -n.y() + 0.5f),
                                              unorm8(0.5f * n.x() + 0.5f)};
            // Direction in (tangent, bitangent) as (r, g) in [-1, 1] -> [0, 1]; blue: strength.
            anisotropy.at<cv::Vec3b>(row, col) = along_weft ? cv::Vec3b{255, 255, 128} : cv::Vec3b{255, 128, 255};
        }
    baked.colour_png = png(colour);
    baked.normal_png = png(normal);
    baked.anisotropy_png = png(anisotropy);
    return baked;
}

}  // namespace foldcast::gltf
