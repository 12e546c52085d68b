#pragma once
// Conversions between the public Image type and OpenCV matrices (private to compare).
#include <opencv2/core.hpp>

#include "foldcast/compare/image.hpp"

namespace foldcast::compare::detail {

// CV_32FC(channels), same channel order as the Image (R,G,B,...).
cv::Mat to_mat(const Image& image);
Image from_mat(const cv::Mat& mat);  // any float matrix, channel order kept

// Three-channel float RGB: grey replicated, alpha dropped.
cv::Mat rgb_of(const Image& image);
// Rec. 709 luma of the stored (encoded) values, one float channel.
cv::Mat luma_of(const Image& image);

// An 8-bit BGR picture (for drawing with OpenCV) and back.
cv::Mat to_bgr8(const Image& image);
Image from_bgr8(const cv::Mat& bgr);

}  // namespace foldcast::compare::detail
