// floorcast_depthio.so: depth maps as float TIFF (libtiff) and EXR (OpenEXR), loaded with dlopen by
// core/depth_io.cpp on first use (see core/module.hpp).
#include <tiffio.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfCompression.h>
#include <ImathBox.h>

#include <algorithm>
#include <cctype>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "../src/depth_formats_api.hpp"

namespace {

using floorcast::depthio_api::Image;

std::string extension(const char* path) {
  std::string p(path);
  const auto dot = p.find_last_of('.');
  std::string e = dot == std::string::npos ? "" : p.substr(dot);
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

// libtiff reports through handlers; keep the last message for the exception.
thread_local std::string tiff_message;
void tiff_handler(const char* module, const char* fmt, va_list ap) {
  char buf[512];
  std::vsnprintf(buf, sizeof buf, fmt, ap);
  tiff_message = std::string(module ? module : "libtiff") + ": " + buf;
}

struct TiffCloser {
  TIFF* t;
  ~TiffCloser() {
    if (t) TIFFClose(t);
  }
};

void read_tiff(const char* path, Image& out) {
  TIFFSetErrorHandler(tiff_handler);
  TIFFSetWarningHandler(nullptr);
  tiff_message.clear();
  TIFF* tif = TIFFOpen(path, "r");
  if (!tif) throw std::runtime_error("cannot open as TIFF" + (tiff_message.empty() ? std::string() : ": " + tiff_message));
  TiffCloser closer{tif};
  std::uint32_t w = 0, h = 0;
  std::uint16_t spp = 1, bps = 0, format = SAMPLEFORMAT_UINT, planar = PLANARCONFIG_CONTIG;
  TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &w);
  TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &h);
  TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &spp);
  TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &bps);
  TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &format);
  TIFFGetFieldDefaulted(tif, TIFFTAG_PLANARCONFIG, &planar);
  if (w < 1 || h < 1 || w > 16384 || h > 16384) throw std::runtime_error("TIFF size out of range");
  if (spp != 1) throw std::runtime_error("a depth TIFF must have one channel (this one has " + std::to_string(spp) + ")");
  const bool is_float = format == SAMPLEFORMAT_IEEEFP && (bps == 32 || bps == 64);
  const bool is_uint = format == SAMPLEFORMAT_UINT && (bps == 8 || bps == 16 || bps == 32);
  if (!is_float && !is_uint) {
    throw std::runtime_error("unsupported TIFF sample type (" + std::to_string(bps) + "-bit, format " + std::to_string(format) +
                             "); expected 32/64-bit float or 16-bit unsigned");
  }
  if (TIFFIsTiled(tif)) throw std::runtime_error("tiled TIFF files are not supported (write strips)");
  out.width = static_cast<int>(w);
  out.height = static_cast<int>(h);
  out.integer = !is_float;
  out.values.resize(static_cast<std::size_t>(w) * h);
  std::vector<unsigned char> line(static_cast<std::size_t>(TIFFScanlineSize(tif)));
  const std::size_t bytes = bps / 8;
  if (line.size() < static_cast<std::size_t>(w) * bytes) throw std::runtime_error("TIFF scanline shorter than the image width");
  for (std::uint32_t r = 0; r < h; ++r) {
    if (TIFFReadScanline(tif, line.data(), r, 0) < 0) throw std::runtime_error("cannot read TIFF row " + std::to_string(r) + ": " + tiff_message);
    float* dst = out.values.data() + static_cast<std::size_t>(r) * w;
    for (std::uint32_t c = 0; c < w; ++c) {
      const unsigned char* p = line.data() + c * bytes;
      if (is_float && bps == 32) {
        float v;
        std::memcpy(&v, p, 4);
        dst[c] = v;
      } else if (is_float) {
        double v;
        std::memcpy(&v, p, 8);
        dst[c] = static_cast<float>(v);
      } else if (bps == 8) {
        dst[c] = p[0];
      } else if (bps == 16) {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        dst[c] = v;
      } else {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        dst[c] = static_cast<float>(v);
      }
    }
  }
}

void write_tiff(const char* path, int width, int height, const float* values) {
  TIFFSetErrorHandler(tiff_handler);
  TIFFSetWarningHandler(nullptr);
  tiff_message.clear();
  TIFF* tif = TIFFOpen(path, "w");
  if (!tif) throw std::runtime_error("cannot create TIFF" + (tiff_message.empty() ? std::string() : ": " + tiff_message));
  TiffCloser closer{tif};
  TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, static_cast<std::uint32_t>(width));
  TIFFSetField(tif, TIFFTAG_IMAGELENGTH, static_cast<std::uint32_t>(height));
  TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
  TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 32);
  TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_IEEEFP);
  TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
  TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(tif, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
  TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, TIFFDefaultStripSize(tif, 0));
  std::vector<float> row(static_cast<std::size_t>(width));
  for (int r = 0; r < height; ++r) {
    std::memcpy(row.data(), values + static_cast<std::size_t>(r) * width, row.size() * sizeof(float));
    if (TIFFWriteScanline(tif, row.data(), static_cast<std::uint32_t>(r), 0) < 0) throw std::runtime_error("cannot write TIFF row: " + tiff_message);
  }
}

void read_exr(const char* path, Image& out) {
  Imf::InputFile file(path);
  const Imath::Box2i dw = file.header().dataWindow();
  const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
  if (w < 1 || h < 1 || w > 16384 || h > 16384) throw std::runtime_error("EXR size out of range");
  const Imf::ChannelList& channels = file.header().channels();
  std::string name;
  for (const char* preferred : {"Z", "Y", "R", "depth", "D"})
    if (channels.findChannel(preferred)) {
      name = preferred;
      break;
    }
  if (name.empty()) {
    int count = 0;
    for (auto it = channels.begin(); it != channels.end(); ++it, ++count) name = it.name();
    if (count != 1) throw std::runtime_error("EXR has no channel Z, Y, R or depth and more than one channel");
  }
  const Imf::Channel* ch = channels.findChannel(name.c_str());
  if (ch->xSampling != 1 || ch->ySampling != 1) throw std::runtime_error("EXR channel " + name + " is subsampled");
  out.width = w;
  out.height = h;
  out.integer = ch->type == Imf::UINT;
  out.values.assign(static_cast<std::size_t>(w) * h, 0.0f);
  Imf::FrameBuffer fb;
  // Read every channel type as float (OpenEXR converts half and uint).
  char* base = reinterpret_cast<char*>(out.values.data()) -
               (static_cast<std::ptrdiff_t>(dw.min.x) + static_cast<std::ptrdiff_t>(dw.min.y) * w) * static_cast<std::ptrdiff_t>(sizeof(float));
  fb.insert(name.c_str(), Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * static_cast<std::size_t>(w)));
  file.setFrameBuffer(fb);
  file.readPixels(dw.min.y, dw.max.y);
}

void write_exr(const char* path, int width, int height, const float* values) {
  Imf::Header header(width, height);
  header.compression() = Imf::ZIP_COMPRESSION;
  header.channels().insert("Z", Imf::Channel(Imf::FLOAT));
  Imf::OutputFile file(path, header);
  Imf::FrameBuffer fb;
  fb.insert("Z", Imf::Slice(Imf::FLOAT, const_cast<char*>(reinterpret_cast<const char*>(values)), sizeof(float),
                            sizeof(float) * static_cast<std::size_t>(width)));
  file.setFrameBuffer(fb);
  file.writePixels(height);
}

bool fail(char* error, std::size_t size, const std::string& message) {
  if (error && size > 0) std::snprintf(error, size, "%s", message.c_str());
  return false;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) bool floorcast_depthio_read(int api_version, const char* path,
                                                                              Image* out, char* error,
                                                                              std::size_t error_size) {
  if (api_version != floorcast::depthio_api::kApiVersion) return fail(error, error_size, "stale floorcast_depthio.so (API version mismatch)");
  try {
    const std::string e = extension(path);
    if (e == ".tif" || e == ".tiff") read_tiff(path, *out);
    else if (e == ".exr") read_exr(path, *out);
    else return fail(error, error_size, "not a TIFF or EXR file name");
    return true;
  } catch (const std::exception& ex) {
    return fail(error, error_size, ex.what());
  }
}

extern "C" __attribute__((visibility("default"))) bool floorcast_depthio_write(int api_version, const char* path,
                                                                               int width, int height,
                                                                               const float* values, char* error,
                                                                               std::size_t error_size) {
  if (api_version != floorcast::depthio_api::kApiVersion) return fail(error, error_size, "stale floorcast_depthio.so (API version mismatch)");
  try {
    const std::string e = extension(path);
    if (e == ".tif" || e == ".tiff") write_tiff(path, width, height, values);
    else if (e == ".exr") write_exr(path, width, height, values);
    else return fail(error, error_size, "not a TIFF or EXR file name");
    return true;
  } catch (const std::exception& ex) {
    return fail(error, error_size, ex.what());
  }
}
