// Depth maps made elsewhere, and numpy arrays.
//
// Bring your own depth: a depth network run offline (Depth Pro, Depth Anything metric, UniDepth,
// Metric3D, ...) writes one depth map per colour image, in the formats those tools write:
//   .npy         2-D float32/float64 (metres) or uint16 (millimetres)
//   .tif/.tiff   single-channel float32/float64 (metres) or 16-bit (millimetres)
//   .exr         float/half, channel Z, Y, R or the only channel (metres)
//   .png         16-bit (millimetres)
// The unit of integer files is DepthFileOptions::integer_unit_m; float files are metres unless
// float_unit_m says otherwise. TIFF and EXR are read by the module floorcast_depthio.so (libtiff,
// OpenEXR; core/module.hpp), loaded on first use.
//
// NPY: numpy's .npy format version 1.0 (little-endian, C order), read and written here without
// numpy: `np.load("posterior.npy")` reads what write_npy writes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <memory>
#include <string>
#include <vector>

#include "floorcast/core/scan.hpp"

namespace floorcast {

/// What a depth map's values measure.
enum class DepthKind {
  kZ,      ///< z-depth along the optical axis (what most depth networks output; floorcast's own)
  kRange,  ///< Euclidean distance from the camera centre (converted to z-depth on load)
};
/// "z" or "range"; throws InputError otherwise.
DepthKind parse_depth_kind(const std::string& text);

struct DepthFileOptions {
  double integer_unit_m = 0.001;  ///< 16-bit values (PNG, TIFF, NPY uint16) are millimetres
  double float_unit_m = 1.0;      ///< float values are metres
  DepthKind kind = DepthKind::kZ;
};

/// Reads one depth file (format by extension, see above) as CV_32F values in the file's units
/// times the unit (not yet checked or converted to z-depth). Throws InputError naming the file
/// and the reason (unknown extension, not 2-D, unsupported type, cannot decode).
cv::Mat read_depth_file(const std::string& path, const DepthFileOptions& options = {});

/// Writes a CV_32F depth map in metres: .npy, .tif/.tiff or .exr (float32), or .png (16-bit in
/// integer_unit_m, rounded; beyond 65535 units -> 0). For tests and exports.
void write_depth_file(const std::string& path, const cv::Mat& depth_m, const DepthFileOptions& options = {});

/// What load_depth_directory did, for the user to read.
struct DepthDirectoryReport {
  std::vector<std::string> files;    ///< the file used for each view
  std::vector<std::string> repairs;  ///< one sentence per repair (resampled, invalid values dropped)
};

/// Replaces the depth of every view of `scan` by the depth map in `dir` made for it. The file of
/// view k (k-th entry of scan.json) is the one existing file named
///   <colour image stem>.EXT, view_NNN.EXT or view_NNN_depth.EXT   (NNN = k with three digits)
/// with EXT one of npy, exr, tif, tiff, png. Repairs (reported): a map of the same aspect ratio
/// but another size is resampled (nearest) to the intrinsics; NaN, infinite, negative and
/// > 1000 m values become 0 (no return); range maps are converted to z-depth. Refused (InputError
/// naming the file): no file or two candidate files for a view, another aspect ratio, no valid
/// value at all.
DepthDirectoryReport load_depth_directory(Scan& scan, const std::string& dir, const DepthFileOptions& options = {});

/// NPY bytes of a 2-D (rows x cols) or, for multi-channel mats, 3-D (rows x cols x channels)
/// array of uint8, uint16, int32, float32 or float64.
std::string npy_bytes(const cv::Mat& array);
/// NPY bytes of an N-D float32 array in C order (shape product must equal values.size()).
std::string npy_bytes(const std::vector<std::size_t>& shape, const std::vector<float>& values);
/// Writes npy_bytes atomically.
void write_npy(const std::string& path, const cv::Mat& array);
void write_npy(const std::string& path, const std::vector<std::size_t>& shape, const std::vector<float>& values);

/// Element types of the streamed writers below (CV_32F input is converted).
enum class NpyDtype { kFloat32, kFloat16 };

/// A .npy file written block by block (a volume slice by slice) without holding the whole array:
/// rows go to a temporary file (AtomicFileWriter, core/file_io.hpp), renamed to PATH by close()
/// once exactly the shape's element count was appended (InputError otherwise; the destructor
/// removes an unfinished temporary).
class NpyStreamWriter {
 public:
  NpyStreamWriter(std::string path, std::vector<std::size_t> shape, NpyDtype dtype);
  ~NpyStreamWriter();
  NpyStreamWriter(const NpyStreamWriter&) = delete;
  NpyStreamWriter& operator=(const NpyStreamWriter&) = delete;
  /// Appends a CV_32F block in C order (its rows one after another).
  void append(const cv::Mat& block);
  void close();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// A .npz archive (numpy.load reads it: a ZIP of .npy members), every member deflated with zlib
/// as it is written, so a volume is compressed slice by slice. Written to a temporary file,
/// renamed by close(). Members larger than 4 GiB uncompressed are refused (no ZIP64).
class NpzWriter {
 public:
  explicit NpzWriter(std::string path);
  ~NpzWriter();
  NpzWriter(const NpzWriter&) = delete;
  NpzWriter& operator=(const NpzWriter&) = delete;
  /// Member NAME.npy: a 2-D array as npy_bytes writes it.
  void add(const std::string& name, const cv::Mat& array);
  /// Member NAME.npy: an N-D float32 array in C order (e.g. 1-D columns).
  void add(const std::string& name, const std::vector<std::size_t>& shape, const std::vector<float>& values);
  /// Member NAME.npy of `shape` from CV_32F slices in order (their elements must add up to it).
  void add_slices(const std::string& name, const std::vector<std::size_t>& shape, NpyDtype dtype,
                  const std::vector<cv::Mat>& slices);
  void close();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// A parsed .npy file: shape and raw little-endian data of one of the types above.
struct NpyArray {
  std::vector<std::size_t> shape;
  std::string dtype;  ///< numpy descr, e.g. "<f4", "<u2", "|u1"
  std::vector<std::uint8_t> data;
};
/// Parses .npy bytes (version 1.0-3.0, C order, little-endian or byte-sized types); throws
/// InputError naming `source` for anything else.
NpyArray parse_npy(const std::string& bytes, const std::string& source);
NpyArray read_npy(const std::string& path);

}  // namespace floorcast
