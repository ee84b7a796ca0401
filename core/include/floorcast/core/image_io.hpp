// Image files: one PNG writer (atomic) and one reader (PNG, binary PGM/PPM) for every component's io
// part, on libpng (not OpenCV's imgcodecs, whose dependencies every process would load at start-up).
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace floorcast {

/// Encodes CV_8UC1/3/4 or CV_16UC1 as PNG and writes it atomically; throws InputError naming the
/// path on failure.
void write_png(const std::string& path, const cv::Mat& image);

/// PNG bytes of a CV_8UC1/3/4 or CV_16UC1 image (channels in OpenCV's BGR(A) order); throws
/// InputError for other types.
std::string encode_png(const cv::Mat& image);

/// Decodes PNG (any colour type; palettes and low bit depths expanded to 8 bit, 16 bit kept) or
/// binary PGM/PPM bytes into CV_8U/CV_16U gray, BGR or BGRA; `path` names the source in errors.
cv::Mat decode_image(const std::string& bytes, const std::string& path);

/// Reads an image file as stored (bit depth and channels unchanged); throws InputError naming the
/// path when it is missing or cannot be decoded. The size in the file's header is checked against
/// the limit max_image_pixels (docs/limits.md) before anything is decoded.
cv::Mat read_image(const std::string& path);

/// Throws LimitError when width x height exceeds max_image_pixels (`what` names the image).
void check_image_size(long long width, long long height, const std::string& what);

}  // namespace floorcast
