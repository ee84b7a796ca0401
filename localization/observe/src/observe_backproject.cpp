// Depth views -> camera-frame point clouds (edge, glass and confidence masks), voxel subsampling.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>

#include "floorcast/observe/observation_module.hpp"

namespace floorcast {
namespace {

void check_view(const DepthView& view, std::size_t k) {
  const std::string where = "scan view " + std::to_string(k) + ": ";
  const CameraIntrinsics& K = view.intrinsics;
  if (view.depth_m.empty()) throw InputError(where + "depth image is empty");
  if (view.depth_m.type() != CV_32F) throw InputError(where + "depth image is not CV_32F");
  if (view.depth_m.cols != K.width_px || view.depth_m.rows != K.height_px) {
    throw InputError(where + "depth image is " + std::to_string(view.depth_m.cols) + "x" +
                     std::to_string(view.depth_m.rows) + " but the intrinsics say " +
                     std::to_string(K.width_px) + "x" + std::to_string(K.height_px));
  }
  if (!(K.fx_px > 0.0) || !(K.fy_px > 0.0)) throw InputError(where + "focal lengths must be > 0");
  auto check_mask = [&](const cv::Mat& m, const char* name) {
    if (m.empty()) return;
    if (m.type() != CV_8U || m.size() != view.depth_m.size()) {
      throw InputError(where + name + " must be CV_8U and the size of the depth image");
    }
  };
  check_mask(view.glass_mask, "glass_mask");
  check_mask(view.confidence, "confidence");
}

ViewCloud back_project_view(const DepthView& view, int index, const BackProjectionParams& params) {
  ViewCloud out;
  out.view_index = index;
  out.T_scan_camera = view.T_scan_camera;
  out.intrinsics = view.intrinsics;
  out.depth_m = view.depth_m;
  const cv::Mat edges = params.remove_depth_edges ? depth_edge_mask(view.depth_m, params) : cv::Mat();
  const bool use_glass = params.mask_glass && !view.glass_mask.empty();
  const bool use_conf = params.min_confidence > 0 && !view.confidence.empty();
  const CameraIntrinsics& K = view.intrinsics;
  const int stride = std::max(1, params.pixel_stride);
  out.points_camera.reserve(static_cast<std::size_t>(K.width_px / stride + 1) *
                            static_cast<std::size_t>(K.height_px / stride + 1));
  for (int v = 0; v < view.depth_m.rows; v += stride) {
    const float* d_row = view.depth_m.ptr<float>(v);
    const std::uint8_t* e_row = edges.empty() ? nullptr : edges.ptr<std::uint8_t>(v);
    const std::uint8_t* g_row = use_glass ? view.glass_mask.ptr<std::uint8_t>(v) : nullptr;
    const std::uint8_t* c_row = use_conf ? view.confidence.ptr<std::uint8_t>(v) : nullptr;
    const float y_over_z = static_cast<float>((v - K.cy_px) / K.fy_px);
    for (int u = 0; u < view.depth_m.cols; u += stride) {
      const float d = d_row[u];
      if (!(d > 0.0f) || !std::isfinite(d)) continue;
      ++out.pixels_valid;
      if (e_row && e_row[u]) {
        ++out.pixels_edge_removed;
        continue;
      }
      if (g_row && g_row[u]) {
        ++out.pixels_glass_removed;
        continue;
      }
      if (c_row && c_row[u] < params.min_confidence) {
        ++out.pixels_low_confidence;
        continue;
      }
      const float x_over_z = static_cast<float>((u - K.cx_px) / K.fx_px);
      out.points_camera.emplace_back(x_over_z * d, y_over_z * d, d);
      out.max_depth_m = std::max(out.max_depth_m, static_cast<double>(d));
    }
  }
  return out;
}

}  // namespace

cv::Mat depth_edge_mask(const cv::Mat& depth_m, const BackProjectionParams& params) {
  CV_Assert(depth_m.type() == CV_32F);
  double lo = 0.0, hi = 0.0;
  cv::Mat valid = (depth_m > 0.0f) & (depth_m == depth_m);  // > 0 and not NaN
  cv::minMaxLoc(depth_m, &lo, &hi, nullptr, nullptr, valid);
  cv::Mat depth8(depth_m.size(), CV_8U, cv::Scalar(0));
  if (hi > lo) {
    // Valid depths to [0, 255] (min-max over valid pixels); holes stay 0.
    depth_m.convertTo(depth8, CV_8U, 255.0 / (hi - lo), -lo * 255.0 / (hi - lo));
    depth8.setTo(0, ~valid);
  }
  cv::Mat edges;
  cv::Canny(depth8, edges, params.canny_low, params.canny_high);
  if (params.edge_dilation_px > 0) {
    const int k = 2 * params.edge_dilation_px + 1;
    cv::dilate(edges, edges, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)));
  }
  return edges;
}

BackProjectionResult back_project_scan(const Scan& scan, const BackProjectionParams& params) {
  if (scan.views.empty()) throw InputError("scan has no views");
  for (std::size_t k = 0; k < scan.views.size(); ++k) check_view(scan.views[k], k);
  std::vector<ViewCloud> clouds(scan.views.size());
  tbb::parallel_for(std::size_t(0), scan.views.size(), [&](std::size_t k) {
    clouds[k] = back_project_view(scan.views[k], static_cast<int>(k), params);
  });
  BackProjectionResult result;
  for (auto& c : clouds) {
    if (c.max_depth_m >= params.max_view_depth_m) {
      result.dropped_views.push_back(c.view_index);
    } else {
      result.views.push_back(std::move(c));
    }
  }
  return result;
}

PointCloud3f view_points_scan(const ViewCloud& view, double scale) {
  PointCloud3f out(view.points_camera.size());
  const Eigen::Matrix3f R = (view.T_scan_camera.linear() * scale).cast<float>();
  const Eigen::Vector3f t = view.T_scan_camera.translation().cast<float>();
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = R * view.points_camera[i] + t;
  return out;
}

namespace {

std::int64_t floor_div(std::int64_t a, std::int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

/// Stable LSD radix sort of (key, index) by key over the low `bits` bits; indices start in
/// ascending order, so equal keys keep their points in index order (deterministic sums).
void radix_sort(std::vector<std::uint64_t>& key, std::vector<std::uint32_t>& idx, int bits) {
  const std::size_t n = key.size();
  std::vector<std::uint64_t> key2(n);
  std::vector<std::uint32_t> idx2(n);
  constexpr int kDigit = 11;
  constexpr std::size_t kBuckets = std::size_t(1) << kDigit;
  std::vector<std::size_t> count(kBuckets);
  for (int shift = 0; shift < bits; shift += kDigit) {
    std::fill(count.begin(), count.end(), 0);
    for (std::size_t i = 0; i < n; ++i) ++count[(key[i] >> shift) & (kBuckets - 1)];
    std::size_t sum = 0;
    for (auto& c : count) {
      const std::size_t t = c;
      c = sum;
      sum += t;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t pos = count[(key[i] >> shift) & (kBuckets - 1)]++;
      key2[pos] = key[i];
      idx2[pos] = idx[i];
    }
    key.swap(key2);
    idx.swap(idx2);
  }
}

int bits_for(std::uint64_t span) {
  int b = 0;
  while (b < 63 && (span >> b) != 0) ++b;
  return b;
}

/// Voxel grid with `ratio` fine cells per coarse cell along each axis: points sorted by (coarse
/// cell, fine cell within it). Returns fine centroids in that order and, per fine centroid, its
/// coarse key.
void nested_voxels(const PointCloud3f& points, double fine_m, std::int64_t ratio, PointCloud3f& fine,
                   std::vector<std::uint64_t>& coarse_key) {
  const std::size_t n = points.size();
  const double inv = 1.0 / fine_m;
  std::vector<std::array<std::int64_t, 3>> cell(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, std::size_t(1) << 14),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        for (int a = 0; a < 3; ++a) {
                          cell[i][a] = static_cast<std::int64_t>(std::floor(static_cast<double>(points[i][a]) * inv));
                        }
                      }
                    });
  std::array<std::int64_t, 3> lo, hi;
  for (int a = 0; a < 3; ++a) lo[a] = hi[a] = floor_div(cell[0][a], ratio);
  for (const auto& c : cell) {
    for (int a = 0; a < 3; ++a) {
      const std::int64_t q = floor_div(c[a], ratio);
      lo[a] = std::min(lo[a], q);
      hi[a] = std::max(hi[a], q);
    }
  }
  std::array<int, 3> bits{};
  for (int a = 0; a < 3; ++a) bits[a] = bits_for(static_cast<std::uint64_t>(hi[a] - lo[a]));
  const int rem_bits = bits_for(static_cast<std::uint64_t>(ratio - 1));
  const int coarse_bits = bits[0] + bits[1] + bits[2];
  const int total_bits = coarse_bits + 3 * rem_bits;
  if (total_bits > 63) {
    throw InputError("voxel grid: the cloud spans too many voxels of " + std::to_string(fine_m) + " m");
  }
  std::vector<std::uint64_t> key(n);
  std::vector<std::uint32_t> idx(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t k = 0;
    std::uint64_t r = 0;
    for (int a = 0; a < 3; ++a) {
      const std::int64_t q = floor_div(cell[i][a], ratio);
      k = (k << bits[a]) | static_cast<std::uint64_t>(q - lo[a]);
      r = (r << rem_bits) | static_cast<std::uint64_t>(cell[i][a] - q * ratio);
    }
    key[i] = (k << (3 * rem_bits)) | r;
    idx[i] = static_cast<std::uint32_t>(i);
  }
  radix_sort(key, idx, total_bits);
  fine.clear();
  coarse_key.clear();
  for (std::size_t b = 0; b < n;) {
    std::size_t e = b;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    while (e < n && key[e] == key[b]) {
      sum += points[idx[e]].cast<double>();
      ++e;
    }
    fine.push_back((sum / static_cast<double>(e - b)).cast<float>());
    coarse_key.push_back(key[b] >> (3 * rem_bits));
    b = e;
  }
}

}  // namespace

PointCloud3f voxel_downsample(const PointCloud3f& points, double voxel_m) {
  if (voxel_m <= 0.0 || points.empty()) return points;
  PointCloud3f fine;
  std::vector<std::uint64_t> coarse_key;
  nested_voxels(points, voxel_m, 1, fine, coarse_key);
  return fine;
}

PointCloud3f voxel_downsample_two_level(const PointCloud3f& points, double fine_m, double coarse_m,
                                        std::size_t* fine_count) {
  if (fine_count) *fine_count = points.size();
  if (points.empty()) return points;
  if (fine_m <= 0.0) return voxel_downsample(points, coarse_m);
  const double ratio = coarse_m / fine_m;
  const std::int64_t r = static_cast<std::int64_t>(std::llround(ratio));
  if (coarse_m <= 0.0 || r < 1 || std::abs(ratio - static_cast<double>(r)) > 1e-9 * ratio) {
    PointCloud3f f = voxel_downsample(points, fine_m);
    if (fine_count) *fine_count = f.size();
    return voxel_downsample(f, coarse_m);
  }
  PointCloud3f fine;
  std::vector<std::uint64_t> coarse_key;
  nested_voxels(points, fine_m, r, fine, coarse_key);
  if (fine_count) *fine_count = fine.size();
  PointCloud3f out;
  for (std::size_t b = 0; b < fine.size();) {
    std::size_t e = b;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    while (e < fine.size() && coarse_key[e] == coarse_key[b]) {
      sum += fine[e].cast<double>();
      ++e;
    }
    out.push_back((sum / static_cast<double>(e - b)).cast<float>());
    b = e;
  }
  return out;
}

}  // namespace floorcast
