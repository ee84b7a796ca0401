#include "floorcast/localization/fft_correlator.hpp"

#include <fftw3.h>

#include <algorithm>
#include <chrono>
#include <complex>
#include <cstring>
#include <mutex>
#include <stdexcept>

namespace floorcast {
namespace {

/// FFTW's planner is not thread-safe; every plan creation and destruction goes through here.
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct FftwFree {
  void operator()(void* p) const { fftwf_free(p); }
};
using RealBuffer = std::unique_ptr<float, FftwFree>;
using ComplexBuffer = std::unique_ptr<fftwf_complex, FftwFree>;

}  // namespace

int next_fast_fft_size(int n) {
  if (n <= 1) return 1;
  for (int m = n;; ++m) {
    int k = m;
    for (int p : {2, 3, 5, 7})
      while (k % p == 0) k /= p;
    if (k == 1) return m;
  }
}

struct FftCorrelator::Impl {
  std::size_t real_count = 0;
  std::size_t complex_count = 0;
  ComplexBuffer map_spectrum;
  fftwf_plan forward = nullptr;
  fftwf_plan inverse = nullptr;
};

struct FftCorrelator::Workspace::Buffers {
  RealBuffer kernel;  ///< kernel wrapped around (0, 0); zero outside its footprint
  ComplexBuffer spectrum;
  RealBuffer result;
};

FftCorrelator::Workspace::Workspace() : b_(std::make_unique<Buffers>()) {}
FftCorrelator::Workspace::~Workspace() = default;

FftCorrelator::FftCorrelator(const cv::Mat& map, int kernel_radius_px) : impl_(std::make_unique<Impl>()) {
  if (map.type() != CV_32F || map.empty()) throw std::invalid_argument("FftCorrelator: map must be non-empty CV_32F");
  if (kernel_radius_px < 0) throw std::invalid_argument("FftCorrelator: negative kernel radius");
  map_rows_ = map.rows;
  map_cols_ = map.cols;
  radius_ = kernel_radius_px;
  // Output rows r + dr range over [-R, H + R); with a transform of size >= H + R the wrapped reads
  // (r + dr < 0 -> size + r + dr >= H) land in the zero padding.
  // The wrapped kernel's two halves must not overlap either: size >= 2R + 1.
  rows_ = next_fast_fft_size(std::max(map_rows_ + radius_, 2 * radius_ + 1));
  cols_ = next_fast_fft_size(std::max(map_cols_ + radius_, 2 * radius_ + 1));
  // Keep the column count even so the r2c half spectrum has a simple layout.
  if (cols_ % 2) cols_ = next_fast_fft_size(cols_ + 1);
  impl_->real_count = static_cast<std::size_t>(rows_) * cols_;
  impl_->complex_count = static_cast<std::size_t>(rows_) * (cols_ / 2 + 1);

  RealBuffer padded(fftwf_alloc_real(impl_->real_count));
  impl_->map_spectrum.reset(fftwf_alloc_complex(impl_->complex_count));
  RealBuffer scratch_real(fftwf_alloc_real(impl_->real_count));
  ComplexBuffer scratch_complex(fftwf_alloc_complex(impl_->complex_count));
  if (!padded || !impl_->map_spectrum || !scratch_real || !scratch_complex) throw std::bad_alloc();
  {
    std::lock_guard<std::mutex> lock(planner_mutex());
    // FFTW_ESTIMATE: no measuring, so the same plan (and the same bits) on every run.
    impl_->forward = fftwf_plan_dft_r2c_2d(rows_, cols_, scratch_real.get(), scratch_complex.get(), FFTW_ESTIMATE);
    impl_->inverse = fftwf_plan_dft_c2r_2d(rows_, cols_, scratch_complex.get(), scratch_real.get(), FFTW_ESTIMATE);
  }
  if (!impl_->forward || !impl_->inverse) throw std::runtime_error("FftCorrelator: FFTW planning failed");
  std::memset(padded.get(), 0, impl_->real_count * sizeof(float));
  for (int r = 0; r < map_rows_; ++r) {
    std::memcpy(padded.get() + static_cast<std::size_t>(r) * cols_, map.ptr<float>(r), sizeof(float) * map_cols_);
  }
  fftwf_execute_dft_r2c(impl_->forward, padded.get(), impl_->map_spectrum.get());
}

FftCorrelator::~FftCorrelator() {
  std::lock_guard<std::mutex> lock(planner_mutex());
  if (impl_->forward) fftwf_destroy_plan(impl_->forward);
  if (impl_->inverse) fftwf_destroy_plan(impl_->inverse);
}

std::size_t FftCorrelator::spectrum_bytes() const { return impl_->complex_count * sizeof(fftwf_complex); }

std::size_t FftCorrelator::workspace_bytes() const {
  return 2 * impl_->real_count * sizeof(float) + impl_->complex_count * sizeof(fftwf_complex);
}

std::unique_ptr<FftCorrelator::Workspace> FftCorrelator::make_workspace() const {
  auto ws = std::make_unique<Workspace>();
  Workspace::Buffers& b = *ws->b_;
  b.kernel.reset(fftwf_alloc_real(impl_->real_count));
  b.spectrum.reset(fftwf_alloc_complex(impl_->complex_count));
  b.result.reset(fftwf_alloc_real(impl_->real_count));
  if (!b.kernel || !b.spectrum || !b.result) throw std::bad_alloc();
  std::memset(b.kernel.get(), 0, impl_->real_count * sizeof(float));
  return ws;
}

void FftCorrelator::correlate(const cv::Mat& kernel, cv::Mat& out, Workspace& workspace, StageTimes* times) const {
  Workspace::Buffers& ws = *workspace.b_;
  const int K = 2 * radius_ + 1;
  if (kernel.type() != CV_32F || kernel.rows != K || kernel.cols != K) {
    throw std::invalid_argument("FftCorrelator::correlate: kernel must be CV_32F " + std::to_string(K) + "x" +
                                std::to_string(K));
  }
  auto t0 = std::chrono::steady_clock::now();
  // Wrap the kernel so its centre sits at (0, 0): offset d lands at index d mod size. Only this
  // footprint is ever written, the rest of the buffer stays zero (r2c preserves its input).
  float* kb = ws.kernel.get();
  for (int dr = -radius_; dr <= radius_; ++dr) {
    const int rr = dr < 0 ? rows_ + dr : dr;
    const float* krow = kernel.ptr<float>(radius_ + dr);
    float* dst = kb + static_cast<std::size_t>(rr) * cols_;
    // dc in [0, R] at the start of the row, dc in [-R, -1] at its end.
    std::memcpy(dst, krow + radius_, sizeof(float) * (radius_ + 1));
    if (radius_ > 0) std::memcpy(dst + cols_ - radius_, krow, sizeof(float) * radius_);
  }
  fftwf_execute_dft_r2c(impl_->forward, kb, ws.spectrum.get());
  auto t1 = std::chrono::steady_clock::now();
  // Correlation: conj(K) * F, with the 1/N of the unnormalised inverse folded in.
  const float scale = 1.0f / static_cast<float>(impl_->real_count);
  auto* s = reinterpret_cast<std::complex<float>*>(ws.spectrum.get());
  const auto* f = reinterpret_cast<const std::complex<float>*>(impl_->map_spectrum.get());
  for (std::size_t i = 0; i < impl_->complex_count; ++i) {
    const float kr = s[i].real(), ki = s[i].imag();
    const float fr = f[i].real(), fi = f[i].imag();
    s[i] = {(kr * fr + ki * fi) * scale, (kr * fi - ki * fr) * scale};
  }
  auto t2 = std::chrono::steady_clock::now();
  fftwf_execute_dft_c2r(impl_->inverse, ws.spectrum.get(), ws.result.get());
  out.create(map_rows_, map_cols_, CV_32F);
  for (int r = 0; r < map_rows_; ++r) {
    std::memcpy(out.ptr<float>(r), ws.result.get() + static_cast<std::size_t>(r) * cols_, sizeof(float) * map_cols_);
  }
  if (times) {
    times->forward_s = std::chrono::duration<double>(t1 - t0).count();
    times->product_s = std::chrono::duration<double>(t2 - t1).count();
    times->inverse_s = seconds_since(t2);
  }
}

}  // namespace floorcast
