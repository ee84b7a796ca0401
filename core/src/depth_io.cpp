#include "floorcast/core/depth_io.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <fstream>
#include <functional>
#include <sstream>

#include <zlib.h>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/image_io.hpp"
#include "floorcast/core/module.hpp"
#include "floorcast/core/types.hpp"
#include "depth_formats_api.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;

constexpr double kMaxDepthM = 1000.0;

std::string lower_extension(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

std::size_t dtype_size(const std::string& d) {
  if (d == "|u1" || d == "<u1" || d == "|i1") return 1;
  if (d == "<u2" || d == "<i2") return 2;
  if (d == "<f4" || d == "<i4" || d == "<u4") return 4;
  if (d == "<f8" || d == "<i8" || d == "<u8") return 8;
  return 0;
}

std::string npy_header(const std::string& descr, const std::vector<std::size_t>& shape) {
  // numpy's own spelling: "(3,)" for 1-D, "(2, 3)" otherwise.
  std::string s = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  if (shape.size() == 1) s += ",";
  s += ")";
  std::string dict = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + s + ", }";
  // Magic (6) + version (2) + header length (2) + header, padded with spaces to a multiple of 64,
  // ending in a newline.
  const std::size_t unpadded = 10 + dict.size() + 1;
  dict.append((64 - unpadded % 64) % 64, ' ');
  dict += '\n';
  std::string out("\x93NUMPY", 6);
  out += static_cast<char>(1);
  out += static_cast<char>(0);
  out += static_cast<char>(dict.size() & 0xff);
  out += static_cast<char>((dict.size() >> 8) & 0xff);
  return out + dict;
}

depthio_api::ReadFn depth_reader() {
  void* h = load_module(depthio_api::kModuleName);
  return reinterpret_cast<depthio_api::ReadFn>(module_symbol(h, depthio_api::kModuleName, depthio_api::kReadSymbol));
}

depthio_api::WriteFn depth_writer() {
  void* h = load_module(depthio_api::kModuleName);
  return reinterpret_cast<depthio_api::WriteFn>(module_symbol(h, depthio_api::kModuleName, depthio_api::kWriteSymbol));
}

cv::Mat npy_to_depth(const NpyArray& a, const std::string& path, const DepthFileOptions& o) {
  std::vector<std::size_t> shape = a.shape;
  while (shape.size() > 2 && shape.front() == 1) shape.erase(shape.begin());  // (1, H, W) from a batch
  while (shape.size() > 2 && shape.back() == 1) shape.pop_back();             // (H, W, 1)
  if (shape.size() != 2) throw InputError(path + ": a depth map must be a 2-D array (H, W); this one has " + std::to_string(a.shape.size()) + " dimensions");
  const int rows = static_cast<int>(shape[0]), cols = static_cast<int>(shape[1]);
  if (rows < 1 || cols < 1 || rows > 16384 || cols > 16384) throw InputError(path + ": depth map size out of range");
  cv::Mat out(rows, cols, CV_32F);
  const std::size_t n = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  float* dst = out.ptr<float>();
  const std::uint8_t* src = a.data.data();
  if (a.dtype == "<f4") {
    for (std::size_t i = 0; i < n; ++i) {
      float v;
      std::memcpy(&v, src + 4 * i, 4);
      dst[i] = static_cast<float>(v * o.float_unit_m);
    }
  } else if (a.dtype == "<f8") {
    for (std::size_t i = 0; i < n; ++i) {
      double v;
      std::memcpy(&v, src + 8 * i, 8);
      dst[i] = static_cast<float>(v * o.float_unit_m);
    }
  } else if (a.dtype == "<u2") {
    for (std::size_t i = 0; i < n; ++i) {
      std::uint16_t v;
      std::memcpy(&v, src + 2 * i, 2);
      dst[i] = static_cast<float>(v * o.integer_unit_m);
    }
  } else {
    throw InputError(path + ": depth arrays must be float32, float64 (metres) or uint16 (millimetres); this one is " + a.dtype);
  }
  return out;
}

/// Nearest-neighbour resampling to width x height (pixel centres map to pixel centres).
cv::Mat resample_nearest(const cv::Mat& src, int width, int height) {
  cv::Mat dst(height, width, CV_32F);
  for (int r = 0; r < height; ++r) {
    const int sr = std::min(src.rows - 1, static_cast<int>((r + 0.5) * src.rows / height));
    const float* s = src.ptr<float>(sr);
    float* d = dst.ptr<float>(r);
    for (int c = 0; c < width; ++c) d[c] = s[std::min(src.cols - 1, static_cast<int>((c + 0.5) * src.cols / width))];
  }
  return dst;
}

std::string view_stem(std::size_t k) {
  std::ostringstream s;
  s << "view_" << std::setw(3) << std::setfill('0') << k;
  return s.str();
}

}  // namespace

DepthKind parse_depth_kind(const std::string& text) {
  if (text == "z") return DepthKind::kZ;
  if (text == "range") return DepthKind::kRange;
  throw InputError("depth kind \"" + text + "\": expected z (depth along the optical axis) or range (distance from the camera)");
}

cv::Mat read_depth_file(const std::string& path, const DepthFileOptions& o) {
  const std::string ext = lower_extension(path);
  if (ext == ".npy") return npy_to_depth(read_npy(path), path, o);
  if (ext == ".png") {
    const cv::Mat m = read_image(path);
    if (m.type() != CV_16U) {
      throw InputError(path + ": a PNG depth map must be single-channel 16-bit (millimetres); this one is " +
                       std::to_string(m.channels()) + "-channel " + (m.depth() == CV_8U ? "8-bit" : "16-bit") +
                       " (8-bit images hold no metric depth)");
    }
    cv::Mat out;
    m.convertTo(out, CV_32F, o.integer_unit_m);
    return out;
  }
  if (ext == ".tif" || ext == ".tiff" || ext == ".exr") {
    check_input_file(path);
    const depthio_api::ReadFn read = depth_reader();
    depthio_api::Image img;
    char error[1024] = {0};
    if (!read(depthio_api::kApiVersion, path.c_str(), &img, error, sizeof(error))) throw InputError(path + ": " + error);
    if (img.width < 1 || img.height < 1 || img.values.size() != static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height)) {
      throw InputError(path + ": the depth reader returned no image");
    }
    cv::Mat out(img.height, img.width, CV_32F);
    const double unit = img.integer ? o.integer_unit_m : o.float_unit_m;
    float* dst = out.ptr<float>();
    for (std::size_t i = 0; i < img.values.size(); ++i) dst[i] = static_cast<float>(img.values[i] * unit);
    return out;
  }
  throw InputError(path + ": unknown depth file type \"" + ext + "\" (expected .npy, .tif, .tiff, .exr or .png)");
}

void write_depth_file(const std::string& path, const cv::Mat& depth_m, const DepthFileOptions& o) {
  if (depth_m.type() != CV_32F || depth_m.empty()) throw InputError(path + ": depth to write must be a non-empty CV_32F map");
  const cv::Mat d = depth_m.isContinuous() ? depth_m : depth_m.clone();
  const std::string ext = lower_extension(path);
  if (ext == ".npy") {
    cv::Mat scaled;
    d.convertTo(scaled, CV_32F, 1.0 / o.float_unit_m);
    write_npy(path, scaled);
  } else if (ext == ".png") {
    cv::Mat q(d.rows, d.cols, CV_16U);
    for (int r = 0; r < d.rows; ++r) {
      const float* s = d.ptr<float>(r);
      auto* t = q.ptr<std::uint16_t>(r);
      for (int c = 0; c < d.cols; ++c) {
        const double u = std::round(s[c] / o.integer_unit_m);
        t[c] = (!(s[c] > 0.0f) || u > 65535.0) ? std::uint16_t{0} : static_cast<std::uint16_t>(std::max(1.0, u));
      }
    }
    write_png(path, q);
  } else if (ext == ".tif" || ext == ".tiff" || ext == ".exr") {
    std::vector<float> values(d.total());
    const float* s = d.ptr<float>();
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<float>(s[i] / o.float_unit_m);
    char error[1024] = {0};
    AtomicFileWriter out(path);
    const std::string& tmp = out.release_temporary_path();
    if (!depth_writer()(depthio_api::kApiVersion, tmp.c_str(), d.cols, d.rows, values.data(), error, sizeof(error))) {
      throw InputError(path + ": " + error);
    }
    out.commit();
  } else {
    throw InputError(path + ": unknown depth file type \"" + ext + "\" (expected .npy, .tif, .tiff, .exr or .png)");
  }
}

DepthDirectoryReport load_depth_directory(Scan& scan, const std::string& dir, const DepthFileOptions& o) {
  if (!fs::is_directory(dir)) throw InputError(dir + ": depth folder missing (not a directory)");
  DepthDirectoryReport report;
  static const char* kExtensions[] = {".npy", ".exr", ".tif", ".tiff", ".png"};
  for (std::size_t k = 0; k < scan.views.size(); ++k) {
    DepthView& v = scan.views[k];
    std::vector<std::string> stems;
    if (!v.rgb_file.empty()) stems.push_back(fs::path(v.rgb_file).stem().string());
    stems.push_back(view_stem(k));
    stems.push_back(view_stem(k) + "_depth");
    std::vector<std::string> found, tried;
    for (const std::string& stem : stems) {
      for (const char* ext : kExtensions) {
        const fs::path p = fs::path(dir) / (stem + ext);
        tried.push_back(p.filename().string());
        std::error_code ec;
        if (fs::is_regular_file(p, ec) && std::find(found.begin(), found.end(), p.string()) == found.end()) found.push_back(p.string());
      }
    }
    const std::string where = dir + ": view " + std::to_string(k);
    if (found.empty()) {
      std::string list;
      for (const std::string& t : tried) list += (list.empty() ? "" : ", ") + t;
      throw InputError(where + ": no depth map (looked for " + list + ")");
    }
    if (found.size() > 1) {
      throw InputError(where + ": more than one depth map (" + found[0] + ", " + found[1] + "); keep one per view");
    }
    const std::string& path = found.front();
    cv::Mat d = read_depth_file(path, o);
    // Values no depth can have are counted in the file as given (before any resampling).
    long invalid = 0;
    for (int r = 0; r < d.rows; ++r) {
      float* p = d.ptr<float>(r);
      for (int c = 0; c < d.cols; ++c) {
        if (!std::isfinite(p[c]) || p[c] < 0.0f || p[c] > kMaxDepthM) {
          ++invalid;
          p[c] = 0.0f;
        }
      }
    }
    const int W = v.intrinsics.width_px, H = v.intrinsics.height_px;
    if (d.cols != W || d.rows != H) {
      const double a_file = static_cast<double>(d.cols) / d.rows, a_view = static_cast<double>(W) / H;
      if (std::abs(a_file / a_view - 1.0) > 0.01) {
        throw InputError(path + ": depth map is " + std::to_string(d.cols) + "x" + std::to_string(d.rows) +
                         " but the view's intrinsics are " + std::to_string(W) + "x" + std::to_string(H) +
                         " (another aspect ratio: crop or pad it to the colour image first)");
      }
      report.repairs.push_back(path + ": resampled " + std::to_string(d.cols) + "x" + std::to_string(d.rows) + " -> " +
                               std::to_string(W) + "x" + std::to_string(H) + " (nearest) to match the intrinsics");
      d = resample_nearest(d, W, H);
    }
    long valid = 0;
    for (int r = 0; r < H; ++r) {
      float* p = d.ptr<float>(r);
      for (int c = 0; c < W; ++c) {
        float z = p[c];
        if (z == 0.0f) continue;
        if (o.kind == DepthKind::kRange) {
          const double x = (c - v.intrinsics.cx_px) / v.intrinsics.fx_px, y = (r - v.intrinsics.cy_px) / v.intrinsics.fy_px;
          z = static_cast<float>(z / std::sqrt(1.0 + x * x + y * y));
          p[c] = z;
        }
        ++valid;
      }
    }
    if (valid == 0) throw InputError(path + ": no valid depth value (all zero, negative, beyond 1000 m or not finite)");
    if (invalid > 0) {
      report.repairs.push_back(path + ": " + std::to_string(invalid) +
                               " NaN, infinite, negative or > 1000 m values set to 0 (no return)");
    }
    v.depth_m = d;
    v.glass_mask.release();  // the masks described the replaced depth
    v.confidence.release();
    report.files.push_back(path);
  }
  return report;
}

std::string npy_bytes(const cv::Mat& array) {
  if (array.empty() || array.dims != 2) throw InputError("npy: expected a non-empty 2-D array");
  std::string descr;
  switch (array.depth()) {
    case CV_8U: descr = "|u1"; break;
    case CV_16U: descr = "<u2"; break;
    case CV_32S: descr = "<i4"; break;
    case CV_32F: descr = "<f4"; break;
    case CV_64F: descr = "<f8"; break;
    default: throw InputError("npy: unsupported element type " + std::to_string(array.type()));
  }
  std::vector<std::size_t> shape{static_cast<std::size_t>(array.rows), static_cast<std::size_t>(array.cols)};
  if (array.channels() > 1) shape.push_back(static_cast<std::size_t>(array.channels()));
  std::string out = npy_header(descr, shape);
  const std::size_t row_bytes = static_cast<std::size_t>(array.cols) * array.elemSize();
  for (int r = 0; r < array.rows; ++r) out.append(reinterpret_cast<const char*>(array.ptr(r)), row_bytes);
  return out;
}

std::string npy_bytes(const std::vector<std::size_t>& shape, const std::vector<float>& values) {
  std::size_t n = 1;
  for (std::size_t s : shape) n *= s;
  if (shape.empty() || n != values.size()) throw InputError("npy: shape does not match the number of values");
  std::string out = npy_header("<f4", shape);
  out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
  return out;
}

void write_npy(const std::string& path, const cv::Mat& array) { write_text_file_atomic(path, npy_bytes(array)); }

void write_npy(const std::string& path, const std::vector<std::size_t>& shape, const std::vector<float>& values) {
  write_text_file_atomic(path, npy_bytes(shape, values));
}

NpyArray parse_npy(const std::string& bytes, const std::string& source) {
  if (bytes.size() < 10 || bytes.compare(0, 6, std::string("\x93NUMPY", 6)) != 0) throw InputError(source + ": not a .npy file (bad magic)");
  const int major = static_cast<unsigned char>(bytes[6]);
  std::size_t header_len = 0, offset = 0;
  if (major == 1) {
    header_len = static_cast<unsigned char>(bytes[8]) | static_cast<std::size_t>(static_cast<unsigned char>(bytes[9])) << 8;
    offset = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) throw InputError(source + ": truncated .npy header");
    for (int i = 0; i < 4; ++i) header_len |= static_cast<std::size_t>(static_cast<unsigned char>(bytes[8 + i])) << (8 * i);
    offset = 12;
  } else {
    throw InputError(source + ": unsupported .npy version " + std::to_string(major));
  }
  if (header_len > 65536 || offset + header_len > bytes.size()) throw InputError(source + ": truncated .npy header");
  const std::string h = bytes.substr(offset, header_len);
  auto value_of = [&](const std::string& key) {
    const std::size_t k = h.find("'" + key + "'");
    if (k == std::string::npos) throw InputError(source + ": .npy header has no '" + key + "'");
    std::size_t i = h.find(':', k);
    if (i == std::string::npos) throw InputError(source + ": malformed .npy header");
    ++i;
    while (i < h.size() && h[i] == ' ') ++i;
    return i;
  };
  NpyArray a;
  {
    std::size_t i = value_of("descr");
    if (i >= h.size() || (h[i] != '\'' && h[i] != '"')) throw InputError(source + ": malformed .npy descr");
    const char q = h[i];
    const std::size_t end = h.find(q, i + 1);
    if (end == std::string::npos) throw InputError(source + ": malformed .npy descr");
    a.dtype = h.substr(i + 1, end - i - 1);
    if (a.dtype.size() == 3 && a.dtype[0] == '=') a.dtype[0] = '<';  // native = little-endian here
  }
  {
    const std::size_t i = value_of("fortran_order");
    if (h.compare(i, 4, "True") == 0) throw InputError(source + ": Fortran-ordered .npy arrays are not supported (save with np.ascontiguousarray)");
  }
  {
    std::size_t i = value_of("shape");
    if (i >= h.size() || h[i] != '(') throw InputError(source + ": malformed .npy shape");
    const std::size_t end = h.find(')', i);
    if (end == std::string::npos) throw InputError(source + ": malformed .npy shape");
    std::string dims = h.substr(i + 1, end - i - 1);
    std::stringstream ss(dims);
    std::string item;
    while (std::getline(ss, item, ',')) {
      const auto b = item.find_first_not_of(' ');
      if (b == std::string::npos) continue;
      std::size_t used = 0;
      unsigned long long v = 0;
      try {
        v = std::stoull(item.substr(b), &used);
      } catch (const std::exception&) {
        throw InputError(source + ": malformed .npy shape \"" + dims + "\"");
      }
      if (v > (1ull << 31)) throw InputError(source + ": .npy dimension too large");
      a.shape.push_back(static_cast<std::size_t>(v));
    }
  }
  const std::size_t elem = dtype_size(a.dtype);
  if (elem == 0) throw InputError(source + ": unsupported .npy dtype \"" + a.dtype + "\" (expected little-endian integers or floats)");
  std::size_t n = 1;
  for (std::size_t s : a.shape) {
    if (s != 0 && n > (std::size_t{1} << 34) / s) throw InputError(source + ": .npy array too large");
    n *= s;
  }
  const std::size_t data_offset = offset + header_len;
  if (bytes.size() - data_offset < n * elem) throw InputError(source + ": .npy data truncated (" + std::to_string(n) + " values of " + std::to_string(elem) + " bytes expected)");
  a.data.assign(bytes.begin() + static_cast<std::ptrdiff_t>(data_offset), bytes.begin() + static_cast<std::ptrdiff_t>(data_offset + n * elem));
  return a;
}

NpyArray read_npy(const std::string& path) { return parse_npy(read_text_file(path), path); }

}  // namespace floorcast

// ---- streamed .npy and .npz writers ----

namespace floorcast {
namespace {

const char* dtype_descr(NpyDtype d) { return d == NpyDtype::kFloat16 ? "<f2" : "<f4"; }

/// The bytes of a CV_32F block as `dtype`, rows in order.
std::string block_bytes(const cv::Mat& block, NpyDtype dtype) {
  if (block.depth() != CV_32F || block.channels() != 1) throw InputError("npy: expected a single-channel float32 block");
  cv::Mat m = block;
  if (dtype == NpyDtype::kFloat16) block.convertTo(m, CV_16F);
  std::string out;
  const std::size_t row = static_cast<std::size_t>(m.cols) * m.elemSize();
  out.reserve(row * static_cast<std::size_t>(m.rows));
  for (int r = 0; r < m.rows; ++r) out.append(reinterpret_cast<const char*>(m.ptr(r)), row);
  return out;
}

std::size_t element_count(const std::vector<std::size_t>& shape) {
  std::size_t n = 1;
  for (std::size_t s : shape) n *= s;
  return n;
}

void put16(std::string& o, unsigned v) {
  o += static_cast<char>(v & 0xff);
  o += static_cast<char>((v >> 8) & 0xff);
}
void put32(std::string& o, unsigned long v) {
  for (int i = 0; i < 4; ++i) o += static_cast<char>((v >> (8 * i)) & 0xff);
}

}  // namespace

struct NpyStreamWriter::State {
  std::unique_ptr<AtomicFileWriter> out;
  std::size_t expected = 0, written = 0;
  NpyDtype dtype = NpyDtype::kFloat32;
};

NpyStreamWriter::NpyStreamWriter(std::string path, std::vector<std::size_t> shape, NpyDtype dtype)
    : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.out = std::make_unique<AtomicFileWriter>(std::move(path));
  s.expected = element_count(shape);
  s.dtype = dtype;
  s.out->write(npy_header(dtype_descr(dtype), shape));
}

NpyStreamWriter::~NpyStreamWriter() = default;

void NpyStreamWriter::append(const cv::Mat& block) {
  State& s = *state_;
  s.out->write(block_bytes(block, s.dtype));
  s.written += block.total();
}

void NpyStreamWriter::close() {
  State& s = *state_;
  if (s.written != s.expected) {
    throw InputError(s.out->path() + ": " + std::to_string(s.written) + " of " + std::to_string(s.expected) + " elements written");
  }
  s.out->commit();
}

struct NpzWriter::State {
  std::string path;
  std::unique_ptr<AtomicFileWriter> out;
  std::string central;
  unsigned long offset = 0;
  unsigned members = 0;

  void write(const std::string& b) {
    out->write(b);
    offset += static_cast<unsigned long>(b.size());
  }

  /// One member from its pieces (header, then data blocks from `next` until it returns false):
  /// a local header with a data descriptor (sizes follow the deflated data), as numpy's zipfile
  /// reads it.
  void member(const std::string& name, const std::function<bool(std::string&)>& next) {
    const unsigned long local = offset;
    std::string h;
    put32(h, 0x04034b50UL);
    put16(h, 20);      // version needed: 2.0 (deflate)
    put16(h, 0x0008);  // sizes and CRC in the data descriptor
    put16(h, 8);       // deflate
    put16(h, 0);       // time
    put16(h, 0x21);    // date: 1980-01-01
    put32(h, 0);
    put32(h, 0);
    put32(h, 0);
    put16(h, static_cast<unsigned>(name.size()));
    put16(h, 0);
    h += name;
    write(h);
    z_stream z{};
    if (deflateInit2(&z, 6, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK) throw InputError(path + ": zlib init failed");
    unsigned long crc = crc32(0L, Z_NULL, 0);
    unsigned long long raw = 0, packed = 0;
    std::string in, buf(1 << 16, '\0');
    bool more = true;
    while (true) {
      in.clear();
      more = next(in);
      crc = crc32(crc, reinterpret_cast<const Bytef*>(in.data()), static_cast<uInt>(in.size()));
      raw += in.size();
      z.next_in = reinterpret_cast<Bytef*>(in.data());
      z.avail_in = static_cast<uInt>(in.size());
      const int flush = more ? Z_NO_FLUSH : Z_FINISH;
      int rc = Z_OK;
      do {
        z.next_out = reinterpret_cast<Bytef*>(buf.data());
        z.avail_out = static_cast<uInt>(buf.size());
        rc = deflate(&z, flush);
        const std::size_t got = buf.size() - z.avail_out;
        packed += got;
        write(buf.substr(0, got));
      } while (z.avail_out == 0 || (flush == Z_FINISH && rc != Z_STREAM_END));
      if (!more) break;
    }
    deflateEnd(&z);
    if (raw > 0xFFFFFFFFULL || packed > 0xFFFFFFFFULL || offset > 0xFFFFFFFFUL) {
      throw InputError(path + ": member " + name + " is larger than 4 GiB (no ZIP64 here): write .npy instead");
    }
    std::string d;
    put32(d, 0x08074b50UL);
    put32(d, crc);
    put32(d, static_cast<unsigned long>(packed));
    put32(d, static_cast<unsigned long>(raw));
    write(d);
    std::string c;
    put32(c, 0x02014b50UL);
    put16(c, 20);
    put16(c, 20);
    put16(c, 0x0008);
    put16(c, 8);
    put16(c, 0);
    put16(c, 0x21);
    put32(c, crc);
    put32(c, static_cast<unsigned long>(packed));
    put32(c, static_cast<unsigned long>(raw));
    put16(c, static_cast<unsigned>(name.size()));
    put16(c, 0);
    put16(c, 0);
    put16(c, 0);
    put16(c, 0);
    put32(c, 0);
    put32(c, local);
    c += name;
    central += c;
    ++members;
  }
};

NpzWriter::NpzWriter(std::string path) : state_(std::make_unique<State>()) {
  state_->path = path;
  state_->out = std::make_unique<AtomicFileWriter>(std::move(path));
}

NpzWriter::~NpzWriter() = default;

void NpzWriter::add(const std::string& name, const std::vector<std::size_t>& shape, const std::vector<float>& values) {
  std::string bytes = npy_bytes(shape, values);
  bool given = false;
  state_->member(name + ".npy", [&](std::string& out) {
    if (!given) out.swap(bytes);
    given = true;
    return false;
  });
}

void NpzWriter::add(const std::string& name, const cv::Mat& array) {
  std::string bytes = npy_bytes(array);
  bool given = false;
  state_->member(name + ".npy", [&](std::string& out) {
    if (!given) out.swap(bytes);
    given = true;
    return false;
  });
}

void NpzWriter::add_slices(const std::string& name, const std::vector<std::size_t>& shape, NpyDtype dtype,
                           const std::vector<cv::Mat>& slices) {
  std::size_t total = 0;
  for (const cv::Mat& m : slices) total += m.total();
  if (total != element_count(shape)) throw InputError(state_->path + ": " + name + ": the slices do not fill the shape");
  std::size_t k = 0;
  bool header = false;
  state_->member(name + ".npy", [&](std::string& out) {
    if (!header) {
      out = npy_header(dtype_descr(dtype), shape);
      header = true;
      return !slices.empty();
    }
    out = block_bytes(slices[k++], dtype);
    return k < slices.size();
  });
}

void NpzWriter::close() {
  State& s = *state_;
  const unsigned long start = s.offset;
  s.write(s.central);
  std::string e;
  put32(e, 0x06054b50UL);
  put16(e, 0);
  put16(e, 0);
  put16(e, s.members);
  put16(e, s.members);
  put32(e, static_cast<unsigned long>(s.central.size()));
  put32(e, start);
  put16(e, 0);
  s.write(e);
  s.out->commit();
}

}  // namespace floorcast
