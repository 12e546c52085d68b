#include "mp4_stream.hpp"

#include <stdexcept>

#include "foldcast/core/error.hpp"

namespace foldcast::batch {

Mp4Stream::Mp4Stream(OutputTransaction& outputs, const std::filesystem::path& mp4, double fps, cv::Size size)
    : mp4_(mp4), size_(size) {
    check_writable(mp4);
    // A registered temporary of a unique name beside the target (removed on failure or interrupt).
    const std::filesystem::path temp = outputs.stage_file(mp4);
    writer_.open(temp.string(), cv::VideoWriter::fourcc('m', 'p', '4', 'v'), fps, size);
    if (!writer_.isOpened())
        throw std::runtime_error("cannot open an MP4 writer (OpenCV videoio, mp4v) for " + mp4.string());
}

void Mp4Stream::add(const cv::Mat& bgr) {
    if (bgr.size() != size_ || bgr.type() != CV_8UC3)
        throw std::logic_error("MP4 " + mp4_.string() + ": a frame of another size or type");
    writer_.write(bgr);
}

}  // namespace foldcast::batch
