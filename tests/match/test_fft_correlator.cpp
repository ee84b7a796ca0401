#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "floorcast/match/fft_correlator.hpp"

namespace floorcast {
namespace {

/// The obvious correlation, in double.
cv::Mat direct_correlation(const cv::Mat& map, const cv::Mat& kernel) {
  const int R = kernel.rows / 2;
  cv::Mat out(map.size(), CV_64F, cv::Scalar(0));
  for (int r = 0; r < map.rows; ++r)
    for (int c = 0; c < map.cols; ++c) {
      double s = 0.0;
      for (int dr = -R; dr <= R; ++dr)
        for (int dc = -R; dc <= R; ++dc) {
          const int rr = r + dr, cc = c + dc;
          if (rr < 0 || cc < 0 || rr >= map.rows || cc >= map.cols) continue;
          s += static_cast<double>(kernel.at<float>(R + dr, R + dc)) * map.at<float>(rr, cc);
        }
      out.at<double>(r, c) = s;
    }
  return out;
}

void expect_equal_to_direct(int rows, int cols, int radius, std::uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat map(rows, cols, CV_32F), kernel(2 * radius + 1, 2 * radius + 1, CV_32F);
  rng.fill(map, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::threshold(map, map, 0.8, 1.0, cv::THRESH_BINARY);  // sparse 0/1 like a wall raster
  rng.fill(kernel, cv::RNG::UNIFORM, -1.0, 1.0);
  const FftCorrelator corr(map, radius);
  auto ws = corr.make_workspace();
  cv::Mat fast;
  corr.correlate(kernel, fast, *ws);
  const cv::Mat slow = direct_correlation(map, kernel);
  ASSERT_EQ(fast.size(), map.size());
  double worst = 0.0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) worst = std::max(worst, std::abs(fast.at<float>(r, c) - slow.at<double>(r, c)));
  // Single precision over sums of up to (2R+1)^2 terms of magnitude <= 1.
  EXPECT_LT(worst, 2e-4) << rows << "x" << cols << " R=" << radius;
  // A second kernel through the same workspace (its buffer must be fully overwritten).
  cv::Mat kernel2(2 * radius + 1, 2 * radius + 1, CV_32F);
  rng.fill(kernel2, cv::RNG::UNIFORM, 0.0, 2.0);
  corr.correlate(kernel2, fast, *ws);
  const cv::Mat slow2 = direct_correlation(map, kernel2);
  worst = 0.0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) worst = std::max(worst, std::abs(fast.at<float>(r, c) - slow2.at<double>(r, c)));
  EXPECT_LT(worst, 2e-4);
}

TEST(FftCorrelator, EqualsDirectCorrelation) {
  expect_equal_to_direct(37, 53, 6, 1);
  expect_equal_to_direct(64, 48, 11, 2);
  expect_equal_to_direct(1, 1, 0, 3);
  // Map smaller than the kernel (no wrap-around into the other side).
  expect_equal_to_direct(5, 9, 12, 4);
  expect_equal_to_direct(23, 3, 7, 5);
}

// Sums of correlations with several maps (the kernel matcher's wall score and CES on different
// rasters) equal the sum of the direct correlations.
TEST(FftCorrelator, SumOfCorrelationsEqualsDirectSum) {
  cv::RNG rng(17);
  const int R = 4;
  cv::Mat a(37, 29, CV_32F), b(37, 29, CV_32F), ka(2 * R + 1, 2 * R + 1, CV_32F), kb(2 * R + 1, 2 * R + 1, CV_32F);
  for (cv::Mat* m : {&a, &b}) {
    rng.fill(*m, cv::RNG::UNIFORM, 0.0, 1.0);
    cv::threshold(*m, *m, 0.8, 1.0, cv::THRESH_BINARY);
  }
  rng.fill(ka, cv::RNG::UNIFORM, -1.0, 1.0);
  rng.fill(kb, cv::RNG::UNIFORM, -1.0, 1.0);
  const FftCorrelator corr(std::vector<cv::Mat>{a, b}, R);
  EXPECT_EQ(corr.num_maps(), 2);
  auto ws = corr.make_workspace();
  corr.run_sum({&ka, &kb}, *ws);
  const cv::Mat slow = direct_correlation(a, ka) + direct_correlation(b, kb);
  double worst = 0.0;
  for (int r = 0; r < a.rows; ++r)
    for (int c = 0; c < a.cols; ++c) worst = std::max(worst, std::abs(corr.result_row(*ws, r)[c] - slow.at<double>(r, c)));
  EXPECT_LT(worst, 1e-4);
  EXPECT_THROW(corr.run_sum({&ka}, *ws), std::invalid_argument);
}

TEST(FftCorrelator, SizesAndErrors) {
  EXPECT_EQ(next_fast_fft_size(1), 1);
  EXPECT_EQ(next_fast_fft_size(11), 12);
  EXPECT_EQ(next_fast_fft_size(97), 100);
  EXPECT_EQ(next_fast_fft_size(696), 720);
  EXPECT_EQ(next_fast_fft_size(1021), 1024);
  const FftCorrelator corr(cv::Mat::zeros(10, 10, CV_32F), 3);
  auto ws = corr.make_workspace();
  cv::Mat out;
  EXPECT_THROW(corr.correlate(cv::Mat::zeros(5, 5, CV_32F), out, *ws), std::invalid_argument);
  EXPECT_THROW(FftCorrelator(cv::Mat::zeros(10, 10, CV_8U), 3), std::invalid_argument);
}

}  // namespace
}  // namespace floorcast
