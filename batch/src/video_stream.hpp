#pragma once
// An MP4 (OpenCV videoio, mp4v) written one frame at a time into a registered temporary of
// an OutputTransaction: a turntable encodes each frame as soon as it is finished, on the
// thread that writes its PNG, instead of reading every PNG back after the last one.
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

#include <filesystem>

#include "foldcast/core/atomic_file.hpp"

namespace foldcast::batch {

class Mp4Stream {
public:
    // Throws if `mp4` cannot be written or no MP4 writer opens.
    Mp4Stream(OutputTransaction& outputs, const std::filesystem::path& mp4, double fps, cv::Size size);
    // One 8-bit BGR frame of the stream's size (throws otherwise).
    void add(const cv::Mat& bgr);
    // Finishes the file; the transaction's commit() then moves it into place.
    void close() { writer_.release(); }

private:
    std::filesystem::path mp4_;
    cv::Size size_;
    cv::VideoWriter writer_;
};

}  // namespace foldcast::batch
