#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>

#include "floorcast/match/posterior.hpp"
#include "floorcast/eval/heatmap.hpp"
#include "floorcast/core/math.hpp"

namespace floorcast {
namespace {


Posterior make_posterior(int slices, int h, int w) {
  Posterior p;
  p.grid.origin_x_m = -1.0;
  p.grid.origin_y_m = 2.0;
  p.grid.resolution_m_per_px = 0.1;
  p.grid.width_px = w;
  p.grid.height_px = h;
  for (int s = 0; s < slices; ++s) {
    p.yaw_rad.push_back(2.0 * kPi * s / slices);
    p.scores.push_back(cv::Mat::zeros(h, w, CV_32F));
  }
  return p;
}

TEST(Posterior, ArgmaxAndTies) {
  Posterior p = make_posterior(4, 20, 30);
  p.scores[2].at<float>(5, 7) = 3.0f;
  p.scores[1].at<float>(9, 9) = 2.0f;
  PoseHypothesis h = p.argmax();
  EXPECT_EQ(h.slice, 2);
  EXPECT_EQ(h.row, 5);
  EXPECT_EQ(h.col, 7);
  EXPECT_NEAR(h.x_m, -1.0 + 7.5 * 0.1, 1e-12);
  EXPECT_NEAR(h.y_m, 2.0 + 5.5 * 0.1, 1e-12);
  EXPECT_NEAR(h.yaw_rad, kPi, 1e-12);
  EXPECT_EQ(h.score, 3.0);
  // Ties: lowest slice, then row, then column.
  p.scores[1].at<float>(12, 3) = 3.0f;
  p.scores[1].at<float>(12, 1) = 3.0f;
  h = p.argmax();
  EXPECT_EQ(h.slice, 1);
  EXPECT_EQ(h.row, 12);
  EXPECT_EQ(h.col, 1);
  EXPECT_NO_THROW(p.check());
  p.scores[0].at<float>(0, 0) = -1.0f;
  EXPECT_THROW(p.check(), std::invalid_argument);
}

TEST(Posterior, TopKNonMaximumSuppressionKnownAnswer) {
  // 8 slices of 45 deg; a 1 m x 30 deg suppression window.
  Posterior p = make_posterior(8, 60, 60);
  auto set = [&](int s, int r, int c, float v) { p.scores[static_cast<std::size_t>(s)].at<float>(r, c) = v; };
  set(0, 10, 10, 10.0f);  // A: best
  set(0, 10, 15, 9.0f);   // 0.5 m from A, same yaw: suppressed
  set(0, 10, 20, 8.5f);   // exactly 1.0 m from A: suppressed (<=)
  set(0, 10, 21, 8.0f);   // 1.1 m from A: kept (B)
  set(1, 10, 10, 7.0f);   // same cell as A, 45 deg away (> 30 deg): kept (C)
  set(7, 40, 40, 6.0f);   // far: kept (D)
  set(7, 40, 42, 5.0f);   // 0.2 m from D, same yaw: suppressed
  set(0, 50, 50, 4.0f);   // E
  const auto modes = p.top_k(10, 1.0, 30.0 * kPi / 180.0);
  ASSERT_EQ(modes.size(), 4u + 1u);
  EXPECT_EQ(modes[0].score, 10.0);
  EXPECT_EQ(modes[1].score, 8.0);
  EXPECT_EQ(modes[1].col, 21);
  EXPECT_EQ(modes[2].score, 7.0);
  EXPECT_EQ(modes[2].slice, 1);
  EXPECT_EQ(modes[3].score, 6.0);
  EXPECT_EQ(modes[4].score, 4.0);
  // k limits the count; modes come in descending order.
  const auto two = p.top_k(2, 1.0, 30.0 * kPi / 180.0);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[1].score, 8.0);
  // A yaw window wider than 45 deg also suppresses C.
  const auto wide = p.top_k(10, 1.0, 50.0 * kPi / 180.0);
  for (const auto& m : wide) EXPECT_NE(m.score, 7.0);
  // Zero posterior: no modes.
  EXPECT_TRUE(make_posterior(2, 5, 5).top_k(3).empty());
}

TEST(Posterior, TopKMatchesBruteForceGreedy) {
  // Random posterior: the fast greedy NMS equals the obvious sort-then-accept version.
  Posterior p = make_posterior(6, 25, 31);
  cv::RNG rng(7);
  for (auto& m : p.scores) {
    rng.fill(m, cv::RNG::UNIFORM, 0.0, 1.0);
    cv::threshold(m, m, 0.7, 0.0, cv::THRESH_TOZERO);
  }
  const double sep_m = 0.45, sep_rad = 70.0 * kPi / 180.0;
  struct Cand {
    float v;
    int s, r, c;
  };
  std::vector<Cand> all;
  for (int s = 0; s < 6; ++s)
    for (int r = 0; r < 25; ++r)
      for (int c = 0; c < 31; ++c)
        if (p.scores[s].at<float>(r, c) > 0) all.push_back({p.scores[s].at<float>(r, c), s, r, c});
  std::stable_sort(all.begin(), all.end(), [](const Cand& a, const Cand& b) { return a.v > b.v; });
  std::vector<Cand> accepted;
  for (const Cand& c : all) {
    bool ok = true;
    for (const Cand& a : accepted) {
      const double d = 0.1 * std::hypot(c.r - a.r, c.c - a.c);
      if (d <= sep_m && angle_distance_rad(p.yaw_rad[c.s], p.yaw_rad[a.s]) <= sep_rad) ok = false;
    }
    if (ok) accepted.push_back(c);
    if (accepted.size() == 40) break;
  }
  const auto modes = p.top_k(40, sep_m, sep_rad);
  ASSERT_EQ(modes.size(), accepted.size());
  for (std::size_t i = 0; i < modes.size(); ++i) {
    EXPECT_EQ(modes[i].score, accepted[i].v) << i;
    EXPECT_EQ(modes[i].slice, accepted[i].s) << i;
    EXPECT_EQ(modes[i].row, accepted[i].r) << i;
    EXPECT_EQ(modes[i].col, accepted[i].c) << i;
  }
}

TEST(Posterior, PdfAndMaxOverYaw) {
  Posterior p = make_posterior(3, 4, 5);
  p.scores[0].at<float>(1, 1) = 1.0f;
  p.scores[1].at<float>(1, 1) = 3.0f;
  p.scores[2].at<float>(2, 3) = 4.0f;
  const auto pdf = p.normalised_pdf();
  double sum = 0.0;
  for (const auto& m : pdf) sum += cv::sum(m)[0];
  EXPECT_NEAR(sum, 1.0, 1e-6);
  EXPECT_NEAR(pdf[2].at<float>(2, 3), 0.5, 1e-6);
  const cv::Mat mx = p.max_over_yaw();
  EXPECT_EQ(mx.at<float>(1, 1), 3.0f);
  EXPECT_EQ(mx.at<float>(2, 3), 4.0f);
  EXPECT_EQ(mx.at<float>(0, 0), 0.0f);
  const auto zero = make_posterior(2, 3, 3).normalised_pdf();
  EXPECT_EQ(cv::countNonZero(zero[0]), 0);
}

TEST(Posterior, HeatmapImage) {
  Posterior p = make_posterior(2, 40, 60);
  p.scores[1].at<float>(30, 10) = 1.0f;
  cv::Mat raster = cv::Mat::zeros(40, 60, CV_8U);
  raster.row(0).setTo(255);
  PoseHypothesis truth;
  truth.x_m = -1.0 + 1.05;
  truth.y_m = 2.0 + 3.05;
  HeatmapStyle style;
  style.pixels_per_cell = 4;
  style.decorations = false;
  const cv::Mat img = render_posterior_heatmap(p, raster, truth, p.argmax(), style);
  ASSERT_EQ(img.type(), CV_8UC3);
  EXPECT_EQ(img.cols, 240);
  EXPECT_EQ(img.rows, 160);
  // Grid row 0 (walls) is drawn at the bottom of the image (+y up).
  EXPECT_EQ(img.at<cv::Vec3b>(159, 100), cv::Vec3b(0, 0, 0));
  EXPECT_NE(img.at<cv::Vec3b>(0, 100), cv::Vec3b(0, 0, 0));
  // Wrong raster size is refused.
  EXPECT_THROW(render_posterior_heatmap(p, cv::Mat::zeros(3, 3, CV_8U), std::nullopt, std::nullopt),
               std::invalid_argument);
}

/// Pixels of `img` (BGR) within `tol` of `colour`.
int count_colour(const cv::Mat& img, const cv::Vec3b& colour, int tol = 10) {
  int n = 0;
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c) {
      const cv::Vec3b v = img.at<cv::Vec3b>(r, c);
      n += std::abs(v[0] - colour[0]) <= tol && std::abs(v[1] - colour[1]) <= tol && std::abs(v[2] - colour[2]) <= tol;
    }
  return n;
}

TEST(Posterior, HeatmapDecorations) {
  Posterior p = make_posterior(2, 40, 60);
  p.scores[1].at<float>(30, 10) = 1.0f;
  p.scores[0].at<float>(20, 40) = 0.3f;
  const cv::Mat raster = cv::Mat::zeros(40, 60, CV_8U);
  PoseHypothesis truth;
  truth.x_m = -1.0 + 1.05;
  truth.y_m = 2.0 + 3.05;
  HeatmapStyle style;
  style.title = "test heatmap";
  const cv::Mat img = render_posterior_heatmap(p, raster, truth, p.argmax(), style);
  HeatmapStyle bare = style;
  bare.decorations = false;
  const cv::Mat map = render_posterior_heatmap(p, raster, truth, p.argmax(), bare);
  // Title band above, colour bar beside, scale bar and legend below the map.
  EXPECT_GT(img.rows, map.rows + 60);
  EXPECT_GT(img.cols, map.cols + 100);
  // The colour bar shows the whole colour map: its lowest (dark blue) and highest (dark red) ends.
  cv::Mat turbo;
  cv::Mat ends = (cv::Mat_<std::uint8_t>(1, 2) << 0, 255);
  cv::applyColorMap(ends, turbo, cv::COLORMAP_TURBO);
  EXPECT_GT(count_colour(img, turbo.at<cv::Vec3b>(0, 0), 6), 20);
  EXPECT_GT(count_colour(img, turbo.at<cv::Vec3b>(0, 1), 6), 20);
  // Markers: truth green and estimate red, sized to the picture (a ring of radius >= 6 px).
  EXPECT_GT(count_colour(map, cv::Vec3b(0, 170, 0), 40), 30);
  EXPECT_GT(count_colour(map, cv::Vec3b(0, 0, 230), 40), 30);
}

TEST(Posterior, HeatmapEmptyPosteriorBanner) {
  const Posterior p = make_posterior(2, 40, 60);  // every score 0
  const cv::Mat raster = cv::Mat::zeros(40, 60, CV_8U);
  HeatmapStyle bare;
  bare.decorations = false;
  const cv::Mat img = render_posterior_heatmap(p, raster, std::nullopt, std::nullopt, bare);
  // A red banner across the middle instead of a blank grey map.
  const cv::Mat middle = img.row(img.rows / 2);
  int reddish = 0;
  for (int c = 0; c < middle.cols; ++c) {
    const cv::Vec3b v = middle.at<cv::Vec3b>(0, c);
    reddish += v[2] > v[0] + 60 || (v[0] > 200 && v[1] > 200 && v[2] > 200 && v != cv::Vec3b(235, 235, 235));
  }
  EXPECT_GT(reddish, middle.cols / 2);
}

TEST(Posterior, HeatmapInsetForLargePlans) {
  // 200 m x 100 m at 0.5 m cells: the whole plan fits 1600 px at 4 px/cell = 8 px/m (< 12): inset.
  Posterior p = make_posterior(1, 200, 400);
  p.grid.resolution_m_per_px = 0.5;
  p.scores[0].at<float>(100, 200) = 1.0f;
  const cv::Mat raster = cv::Mat::zeros(200, 400, CV_8U);
  PoseHypothesis truth;
  truth.x_m = p.grid.cell_center_m(100, 202).x();
  truth.y_m = p.grid.cell_center_m(100, 202).y();
  const PoseHypothesis est = p.argmax();
  HeatmapStyle style;
  const cv::Mat with_inset = render_posterior_heatmap(p, raster, truth, est, style);
  style.inset_min_plan_m = 1e9;
  const cv::Mat without = render_posterior_heatmap(p, raster, truth, est, style);
  EXPECT_GT(with_inset.cols, without.cols + 150);  // the inset panel
  // The inset's frame on the map is magenta.
  EXPECT_GT(count_colour(with_inset, cv::Vec3b(255, 0, 255), 30), 40);
  EXPECT_EQ(count_colour(without, cv::Vec3b(255, 0, 255), 30), 0);
}

}  // namespace
}  // namespace floorcast
