#pragma once
// A small image type for compare's public API, so callers need no OpenCV headers.
#include <filesystem>
#include <string>
#include <vector>

#include "foldcast/core/error.hpp"

namespace foldcast::compare {

// Row-major, channels interleaved in R,G,B(,A) order (grey: 1 channel).  Values of 8- and
// 16-bit files are scaled to [0,1] (255 -> 1, 65535 -> 1), as idiff does; they stay in the
// file's encoding (sRGB for ordinary PNG/JPEG), nothing is linearised on reading.
struct Image {
    int width = 0;
    int height = 0;
    int channels = 0;
    std::vector<float> values;

    Image() = default;
    Image(int w, int h, int c) : width(w), height(h), channels(c), values(static_cast<size_t>(w) * h * c, 0.0f) {}
    float& at(int x, int y, int c) { return values[(static_cast<size_t>(y) * width + x) * channels + c]; }
    float at(int x, int y, int c) const { return values[(static_cast<size_t>(y) * width + x) * channels + c]; }
    bool empty() const { return values.empty(); }
};

// A file that does not exist or cannot be decoded as an image.  An InputError (exit 2 for
// most subcommands); `foldcast diff` maps it to idiff's exit 4.
class UnreadableImage : public InputError {
public:
    using InputError::InputError;
};

// Reads PNG, JPEG, TIFF, BMP, PPM/PGM, WebP (what OpenCV's imgcodecs decodes; 8 or 16 bit).
// Throws UnreadableImage naming the file.
Image read_image(const std::filesystem::path& path);

// Writes an 8-bit image (values clamped to [0,1], rounded) atomically; the format follows
// the extension (.png, .jpg, ...).  Throws InputError for an unwritable path or extension.
void write_image(const std::filesystem::path& path, const Image& image);

// Silences OpenCV's own log lines (warnings it prints before a failed call returns): the
// command line reports every failure in one line of its own.
void silence_library_logging();

}  // namespace foldcast::compare
