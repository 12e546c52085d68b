// Writing renders: PNG (8-bit sRGB, OpenCV) and EXR (linear float, OpenEXR), atomically.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/error.hpp"
#include "foldcast/render/render.hpp"
#include "srgb_encode.hpp"

namespace foldcast::render {
namespace fs = std::filesystem;
namespace {

void write_png(OutputTransaction& outputs, const fs::path& path, const cv::Mat& bgr_or_bgra) {
    std::vector<std::uint8_t> bytes;
    if (!cv::imencode(".png", bgr_or_bgra, bytes)) throw std::runtime_error("PNG encoding failed for " + path.string());
    outputs.stage(path).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

// Channels named e.g. {"R","G","B","A"} or {"Y"}, interleaved float pixels.
void write_exr(OutputTransaction& outputs, const fs::path& path, const Image& img,
               const std::vector<std::string>& names) {
    std::ofstream& file = outputs.stage(path);
    {
        Imf::Header header(img.width, img.height);
        Imf::FrameBuffer fb;
        const std::size_t xs = sizeof(float) * static_cast<std::size_t>(img.channels);
        const std::size_t ys = xs * static_cast<std::size_t>(img.width);
        for (std::size_t c = 0; c < names.size(); ++c) {
            header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
            // OpenEXR's Slice takes a non-const base pointer but only reads when writing.
            fb.insert(names[c], Imf::Slice(Imf::FLOAT,
                                           reinterpret_cast<char*>(const_cast<float*>(img.pixels.data()) + c), xs, ys));
        }
        Imf::StdOFStream stream(file, path.c_str());
        Imf::OutputFile out(stream, header);
        out.setFrameBuffer(fb);
        out.writePixels(img.height);
    }
}

cv::Mat aov_to_png(Aov aov, const Image& img) {
    const int w = img.width, h = img.height;
    switch (aov) {
        case Aov::albedo: {
            cv::Mat m(h, w, CV_8UC3);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const float* p = img.at(x, y);
                    m.at<cv::Vec3b>(y, x) = cv::Vec3b(encode_srgb8(p[2]), encode_srgb8(p[1]), encode_srgb8(p[0]));
                }
            return m;
        }
        case Aov::normal: {
            cv::Mat m(h, w, CV_8UC3);
            auto enc = [](float v) {
                return static_cast<std::uint8_t>(std::lround(std::clamp(0.5f * v + 0.5f, 0.0f, 1.0f) * 255.0f));
            };
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const float* p = img.at(x, y);
                    m.at<cv::Vec3b>(y, x) = cv::Vec3b(enc(p[2]), enc(p[1]), enc(p[0]));
                }
            return m;
        }
        case Aov::depth: {  // 16-bit, near = bright, scaled to the farthest depth seen
            float far = 0.0f;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) far = std::max(far, *img.at(x, y));
            cv::Mat m(h, w, CV_16UC1);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const float d = *img.at(x, y);
                    m.at<std::uint16_t>(y, x) =
                        d > 0.0f && far > 0.0f ? static_cast<std::uint16_t>(std::lround((1.0f - d / far) * 65535.0f))
                                               : 0;
                }
            return m;
        }
        case Aov::fold: {  // positive folds red, negative blue, brightness = strength
            cv::Mat m(h, w, CV_8UC3);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const float f = std::clamp(*img.at(x, y), -1.0f, 1.0f);
                    const auto v = static_cast<std::uint8_t>(std::lround(std::abs(f) * 255.0f));
                    m.at<cv::Vec3b>(y, x) = f >= 0.0f ? cv::Vec3b(0, 0, v) : cv::Vec3b(v, 0, 0);
                }
            return m;
        }
    }
    return {};
}

// The beauty image (or the image before denoising) as PNG or EXR.
void write_beauty(OutputTransaction& outputs, const fs::path& path, const std::string& ext, const Image& img,
                  const SceneSpec& scene) {
    if (ext == ".png") {
        const bool alpha = scene.transparent;
        std::vector<std::uint8_t> px = to_srgb8(img, scene.exposure_ev, alpha);
        cv::Mat rgb(img.height, img.width, alpha ? CV_8UC4 : CV_8UC3, px.data());
        cv::Mat bgr;
        cv::cvtColor(rgb, bgr, alpha ? cv::COLOR_RGBA2BGRA : cv::COLOR_RGB2BGR);
        write_png(outputs, path, bgr);
    } else {
        Image scaled = img;
        const float gain = static_cast<float>(std::exp2(scene.exposure_ev));
        for (std::size_t i = 0; i < scaled.pixels.size(); ++i)
            if (i % 4 != 3) scaled.pixels[i] *= gain;
        write_exr(outputs, path, scaled, {"R", "G", "B", "A"});
    }
}

}  // namespace

std::vector<std::uint8_t> to_srgb8(const Image& rgba, double exposure_ev, bool keep_alpha) {
    const float gain = static_cast<float>(std::exp2(exposure_ev));
    const int out_ch = keep_alpha ? 4 : 3;
    std::vector<std::uint8_t> out(static_cast<std::size_t>(rgba.width) * rgba.height * out_ch);
    for (int y = 0; y < rgba.height; ++y)
        for (int x = 0; x < rgba.width; ++x) {
            const float* p = rgba.at(x, y);
            std::uint8_t* o = &out[(static_cast<std::size_t>(y) * rgba.width + x) * out_ch];
            for (int c = 0; c < 3; ++c) o[c] = encode_srgb8(p[c] * gain);
            if (keep_alpha) o[3] = static_cast<std::uint8_t>(std::lround(std::clamp(p[3], 0.0f, 1.0f) * 255.0f));
        }
    return out;
}

std::vector<fs::path> write_render(const fs::path& out, const RenderResult& result, const SceneSpec& scene) {
    OutputTransaction outputs;  // the beauty and its AOVs: all new or all old
    std::vector<fs::path> written = write_render(outputs, out, result, scene);
    outputs.commit();
    return written;
}

std::vector<fs::path> write_render(OutputTransaction& outputs, const fs::path& out, const RenderResult& result,
                                   const SceneSpec& scene) {
    std::string ext = out.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext != ".png" && ext != ".exr")
        throw InputError("render output '" + out.string() + "': the file name must end in .png or .exr");
    check_writable(out);
    std::vector<fs::path> written;
    write_beauty(outputs, out, ext, result.beauty, scene);
    written.push_back(out);
    if (result.raw) {
        fs::path path = out;
        path.replace_extension(".raw" + ext);
        write_beauty(outputs, path, ext, *result.raw, scene);
        written.push_back(path);
    }
    for (const AovImage& aov : result.aovs) {
        fs::path path = out;
        path.replace_extension(std::string(".") + aov_name(aov.aov) + ext);
        if (ext == ".png") {
            write_png(outputs, path, aov_to_png(aov.aov, aov.image));
        } else if (aov.image.channels == 3) {
            write_exr(outputs, path, aov.image, {"R", "G", "B"});
        } else {
            write_exr(outputs, path, aov.image, {"Y"});
        }
        written.push_back(path);
    }
    return written;
}

}  // namespace foldcast::render
