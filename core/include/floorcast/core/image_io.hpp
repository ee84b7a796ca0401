// PNG files: one writer (atomic) and one reader for every component's io part.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace floorcast {

/// Encodes CV_8UC1/3/4 or CV_16UC1 as PNG and writes it atomically; throws InputError naming the
/// path on failure.
void write_png(const std::string& path, const cv::Mat& image);

/// Reads an image file as stored (bit depth and channels unchanged); throws InputError naming the
/// path when it is missing or cannot be decoded.
cv::Mat read_image(const std::string& path);

}  // namespace floorcast
