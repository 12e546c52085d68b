#include <opencv2/core/utils/logger.hpp>

#include "foldcast/compare/image.hpp"

namespace foldcast::compare {

// OpenCV (and FFmpeg, GStreamer and libpng below it, through OpenCV's logger) would print
// "[ WARN:0@0.02] ... findDecoder" or "[ERROR:0@0.33] ... Could not open codec" before our
// one line naming the problem: every caller reports failures itself.
void silence_library_logging() { cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT); }

}  // namespace foldcast::compare
