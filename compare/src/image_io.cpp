#include <opencv2/imgcodecs.hpp>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <system_error>

#include "foldcast/core/atomic_file.hpp"
#include "foldcast/core/quiet_stderr.hpp"
#include "mat_convert.hpp"

namespace foldcast::compare {
namespace fs = std::filesystem;

Image read_image(const fs::path& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
        throw UnreadableImage("cannot read image '" + path.string() + "': no such file");
    cv::Mat raw;
    std::string why, library_said;
    {
        // libpng/libjpeg warnings and OpenCV's size assertion (a header claiming 100000 x
        // 100000) become one line of ours naming the file.
        const QuietStderr quiet;
        try {
            raw = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
        } catch (const cv::Exception& e) {
            raw.release();
            why = "; " + e.err;
        }
        library_said = quiet.first_line();
        if (raw.empty() && why.empty() && !library_said.empty()) why = "; " + library_said;
    }
    // Decoded despite a complaint (libjpeg fills a cut-short JPEG with grey): say so, once.
    if (!raw.empty() && !library_said.empty())
        std::fprintf(stderr, "foldcast: warning: image '%s': %s\n", path.c_str(), library_said.c_str());
    if (raw.empty())
        throw UnreadableImage("cannot read image '" + path.string() +
                              "': not an image OpenCV can decode (PNG, JPEG, TIFF, BMP, PPM, WebP) or larger than " +
                              "2^30 pixels, or truncated" + why);
    double scale = 1.0;
    switch (raw.depth()) {
        case CV_8U:
            scale = 1.0 / 255.0;
            break;
        case CV_16U:
            scale = 1.0 / 65535.0;
            break;
        case CV_32F:
            scale = 1.0;
            break;
        default:
            throw UnreadableImage("cannot read image '" + path.string() +
                                  "': unsupported sample type (8-bit, 16-bit or float only)");
    }
    cv::Mat values;
    raw.convertTo(values, CV_32F, scale);
    if (values.channels() == 3) cv::cvtColor(values, values, cv::COLOR_BGR2RGB);
    if (values.channels() == 4) cv::cvtColor(values, values, cv::COLOR_BGRA2RGBA);
    return detail::from_mat(values);
}

void write_image(const fs::path& path, const Image& image) {
    check_writable(path);
    cv::Mat values = detail::to_mat(image);
    if (values.channels() == 3) cv::cvtColor(values, values, cv::COLOR_RGB2BGR);
    if (values.channels() == 4) cv::cvtColor(values, values, cv::COLOR_RGBA2BGRA);
    cv::Mat bytes;
    values.convertTo(bytes, CV_8U, 255.0);  // saturating and rounding
    std::string ext = path.extension().string();
    if (ext.empty()) throw InputError("cannot write '" + path.string() + "': no extension (use .png)");
    std::vector<uchar> encoded;
    bool ok = false;
    try {
        ok = cv::imencode(ext, bytes, encoded);
    } catch (const cv::Exception&) {
        ok = false;
    }
    if (!ok)
        throw InputError("cannot write '" + path.string() + "': unsupported image extension '" + ext + "' (use .png)");
    write_file_atomically(path, std::string_view(reinterpret_cast<const char*>(encoded.data()), encoded.size()));
}

namespace detail {

cv::Mat to_mat(const Image& image) {
    cv::Mat header(image.height, image.width, CV_32FC(image.channels), const_cast<float*>(image.values.data()));
    return header.clone();
}

Image from_mat(const cv::Mat& mat) {
    cv::Mat f;
    if (mat.depth() == CV_32F)
        f = mat;
    else
        mat.convertTo(f, CV_32F);
    if (!f.isContinuous()) f = f.clone();
    Image image(f.cols, f.rows, f.channels());
    std::copy(f.ptr<float>(), f.ptr<float>() + image.values.size(), image.values.begin());
    return image;
}

cv::Mat rgb_of(const Image& image) {
    cv::Mat m = to_mat(image);
    if (image.channels == 1)
        cv::cvtColor(m, m, cv::COLOR_GRAY2RGB);
    else if (image.channels == 4)
        cv::cvtColor(m, m, cv::COLOR_RGBA2RGB);
    else if (image.channels == 2) {
        std::vector<cv::Mat> planes;
        cv::split(m, planes);
        cv::merge(std::vector<cv::Mat>{planes[0], planes[0], planes[0]}, m);
    } else if (image.channels > 4) {
        std::vector<cv::Mat> planes;
        cv::split(m, planes);
        cv::merge(std::vector<cv::Mat>{planes[0], planes[1], planes[2]}, m);
    }
    return m;
}

cv::Mat luma_of(const Image& image) {
    if (image.channels == 1 || image.channels == 2) {
        std::vector<cv::Mat> planes;
        cv::split(to_mat(image), planes);
        return planes[0];
    }
    cv::Mat rgb = rgb_of(image);
    cv::Mat luma;
    cv::transform(rgb, luma, cv::Matx13f(0.2126f, 0.7152f, 0.0722f));
    return luma;
}

cv::Mat to_bgr8(const Image& image) {
    cv::Mat rgb = rgb_of(image), bgr, bytes;
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
    bgr.convertTo(bytes, CV_8U, 255.0);
    return bytes;
}

Image from_bgr8(const cv::Mat& bgr) {
    cv::Mat rgb, values;
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    rgb.convertTo(values, CV_32F, 1.0 / 255.0);
    return from_mat(values);
}

}  // namespace detail
}  // namespace foldcast::compare
