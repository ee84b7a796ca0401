#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "floorcast/eval/plot.hpp"

namespace floorcast {
namespace {

int count_colour(const cv::Mat& img, const cv::Scalar& bgr) {
  cv::Mat mask;
  cv::inRange(img, bgr, bgr, mask);
  return cv::countNonZero(mask);
}

TEST(Plot, CdfSeriesAreMonotoneAndDrawnInTheirColours) {
  std::map<std::string, std::vector<double>> errors = {{"a", {0.1, 0.2, 0.5, 3.0}}, {"b", {1.0, 2.0, 20.0}}};
  const LinePlot p = error_cdf_plot(errors, 5.0, "CDF", "position error [m]");
  ASSERT_EQ(p.series.size(), 2u);
  for (const auto& s : p.series) {
    for (std::size_t i = 1; i < s.y.size(); ++i) EXPECT_GE(s.y[i], s.y[i - 1]);
    for (double x : s.x) EXPECT_LE(x, 5.0);
  }
  EXPECT_DOUBLE_EQ(p.series[0].y.back(), 1.0);            // all of a's errors are <= 5 m
  EXPECT_NEAR(p.series[1].y.back(), 2.0 / 3.0, 1e-12);   // b's 20 m error is beyond the axis
  const cv::Mat img = draw_line_plot(p);
  EXPECT_EQ(img.cols, p.width_px);
  EXPECT_EQ(img.rows, p.height_px);
  EXPECT_GT(count_colour(img, series_colour(0)), 100);
  EXPECT_GT(count_colour(img, series_colour(1)), 100);
}

TEST(Plot, CategoricalAxis) {
  LinePlot p;
  p.x_categories = {"full", "partial", "single"};
  p.series = {{"kernel", {0, 1, 2}, {0.9, 0.6, 0.3}, {}, {}}};
  p.draw_markers = true;
  const cv::Mat img = draw_line_plot(p);
  EXPECT_GT(count_colour(img, series_colour(0)), 50);
}

}  // namespace
}  // namespace floorcast
