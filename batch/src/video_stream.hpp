#pragma once
// A turntable video that browsers play, encoded one frame at a time by Debian's ffmpeg
// (the command-line tool, fed raw frames through a pipe) into a registered temporary of an
// OutputTransaction: H.264 (libx264, yuv420p, BT.709, +faststart) in MP4, or VP9
// (libvpx-vp9) in WebM, chosen by the target's extension.  A turntable encodes each frame
// as soon as it is finished, on the thread that writes its PNG.
#include <opencv2/core.hpp>

#include <cstdio>
#include <filesystem>
#include <sys/types.h>

#include "foldcast/batch/turntable.hpp"
#include "foldcast/core/atomic_file.hpp"

namespace foldcast::batch {

class VideoStream {
public:
    // Throws InputError if `video` cannot be written or has another extension than .mp4 or
    // .webm; std::runtime_error if ffmpeg cannot be started.
    VideoStream(OutputTransaction& outputs, const std::filesystem::path& video, double fps, cv::Size size,
                const VideoOptions& options);
    ~VideoStream();
    VideoStream(const VideoStream&) = delete;
    VideoStream& operator=(const VideoStream&) = delete;
    // One 8-bit BGR frame of the stream's size (throws otherwise, or if ffmpeg failed).
    void add(const cv::Mat& bgr);
    // Finishes the file (throws with ffmpeg's message if it failed); the transaction's
    // commit() then moves it into place.
    void close();

private:
    [[noreturn]] void fail(const std::string& what);
    std::filesystem::path video_;
    cv::Size size_;
    int input_ = -1;  // our end of ffmpeg's standard input
    pid_t child_ = -1;
    std::FILE* log_ = nullptr;  // ffmpeg's standard error (an unlinked temporary)
};

}  // namespace foldcast::batch
