#include <Eigen/Geometry>
#include "garment_surface.hpp"
#include "vec3_div.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "foldcast/core/error.hpp"
#include "foldcast/core/quiet_stderr.hpp"
#include "foldcast/looks/weave.hpp"
#include "foldcast/core/colour.hpp"

namespace foldcast::render {
namespace {

// Tiled bilinear lookup of a float image at texture coordinates st (1 = one tile).
V3 sample_tiled(const cv::Mat& img, float s, float t) {
    const float x = (s - std::floor(s)) * static_cast<float>(img.cols) - 0.5f;
    const float y = (t - std::floor(t)) * static_cast<float>(img.rows) - 0.5f;
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
    auto texel = [&](int xi, int yi) {
        xi = ((xi % img.cols) + img.cols) % img.cols;
        yi = ((yi % img.rows) + img.rows) % img.rows;
        const cv::Vec3f& p = img.at<cv::Vec3f>(yi, xi);
        return V3(p[2], p[1], p[0]);  // OpenCV stores BGR
    };
    return (1 - fy) * ((1 - fx) * texel(x0, y0) + fx * texel(x0 + 1, y0)) +
           fy * ((1 - fx) * texel(x0, y0 + 1) + fx * texel(x0 + 1, y0 + 1));
}

cv::Mat load_image(const std::filesystem::path& path, bool srgb) {
    cv::Mat raw;
    std::string why, library_said;
    {
        const QuietStderr quiet;  // libpng/libjpeg warnings become part of our one line
        try {
            raw = cv::imread(path.string(), cv::IMREAD_COLOR);
        } catch (const cv::Exception& e) {  // e.g. a header claiming more than 2^30 pixels
            raw.release();
            why = ": " + e.err;
        }
        library_said = quiet.first_line();
        if (raw.empty() && why.empty() && !library_said.empty()) why = ": " + library_said;
    }
    if (!raw.empty() && !library_said.empty())
        std::fprintf(stderr, "foldcast: warning: look texture %s: %s\n", path.c_str(), library_said.c_str());
    if (raw.empty())
        throw InputError("look texture " + path.string() + ": cannot be read as an image (PNG, JPEG, EXR...)" + why);
    cv::Mat f;
    raw.convertTo(f, CV_32FC3, 1.0 / 255.0);
    if (srgb)
        for (auto it = f.begin<cv::Vec3f>(); it != f.end<cv::Vec3f>(); ++it)
            for (int c = 0; c < 3; ++c) (*it)[c] = srgb_to_linear((*it)[c]);
    return f;
}

// The look's BSDF parameters other than the diffuse colour (GarmentShader::lobe_params).
BsdfParams look_lobe_params(const looks::Appearance& a) {
    BsdfParams p;
    p.sheen = a.sheen_colour.cwiseMax(0.0f).cwiseMin(1.0f);
    p.sheen_roughness = static_cast<float>(a.sheen_roughness);
    p.f0 = static_cast<float>(0.08 * a.specular);
    p.roughness = static_cast<float>(a.roughness);
    p.anisotropy = static_cast<float>(a.anisotropy);
    return p;
}

}  // namespace

struct GarmentShader::Images {
    cv::Mat colour;  // linear RGB (stored BGR), empty if none
    cv::Mat normal;  // tangent-space normal map in [0,1], empty if none
};

GarmentShader::GarmentShader(const looks::Appearance& appearance)
    : appearance_(appearance), lobe_params_(look_lobe_params(appearance)), images_(std::make_unique<Images>()) {
    if (!appearance_.texture.empty()) images_->colour = load_image(appearance_.texture, true);
    if (!appearance_.normal_map.empty()) images_->normal = load_image(appearance_.normal_map, false);
}

GarmentShader::~GarmentShader() = default;

GarmentSurface GarmentShader::shade(const Eigen::Vector2f& uv_m, float footprint_m) const {
    const looks::Appearance& a = appearance_;
    GarmentSurface s;
    V3 base = a.base_colour;
    const float tile_m = static_cast<float>(std::max(1e-6, a.repeat_mm * 1e-3));
    const float st_u = uv_m.x() / tile_m, st_v = uv_m.y() / tile_m;
    if (!images_->colour.empty()) base = sample_tiled(images_->colour, st_u, st_v);
    V3 n(0.0f, 0.0f, 1.0f);
    if (!images_->normal.empty()) {
        const V3 m = 2.0f * sample_tiled(images_->normal, st_u, st_v) - V3::Ones();
        n = V3(m.x() * static_cast<float>(a.bump_strength), m.y() * static_cast<float>(a.bump_strength),
               std::max(0.05f, m.z()));
    }
    bool along_weft = a.anisotropy_axis == looks::AnisotropyAxis::weft;
    if (a.weave != looks::Weave::none) {
        const looks::WeaveSample w = looks::sample_weave(a, uv_m.cast<double>(), footprint_m);
        // Without a texture the weave decides the colour: warp and weft (denim's ecru weft)
        // mixed by which shows here, times the yarn shading.
        base = images_->colour.empty() ? looks::weave_albedo(a, w) : V3(base * w.albedo_scale);
        n = V3(n.x() + w.normal.x(), n.y() + w.normal.y(), n.z() * w.normal.z());
        // The highlight stretches along whichever yarn lies on top here.
        if (w.yarn == 1) along_weft = false;
        if (w.yarn == 2) along_weft = true;
    }
    s.normal_ts = normalized3(n);
    s.anisotropy_along_weft = along_weft;
    s.bsdf = lobe_params_;
    s.bsdf.diffuse = base.cwiseMax(0.0f).cwiseMin(1.0f);
    return s;
}

}  // namespace foldcast::render
