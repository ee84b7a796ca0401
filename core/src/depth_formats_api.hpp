// The interface between core/depth_io.cpp and the module floorcast_depthio.so
// (core/modules/depth_formats.cpp: float TIFF through libtiff, EXR through OpenEXR), loaded with
// dlopen on first use so that no floorcast process maps libtiff/OpenEXR unless it reads or writes
// such a file. Private to floorcast (both sides built from one tree).
#pragma once

#include <cstddef>
#include <vector>

namespace floorcast::depthio_api {

constexpr int kApiVersion = 1;
constexpr const char* kModuleName = "floorcast_depthio";

struct Image {
  int width = 0;
  int height = 0;
  bool integer = false;  ///< values came from an integer image (units: DepthFileOptions::integer_unit_m)
  std::vector<float> values;  ///< row-major, row 0 at the top
};

/// Reads a single-channel TIFF (float32/float64, or 8/16/32-bit unsigned) or EXR (channel Z, Y, R
/// or the only one; half/float/uint) by extension. False with a message in `error` on failure.
using ReadFn = bool (*)(int api_version, const char* path, Image* out, char* error, std::size_t error_size);
constexpr const char* kReadSymbol = "floorcast_depthio_read";

/// Writes a float32 single-channel TIFF (.tif/.tiff) or EXR (.exr, channel Z, zip compression).
using WriteFn = bool (*)(int api_version, const char* path, int width, int height, const float* values, char* error,
                         std::size_t error_size);
constexpr const char* kWriteSymbol = "floorcast_depthio_write";

}  // namespace floorcast::depthio_api
