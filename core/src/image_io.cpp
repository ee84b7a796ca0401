#include "floorcast/core/image_io.hpp"

#include <png.h>

#include <cctype>
#include <csetjmp>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/limits.hpp"
#include "floorcast/core/types.hpp"

// PNG through libpng directly, not OpenCV's imgcodecs: imgcodecs links GDAL, GDCM, OpenEXR and
// ~100 further shared libraries that every floorcast process would otherwise load at start-up.
namespace floorcast {
namespace {


struct PngError {
  std::string message;
};

void on_png_error(png_structp png, png_const_charp message) {
  auto* error = static_cast<PngError*>(png_get_error_ptr(png));
  if (error != nullptr) error->message = message;
  png_longjmp(png, 1);
}

void on_png_warning(png_structp, png_const_charp) {}

// Reads from an in-memory buffer.
struct ByteSource {
  const unsigned char* data;
  std::size_t size;
  std::size_t offset = 0;
};

void read_bytes(png_structp png, png_bytep out, png_size_t n) {
  auto* src = static_cast<ByteSource*>(png_get_io_ptr(png));
  if (src->offset + n > src->size) png_error(png, "the file ends inside the image");
  std::memcpy(out, src->data + src->offset, n);
  src->offset += n;
}

void write_bytes(png_structp png, png_bytep data, png_size_t n) {
  auto* out = static_cast<std::string*>(png_get_io_ptr(png));
  out->append(reinterpret_cast<const char*>(data), n);
}

void flush_bytes(png_structp) {}

// libpng's longjmp error handling: no C++ object with a non-trivial destructor may live in a frame
// that png_longjmp skips, so the decoders below keep their objects in the caller.
bool decode_png_into(const std::string& bytes, cv::Mat& image, std::vector<png_bytep>& rows, PngError& error) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error, on_png_error, on_png_warning);
  if (png == nullptr) {
    error.message = "out of memory";
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    error.message = "out of memory";
    return false;
  }
  ByteSource src{reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()};
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_set_read_fn(png, &src, read_bytes);
  png_read_info(png, info);
  const png_uint_32 width = png_get_image_width(png, info);
  const png_uint_32 height = png_get_image_height(png, info);
  // Checked against max_image_pixels by the caller from the IHDR bytes; this is the backstop.
  if (static_cast<double>(width) * static_cast<double>(height) > input_limit("max_image_pixels")) {
    png_error(png, "the image is larger than the limit max_image_pixels");
  }
  const int color = png_get_color_type(png, info);
  const int depth = png_get_bit_depth(png, info);
  // Everything arrives as 8- or 16-bit gray, BGR or BGRA, as OpenCV stores images.
  if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (color == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
  if (color == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png);
  if (depth == 16) png_set_swap(png);  // host order (little endian)
  png_set_bgr(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  const int channels = png_get_channels(png, info);
  const int out_depth = png_get_bit_depth(png, info);
  const int cv_depth = out_depth == 16 ? CV_16U : CV_8U;
  image.create(static_cast<int>(height), static_cast<int>(width), CV_MAKETYPE(cv_depth, channels));
  rows.resize(height);
  for (png_uint_32 r = 0; r < height; ++r) rows[r] = image.ptr<png_byte>(static_cast<int>(r));
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

bool encode_png_into(const cv::Mat& image, std::string& out, PngError& error) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, on_png_error, on_png_warning);
  if (png == nullptr) {
    error.message = "out of memory";
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    error.message = "out of memory";
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, &out, write_bytes, flush_bytes);
  const int channels = image.channels();
  const int color = channels == 1 ? PNG_COLOR_TYPE_GRAY : channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGB_ALPHA;
  const int depth = image.depth() == CV_16U ? 16 : 8;
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows), depth, color,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 1);  // fast: scans write many depth images
  png_write_info(png, info);
  if (depth == 16) png_set_swap(png);
  if (channels >= 3) png_set_bgr(png);
  for (int r = 0; r < image.rows; ++r) png_write_row(png, image.ptr<png_byte>(r));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

// Binary netpbm (P5 gray, P6 colour; 8 or 16 bit): ROS occupancy maps are PGM files.
cv::Mat decode_netpbm(const std::string& bytes, const std::string& path) {
  std::size_t i = 2;
  auto skip_space = [&]() {
    while (i < bytes.size()) {
      if (bytes[i] == '#') {
        while (i < bytes.size() && bytes[i] != '\n') ++i;
      } else if (std::isspace(static_cast<unsigned char>(bytes[i])) != 0) {
        ++i;
      } else {
        break;
      }
    }
  };
  auto number = [&](const char* what) {
    skip_space();
    std::size_t value = 0;
    std::size_t digits = 0;
    while (i < bytes.size() && std::isdigit(static_cast<unsigned char>(bytes[i])) != 0 && digits < 9) {
      value = value * 10 + static_cast<std::size_t>(bytes[i] - '0');
      ++i;
      ++digits;
    }
    if (digits == 0 || value == 0) throw InputError(path + ": netpbm header: bad " + std::string(what));
    return value;
  };
  const bool colour = bytes[1] == '6';
  const std::size_t width = number("width");
  const std::size_t height = number("height");
  const std::size_t maxval = number("maximum value");
  if (maxval > 65535) throw InputError(path + ": netpbm header: maximum value above 65535");
  check_image_size(static_cast<long long>(width), static_cast<long long>(height), path);
  ++i;  // the single white-space character before the raster
  const int channels = colour ? 3 : 1;
  const bool wide = maxval > 255;
  const std::size_t need = width * height * static_cast<std::size_t>(channels) * (wide ? 2 : 1);
  if (i + need > bytes.size()) throw InputError(path + ": the file ends inside the image");
  cv::Mat image(static_cast<int>(height), static_cast<int>(width), CV_MAKETYPE(wide ? CV_16U : CV_8U, channels));
  const auto* src = reinterpret_cast<const unsigned char*>(bytes.data() + i);
  for (int r = 0; r < image.rows; ++r) {
    for (int c = 0; c < image.cols * channels; ++c) {
      // RGB order in the file, BGR in memory.
      const int k = colour ? (c - c % 3) + (2 - c % 3) : c;
      if (wide) {
        image.ptr<std::uint16_t>(r)[k] = static_cast<std::uint16_t>((src[0] << 8) | src[1]);
        src += 2;
      } else {
        image.ptr<std::uint8_t>(r)[k] = *src++;
      }
    }
  }
  return image;
}

}  // namespace

std::string encode_png(const cv::Mat& image) {
  const int depth = image.depth();
  const int channels = image.channels();
  if ((depth != CV_8U && depth != CV_16U) || (channels != 1 && channels != 3 && channels != 4)) {
    throw InputError("PNG encoding: unsupported image type (8- or 16-bit, 1, 3 or 4 channels)");
  }
  if (image.empty()) throw InputError("PNG encoding: empty image");
  std::string out;
  PngError error;
  if (!encode_png_into(image, out, error)) throw InputError("PNG encoding failed: " + error.message);
  return out;
}

cv::Mat decode_image(const std::string& bytes, const std::string& path) {
  static const unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() >= 8 && std::memcmp(bytes.data(), kPngSignature, 8) == 0) {
    if (bytes.size() >= 24 && bytes.compare(12, 4, "IHDR") == 0) {
      const auto u = [&](std::size_t i) { return static_cast<long long>(static_cast<unsigned char>(bytes[i])); };
      check_image_size((u(16) << 24) | (u(17) << 16) | (u(18) << 8) | u(19),
                       (u(20) << 24) | (u(21) << 16) | (u(22) << 8) | u(23), path);
    }
    cv::Mat image;
    std::vector<png_bytep> rows;
    PngError error;
    if (!decode_png_into(bytes, image, rows, error)) throw InputError(path + ": cannot decode PNG: " + error.message);
    return image;
  }
  if (bytes.size() >= 3 && bytes[0] == 'P' && (bytes[1] == '5' || bytes[1] == '6')) return decode_netpbm(bytes, path);
  throw InputError(path + ": cannot decode image: not a PNG or binary PGM/PPM file (the formats floorcast reads)");
}

void check_image_size(long long width, long long height, const std::string& what) {
  check_limit("max_image_pixels", static_cast<double>(width) * static_cast<double>(height),
              what + ": image of " + std::to_string(width) + " x " + std::to_string(height) + " pixels:", "pixels");
}

void write_png(const std::string& path, const cv::Mat& image) {
  std::string bytes;
  try {
    bytes = encode_png(image);
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
  write_text_file_atomic(path, bytes);
}

cv::Mat read_image(const std::string& path) {
  if (std::error_code ec; !std::filesystem::exists(path, ec)) throw InputError(path + ": image missing");  // other kinds: read_text_file
  return decode_image(read_text_file(path), path);
}

}  // namespace floorcast
