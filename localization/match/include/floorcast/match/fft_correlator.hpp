// Cross-correlation of a fixed map with many small kernels via FFTW (single precision, r2c/c2r).
// The map's transform is computed once and reused for every kernel.
//
//   out(r, c) = sum_{dr, dc in [-R, R]} kernel(R + dr, R + dc) * map(r + dr, c + dc)
//
// with map = 0 outside [0, H) x [0, W) (no wrap-around: the transform size is padded by R).
// Thread-safe: correlate() may run concurrently, each call with its own Workspace.
#pragma once

#include <cstddef>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

namespace floorcast {

/// Smallest n' >= n whose prime factors are all 2, 3 or 5 (sizes FFTW transforms fastest;
/// factors of 7 measured ~10% slower at campus sizes).
int next_fast_fft_size(int n);

class FftCorrelator {
 public:
  /// map: CV_32F (H x W); kernels are (2R+1) x (2R+1) with R = kernel_radius_px.
  FftCorrelator(const cv::Mat& map_f32, int kernel_radius_px);
  /// Several maps of one size, for sums of correlations (run_sum): sum_i corr(map_i, kernel_i)
  /// with one inverse transform.
  FftCorrelator(const std::vector<cv::Mat>& maps_f32, int kernel_radius_px);
  ~FftCorrelator();
  FftCorrelator(const FftCorrelator&) = delete;
  FftCorrelator& operator=(const FftCorrelator&) = delete;

  /// Per-thread scratch buffers (two real and one complex array of the transform size).
  class Workspace {
   public:
    Workspace();
    ~Workspace();
    Workspace(const Workspace&) = delete;
    Workspace& operator=(const Workspace&) = delete;

   private:
    friend class FftCorrelator;
    struct Buffers;
    std::unique_ptr<Buffers> b_;
  };
  std::unique_ptr<Workspace> make_workspace() const;

  /// Thread CPU seconds of one correlate() call: kernel transform, spectrum product, inverse
  /// transform.
  struct StageTimes {
    double forward_s = 0.0;
    double product_s = 0.0;
    double inverse_s = 0.0;
  };

  /// out: CV_32F H x W (allocated if needed). kernel: CV_32F (2R+1) x (2R+1).
  void correlate(const cv::Mat& kernel_f32, cv::Mat& out, Workspace& ws, StageTimes* times = nullptr) const;

  /// The same without the copy: the result stays in the workspace, row r (W values) at
  /// result_row(ws, r), valid until the workspace's next run. Correlates with the first map.
  void run(const cv::Mat& kernel_f32, Workspace& ws, StageTimes* times = nullptr) const;
  /// sum_i corr(map_i, kernels[i]) (one kernel per map, in the maps' order), result as run().
  void run_sum(const std::vector<const cv::Mat*>& kernels_f32, Workspace& ws, StageTimes* times = nullptr) const;
  int num_maps() const;
  const float* result_row(const Workspace& ws, int row) const;

  int kernel_radius_px() const { return radius_; }
  int fft_rows() const { return rows_; }
  int fft_cols() const { return cols_; }
  /// Bytes held by the maps' spectra.
  std::size_t spectrum_bytes() const;
  /// Bytes of one workspace.
  std::size_t workspace_bytes() const;

 private:
  /// The kernel's spectrum into the workspace's spectrum buffer.
  void forward_kernel(const cv::Mat& kernel_f32, Workspace& ws) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int map_rows_ = 0, map_cols_ = 0, radius_ = 0, rows_ = 0, cols_ = 0;
};

}  // namespace floorcast
