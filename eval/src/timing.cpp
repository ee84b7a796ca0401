#include "floorcast/eval/timing.hpp"

#include <algorithm>
#include <chrono>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "floorcast/eval/metrics.hpp"

namespace floorcast {

double reference_workload_s(int repeats) {
  cv::Mat img(1024, 1024, CV_32F);
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c)
      img.at<float>(r, c) = static_cast<float>(mix64(static_cast<std::uint64_t>(r) * 1024 + c) % 1000) * 1e-3f;
  const int previous_threads = cv::getNumThreads();
  cv::setNumThreads(1);
  std::vector<double> times;
  volatile double sink = 0.0;
  for (int i = 0; i < std::max(repeats, 1); ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    cv::Mat spectrum, back, blurred;
    cv::dft(img, spectrum, cv::DFT_COMPLEX_OUTPUT);
    cv::dft(spectrum, back, cv::DFT_INVERSE | cv::DFT_REAL_OUTPUT | cv::DFT_SCALE);
    cv::GaussianBlur(back, blurred, cv::Size(15, 15), 3.0);
    sink = sink + cv::sum(blurred)[0];
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  cv::setNumThreads(previous_threads);
  return median(times);
}

}  // namespace floorcast
