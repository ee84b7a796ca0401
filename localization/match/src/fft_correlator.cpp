#include "floorcast/match/fft_correlator.hpp"

#include <fftw3.h>

#include <algorithm>
#include <complex>
#include <cstring>
#include <ctime>
#include <mutex>
#include <stdexcept>
#include <string>

namespace floorcast {
namespace {

/// FFTW's planner is not thread-safe; every plan creation and destruction goes through here.
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

double cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct FftwFree {
  void operator()(void* p) const { fftwf_free(p); }
};
using RealBuffer = std::unique_ptr<float, FftwFree>;
using ComplexBuffer = std::unique_ptr<fftwf_complex, FftwFree>;

RealBuffer alloc_real(std::size_t n) {
  RealBuffer b(fftwf_alloc_real(std::max<std::size_t>(n, 1)));
  if (!b) throw std::bad_alloc();
  return b;
}
ComplexBuffer alloc_complex(std::size_t n) {
  ComplexBuffer b(fftwf_alloc_complex(std::max<std::size_t>(n, 1)));
  if (!b) throw std::bad_alloc();
  return b;
}

}  // namespace

int next_fast_fft_size(int n) {
  if (n <= 1) return 1;
  for (int m = n;; ++m) {
    int k = m;
    for (int p : {2, 3, 5})
      while (k % p == 0) k /= p;
    if (k == 1) return m;
  }
}

// The 2D transform is done in two passes so the kernel's zeros are skipped:
//   forward: r2c along each row (only the 2R+1 rows the wrapped kernel occupies; all other rows
//            of the spectrum are zero), then c2c along every column;
//   inverse: c2c along every column, then c2r along each row (only the H rows of the output).
// Same layout as fftwf_plan_dft_r2c_2d ([rows][cols/2+1]), which computes the map's spectrum.
struct FftCorrelator::Impl {
  int half = 0;  ///< cols / 2 + 1
  std::size_t real_count = 0;
  std::size_t complex_count = 0;
  std::vector<ComplexBuffer> map_spectra;  ///< one per map
  fftwf_plan rows_top = nullptr;     ///< r2c of kernel rows dr = 0..R into spectrum rows 0..R
  fftwf_plan rows_bottom = nullptr;  ///< r2c of kernel rows dr = -R..-1 into rows M-R..M-1
  fftwf_plan cols_forward = nullptr;
  fftwf_plan cols_inverse = nullptr;
  fftwf_plan rows_inverse = nullptr;  ///< c2r of spectrum rows 0..H-1
};

struct FftCorrelator::Workspace::Buffers {
  RealBuffer kernel;       ///< (2R+1) x cols: wrapped kernel rows dr = 0..R, then -R..-1
  ComplexBuffer spectrum;  ///< rows x (cols/2+1)
  ComplexBuffer sum;       ///< rows x (cols/2+1), run_sum's accumulator (allocated on first use)
  RealBuffer result;       ///< H x cols
};

FftCorrelator::Workspace::Workspace() : b_(std::make_unique<Buffers>()) {}
FftCorrelator::Workspace::~Workspace() = default;

FftCorrelator::FftCorrelator(const cv::Mat& map, int kernel_radius_px)
    : FftCorrelator(std::vector<cv::Mat>{map}, kernel_radius_px) {}

FftCorrelator::FftCorrelator(const std::vector<cv::Mat>& maps, int kernel_radius_px) : impl_(std::make_unique<Impl>()) {
  if (maps.empty()) throw std::invalid_argument("FftCorrelator: no map");
  const cv::Mat& map = maps.front();
  for (const cv::Mat& m : maps) {
    if (m.type() != CV_32F || m.empty() || m.size() != map.size()) {
      throw std::invalid_argument("FftCorrelator: maps must be non-empty CV_32F of one size");
    }
  }
  if (kernel_radius_px < 0) throw std::invalid_argument("FftCorrelator: negative kernel radius");
  map_rows_ = map.rows;
  map_cols_ = map.cols;
  radius_ = kernel_radius_px;
  // Output rows r + dr range over [-R, H + R); with a transform of size >= H + R the wrapped reads
  // (r + dr < 0 -> size + r + dr >= H) land in the zero padding. The wrapped kernel's two halves
  // must not overlap either: size >= 2R + 1.
  rows_ = next_fast_fft_size(std::max(map_rows_ + radius_, 2 * radius_ + 1));
  cols_ = next_fast_fft_size(std::max(map_cols_ + radius_, 2 * radius_ + 1));
  if (cols_ % 2) cols_ = next_fast_fft_size(cols_ + 1);  // even: simple half-spectrum layout
  Impl& im = *impl_;
  im.half = cols_ / 2 + 1;
  im.real_count = static_cast<std::size_t>(rows_) * cols_;
  im.complex_count = static_cast<std::size_t>(rows_) * im.half;

  const int R = radius_, K = 2 * radius_ + 1, H = map_rows_, M = rows_, N = cols_, C = im.half;
  RealBuffer padded = alloc_real(im.real_count);
  for (std::size_t i = 0; i < maps.size(); ++i) im.map_spectra.push_back(alloc_complex(im.complex_count));
  // Planning arrays with the workspaces' layout (same offsets, so the same alignment).
  RealBuffer k_in = alloc_real(static_cast<std::size_t>(K) * N);
  ComplexBuffer spec = alloc_complex(im.complex_count);
  RealBuffer out = alloc_real(static_cast<std::size_t>(H) * N);
  fftwf_plan map_plan = nullptr;
  {
    std::lock_guard<std::mutex> lock(planner_mutex());
    // FFTW_ESTIMATE: no measuring, so the same plans (and the same bits) on every run.
    map_plan = fftwf_plan_dft_r2c_2d(M, N, padded.get(), im.map_spectra.front().get(), FFTW_ESTIMATE);
    im.rows_top = fftwf_plan_many_dft_r2c(1, &N, R + 1, k_in.get(), nullptr, 1, N, spec.get(), nullptr, 1, C,
                                          FFTW_ESTIMATE);
    if (R > 0) {
      im.rows_bottom = fftwf_plan_many_dft_r2c(1, &N, R, k_in.get() + static_cast<std::size_t>(R + 1) * N, nullptr, 1, N,
                                               spec.get() + static_cast<std::size_t>(M - R) * C, nullptr, 1, C,
                                               FFTW_ESTIMATE);
    }
    im.cols_forward = fftwf_plan_many_dft(1, &M, C, spec.get(), nullptr, C, 1, spec.get(), nullptr, C, 1, FFTW_FORWARD,
                                          FFTW_ESTIMATE);
    im.cols_inverse = fftwf_plan_many_dft(1, &M, C, spec.get(), nullptr, C, 1, spec.get(), nullptr, C, 1, FFTW_BACKWARD,
                                          FFTW_ESTIMATE);
    im.rows_inverse = fftwf_plan_many_dft_c2r(1, &N, H, spec.get(), nullptr, 1, C, out.get(), nullptr, 1, N,
                                              FFTW_ESTIMATE);
  }
  if (!map_plan || !im.rows_top || (R > 0 && !im.rows_bottom) || !im.cols_forward || !im.cols_inverse ||
      !im.rows_inverse) {
    throw std::runtime_error("FftCorrelator: FFTW planning failed");
  }
  for (std::size_t i = 0; i < maps.size(); ++i) {
    std::memset(padded.get(), 0, im.real_count * sizeof(float));
    for (int r = 0; r < map_rows_; ++r) {
      std::memcpy(padded.get() + static_cast<std::size_t>(r) * N, maps[i].ptr<float>(r), sizeof(float) * map_cols_);
    }
    fftwf_execute_dft_r2c(map_plan, padded.get(), im.map_spectra[i].get());
  }
  std::lock_guard<std::mutex> lock(planner_mutex());
  fftwf_destroy_plan(map_plan);
}

FftCorrelator::~FftCorrelator() {
  std::lock_guard<std::mutex> lock(planner_mutex());
  for (fftwf_plan p : {impl_->rows_top, impl_->rows_bottom, impl_->cols_forward, impl_->cols_inverse, impl_->rows_inverse}) {
    if (p) fftwf_destroy_plan(p);
  }
}

std::size_t FftCorrelator::spectrum_bytes() const {
  return impl_->map_spectra.size() * impl_->complex_count * sizeof(fftwf_complex);
}

int FftCorrelator::num_maps() const { return static_cast<int>(impl_->map_spectra.size()); }

std::size_t FftCorrelator::workspace_bytes() const {
  return (static_cast<std::size_t>(2 * radius_ + 1) + static_cast<std::size_t>(map_rows_)) * cols_ * sizeof(float) +
         impl_->complex_count * sizeof(fftwf_complex);
}

std::unique_ptr<FftCorrelator::Workspace> FftCorrelator::make_workspace() const {
  auto ws = std::make_unique<Workspace>();
  Workspace::Buffers& b = *ws->b_;
  const std::size_t k_count = static_cast<std::size_t>(2 * radius_ + 1) * cols_;
  b.kernel = alloc_real(k_count);
  b.spectrum = alloc_complex(impl_->complex_count);
  b.result = alloc_real(static_cast<std::size_t>(map_rows_) * cols_);
  std::memset(b.kernel.get(), 0, k_count * sizeof(float));
  return ws;
}

void FftCorrelator::forward_kernel(const cv::Mat& kernel, Workspace& workspace) const {
  const int R = radius_, K = 2 * radius_ + 1, M = rows_, N = cols_;
  if (kernel.type() != CV_32F || kernel.rows != K || kernel.cols != K) {
    throw std::invalid_argument("FftCorrelator::correlate: kernel must be CV_32F " + std::to_string(K) + "x" +
                                std::to_string(K));
  }
  const Impl& im = *impl_;
  Workspace::Buffers& ws = *workspace.b_;
  const std::size_t C = static_cast<std::size_t>(im.half);
  // Wrap the kernel so its centre sits at (0, 0): offset (dr, dc) lands at row dr mod M, column
  // dc mod N. Compact row order: dr = 0..R, then dr = -R..-1. Only the kernel's columns are ever
  // written; the rest of each row stays zero.
  float* kb = ws.kernel.get();
  for (int j = 0; j < K; ++j) {
    const int dr = j <= R ? j : j - K;  // j = R+1 .. 2R -> dr = -R .. -1
    const float* krow = kernel.ptr<float>(R + dr);
    float* dst = kb + static_cast<std::size_t>(j) * N;
    std::memcpy(dst, krow + R, sizeof(float) * (R + 1));                 // dc = 0..R
    if (R > 0) std::memcpy(dst + N - R, krow, sizeof(float) * R);         // dc = -R..-1
  }
  fftwf_complex* spec = ws.spectrum.get();
  fftwf_execute_dft_r2c(im.rows_top, kb, spec);
  if (im.rows_bottom) fftwf_execute_dft_r2c(im.rows_bottom, kb + static_cast<std::size_t>(R + 1) * N, spec + (M - R) * C);
  if (M - R > R + 1) std::memset(spec + (R + 1) * C, 0, static_cast<std::size_t>(M - 2 * R - 1) * C * sizeof(fftwf_complex));
  fftwf_execute_dft(im.cols_forward, spec, spec);
}

void FftCorrelator::run(const cv::Mat& kernel, Workspace& workspace, StageTimes* times) const {
  const Impl& im = *impl_;
  Workspace::Buffers& ws = *workspace.b_;
  const double t0 = cpu_s();
  forward_kernel(kernel, workspace);
  const double t1 = cpu_s();
  // Correlation: conj(K) * F, with the 1/N of the unnormalised inverse folded in.
  fftwf_complex* spec = ws.spectrum.get();
  const float scale = 1.0f / static_cast<float>(im.real_count);
  auto* s = reinterpret_cast<std::complex<float>*>(spec);
  const auto* f = reinterpret_cast<const std::complex<float>*>(im.map_spectra.front().get());
  for (std::size_t i = 0; i < im.complex_count; ++i) {
    const float kr = s[i].real(), ki = s[i].imag();
    const float fr = f[i].real(), fi = f[i].imag();
    s[i] = {(kr * fr + ki * fi) * scale, (kr * fi - ki * fr) * scale};
  }
  const double t2 = cpu_s();
  fftwf_execute_dft(im.cols_inverse, spec, spec);
  fftwf_execute_dft_c2r(im.rows_inverse, spec, ws.result.get());
  if (times) {
    times->forward_s = t1 - t0;
    times->product_s = t2 - t1;
    times->inverse_s = cpu_s() - t2;
  }
}

void FftCorrelator::run_sum(const std::vector<const cv::Mat*>& kernels, Workspace& workspace, StageTimes* times) const {
  const Impl& im = *impl_;
  if (kernels.size() != im.map_spectra.size()) {
    throw std::invalid_argument("FftCorrelator::run_sum: " + std::to_string(kernels.size()) + " kernels for " +
                                std::to_string(im.map_spectra.size()) + " maps");
  }
  Workspace::Buffers& ws = *workspace.b_;
  if (!ws.sum) ws.sum = alloc_complex(im.complex_count);
  auto* acc = reinterpret_cast<std::complex<float>*>(ws.sum.get());
  const float scale = 1.0f / static_cast<float>(im.real_count);
  double forward = 0.0, product = 0.0;
  for (std::size_t m = 0; m < kernels.size(); ++m) {
    const double t0 = cpu_s();
    forward_kernel(*kernels[m], workspace);
    const double t1 = cpu_s();
    const auto* s = reinterpret_cast<const std::complex<float>*>(ws.spectrum.get());
    const auto* f = reinterpret_cast<const std::complex<float>*>(im.map_spectra[m].get());
    for (std::size_t i = 0; i < im.complex_count; ++i) {
      const float kr = s[i].real(), ki = s[i].imag();
      const float fr = f[i].real(), fi = f[i].imag();
      const std::complex<float> v{(kr * fr + ki * fi) * scale, (kr * fi - ki * fr) * scale};
      acc[i] = m == 0 ? v : acc[i] + v;
    }
    forward += t1 - t0;
    product += cpu_s() - t1;
  }
  const double t2 = cpu_s();
  fftwf_execute_dft(im.cols_inverse, ws.sum.get(), ws.sum.get());
  fftwf_execute_dft_c2r(im.rows_inverse, ws.sum.get(), ws.result.get());
  if (times) {
    times->forward_s = forward;
    times->product_s = product;
    times->inverse_s = cpu_s() - t2;
  }
}

const float* FftCorrelator::result_row(const Workspace& workspace, int row) const {
  return workspace.b_->result.get() + static_cast<std::size_t>(row) * cols_;
}

void FftCorrelator::correlate(const cv::Mat& kernel, cv::Mat& out, Workspace& ws, StageTimes* times) const {
  run(kernel, ws, times);
  out.create(map_rows_, map_cols_, CV_32F);
  for (int r = 0; r < map_rows_; ++r) std::memcpy(out.ptr<float>(r), result_row(ws, r), sizeof(float) * map_cols_);
}

}  // namespace floorcast
