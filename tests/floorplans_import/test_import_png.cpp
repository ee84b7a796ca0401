// Occupancy-image importer: known answers on an F3Loc-style fixture, and a round trip
// plan -> raster -> PNG -> import -> raster with stated tolerances.
#include <gtest/gtest.h>

#include "common/scratch_dir.hpp"

#include <cstdio>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/import.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "import_test_util.hpp"

namespace floorcast {
namespace {

using test::data_path;
using test::distance_to_walls;
using test::expect_input_error;
using test::find_wall;

ImportOptions png_options(double res) {
  ImportOptions o;
  o.resolution_m_per_px = res;
  return o;
}

TEST(ImportPng, F3LocStyleFixtureGivesItsSixWalls) {
  // Image 160 x 100 px at 0.05 m/px (see make_fixtures.py): 4 px (0.2 m) gray walls; outer box
  // centrelines x 0.6 / 7.4, y 0.6 / 4.4; interior wall x = 4.0 from the top down to y = 2.0;
  // door gap x 1.5 .. 2.4 in the bottom wall; a one-pixel speck.
  const ImportResult r = import_floor_plan(data_path("png/two_rooms_f3loc.png"), ImportFormat::kPng, png_options(0.05));
  const FloorPlan& p = r.plan;
  ASSERT_EQ(p.walls.size(), 6u);
  const double tol = 0.0125;  // a quarter pixel
  EXPECT_NE(find_wall(p, {0.6, 4.4}, {7.4, 4.4}, tol), nullptr);
  EXPECT_NE(find_wall(p, {0.6, 0.6}, {0.6, 4.4}, tol), nullptr);
  EXPECT_NE(find_wall(p, {7.4, 0.6}, {7.4, 4.4}, tol), nullptr);
  EXPECT_NE(find_wall(p, {0.6, 0.6}, {1.5, 0.6}, tol), nullptr);
  EXPECT_NE(find_wall(p, {2.4, 0.6}, {7.4, 0.6}, tol), nullptr);
  EXPECT_NE(find_wall(p, {4.0, 4.4}, {4.0, 2.0}, tol), nullptr);  // T-junction and free end
  for (const Wall& w : p.walls) EXPECT_NEAR(w.thickness_m, 0.2, 0.0125);
  ASSERT_EQ(r.notes.size(), 1u);
  EXPECT_NE(r.notes[0].find("1 occupied speck"), std::string::npos);
}

TEST(ImportPng, OriginOptionShiftsTheImage) {
  ImportOptions o = png_options(0.05);
  o.png_origin_m = Vec2(-10.0, 20.0);
  const ImportResult r = import_floor_plan(data_path("png/two_rooms_f3loc.png"), ImportFormat::kPng, o);
  EXPECT_NE(find_wall(r.plan, {-9.4, 24.4}, {-2.6, 24.4}, 0.0125), nullptr);
}

/// A plan with thick and thin walls, a T-junction, an open door (a gap), a closed door (drawn as
/// wall), and a free-standing wall at about 31 degrees.
FloorPlan round_trip_plan() {
  FloorPlan p;
  p.name = "round trip";
  auto add = [&p](const char* id, Vec2 a, Vec2 b, double t) {
    Wall w;
    w.id = id;
    w.a_m = a;
    w.b_m = b;
    w.thickness_m = t;
    p.walls.push_back(w);
  };
  add("s", {0, 0}, {8, 0}, 0.2);
  add("e", {8, 0}, {8, 6}, 0.2);
  add("n", {8, 6}, {0, 6}, 0.2);
  add("w", {0, 6}, {0, 0}, 0.2);
  add("mid", {3, 0}, {3, 6}, 0.15);
  add("shelf", {3, 3.5}, {8, 3.5}, 0.1);
  add("diag", {4.5, 0.8}, {7.0, 2.3}, 0.15);
  p.doors.push_back({"open", "mid", {3, 2}, 0.9, false});
  p.doors.push_back({"shut", "shelf", {5.5, 3.5}, 0.9, true});
  validate_floor_plan(p, "round trip");
  return p;
}

/// Writes occupancy (255 = blocked, rows growing with +y) as an F3Loc image (255 free, 0
/// occupied, top row = largest y).
std::string write_f3loc_png(const cv::Mat& occupancy, const std::string& path) {
  cv::Mat img(occupancy.size(), CV_8UC1);
  for (int r = 0; r < occupancy.rows; ++r) {
    for (int c = 0; c < occupancy.cols; ++c) img.at<uchar>(occupancy.rows - 1 - r, c) = occupancy.at<uchar>(r, c) ? 0 : 255;
  }
  EXPECT_TRUE(cv::imwrite(path, img));
  return path;
}

double iou(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat inter, uni;
  cv::bitwise_and(a, b, inter);
  cv::bitwise_or(a, b, uni);
  return static_cast<double>(cv::countNonZero(inter)) / std::max(1, cv::countNonZero(uni));
}

/// The plan rotated by `angle_rad` about the origin and shifted off the pixel grid.
FloorPlan transformed(FloorPlan p, double angle_rad) {
  const Pose2 T{0.0137, 0.0291, angle_rad};
  for (Wall& w : p.walls) {
    w.a_m = T.transform(w.a_m);
    w.b_m = T.transform(w.b_m);
  }
  for (Door& d : p.doors) d.center_m = T.transform(d.center_m);
  return p;
}

class PngRoundTrip : public ::testing::TestWithParam<std::tuple<double, double>> {};

TEST_P(PngRoundTrip, KeepsOccupancyAndWallPositions) {
  const double res = std::get<0>(GetParam());
  const double angle = std::get<1>(GetParam());
  const FloorPlan truth = transformed(round_trip_plan(), angle);
  const BlockingOptions blocking;  // closed doors block, open doors are gaps
  const GridSpec grid = grid_for_plan(truth, res, 0.5);
  const cv::Mat occ = rasterize_occupancy(truth, grid, blocking);
  const test::ScratchDir scratch;
  const std::string path = write_f3loc_png(occ, scratch.file("round_trip.png"));

  ImportOptions o = png_options(res);
  o.png_origin_m = Vec2(grid.origin_x_m, grid.origin_y_m);
  const ImportResult r = import_floor_plan(path, ImportFormat::kPng, o);
  const FloorPlan& got = r.plan;

  // 1. Occupancy IoU of the re-rasterised import against the original raster.
  const cv::Mat occ2 = rasterize_occupancy(got, grid, blocking);
  const double score = iou(occ, occ2);
  EXPECT_GE(score, 0.90) << "occupancy IoU";

  // 2. Every blocking wall axis of the truth (away from its ends) lies within one pixel of an
  // imported wall centreline, and vice versa.
  const double tol = res;
  const double end_margin = 0.2;
  double worst_truth = 0.0, worst_got = 0.0;
  std::vector<Segment2> truth_axes;
  for (const Footprint& f : blocking_footprints(truth, blocking)) {
    if (f.has_axis) truth_axes.push_back(f.axis_m);
  }
  for (const Segment2& s : truth_axes) {
    const double len = s.length_m();
    for (double t = end_margin; t <= len - end_margin; t += 0.05) {
      const Vec2 q = s.a_m + (s.b_m - s.a_m) * (t / len);
      worst_truth = std::max(worst_truth, distance_to_walls(got, q));
    }
  }
  for (const Wall& w : got.walls) {
    const double len = w.length_m();
    for (double t = std::min(end_margin, 0.5 * len); t <= len - std::min(end_margin, 0.5 * len); t += 0.05) {
      const Vec2 q = w.a_m + (w.b_m - w.a_m) * (t / len);
      double best = 1e9;
      for (const Segment2& s : truth_axes) best = std::min(best, test::point_segment_distance(q, s.a_m, s.b_m));
      worst_got = std::max(worst_got, best);
    }
  }
  EXPECT_LE(worst_truth, tol) << "truth wall axis farther than 1 px from any imported wall";
  EXPECT_LE(worst_got, tol) << "imported wall farther than 1 px from any truth wall axis";

  // 3. The open door stays a gap: no imported wall crosses its centre; the closed door is wall.
  EXPECT_GT(distance_to_walls(got, truth.doors[0].center_m), 0.3);
  EXPECT_LT(distance_to_walls(got, truth.doors[1].center_m), tol);

  // 4. Thickness within a pixel (the raster quantises thickness to whole cells).
  for (const Wall& w : got.walls) {
    if (w.length_m() < 0.5) continue;
    const Vec2 mid = 0.5 * (w.a_m + w.b_m);
    double best = 1e9, thickness = 0.0;
    for (const Wall& tw : truth.walls) {
      const double d = test::point_segment_distance(mid, tw.a_m, tw.b_m);
      if (d < best) {
        best = d;
        thickness = tw.thickness_m;
      }
    }
    EXPECT_NEAR(w.thickness_m, thickness, res + 1e-9) << w.id;
  }
  // The diagonal wall comes back as one straight wall at its angle.
  bool diagonal = false;
  for (const Wall& w : got.walls) {
    const double a = std::atan2(w.b_m.y() - w.a_m.y(), w.b_m.x() - w.a_m.x());
    const double want = wrap_angle_rad(std::atan2(1.5, 2.5) + angle);
    if ((std::abs(a - want) < 0.02 || std::abs(std::abs(a - want) - M_PI) < 0.02) && w.length_m() > 2.6) diagonal = true;
  }
  EXPECT_TRUE(diagonal);
  RecordProperty("iou", std::to_string(score));
  RecordProperty("worst_truth_m", std::to_string(worst_truth));
  RecordProperty("worst_import_m", std::to_string(worst_got));
  std::printf("png round trip at %.3f m/px, rotated %.1f deg: IoU %.3f, worst truth->import %.4f m, worst "
              "import->truth %.4f m, %zu walls\n",
              res, angle * 180.0 / M_PI, score, worst_truth, worst_got, got.walls.size());
}

// PALMS rasters (0.1 m/px), the fixture's 0.05 m/px, and finer maps (0.02, F3Loc's 0.01 m/px);
// axis-aligned and rotated by 7 degrees (every wall then crosses the pixel grid).
INSTANTIATE_TEST_SUITE_P(Resolutions, PngRoundTrip,
                         ::testing::Combine(::testing::Values(0.1, 0.05, 0.02, 0.01), ::testing::Values(0.0, 7.0 * M_PI / 180.0)));

TEST(ImportPng, RefusesWhatItCannotRead) {
  expect_input_error([] { import_floor_plan(data_path("png/two_rooms_f3loc.png"), ImportFormat::kPng, {}); },
                     {"two_rooms_f3loc.png", "--resolution"});
  expect_input_error([] { import_floor_plan(data_path("png/two_rooms_f3loc.png"), ImportFormat::kPng, png_options(-1.0)); },
                     {"resolution -1"});
  expect_input_error([] { import_floor_plan(data_path("png/none.png"), ImportFormat::kPng, png_options(0.05)); },
                     {"none.png", "cannot read image"});
  expect_input_error([] { import_floor_plan(data_path("csv/bad_line.csv"), ImportFormat::kPng, png_options(0.05)); },
                     {"bad_line.csv", "cannot decode image"});
  cv::Mat deep(20, 20, CV_16UC1, cv::Scalar(0));
  expect_input_error([&] { import_png_image(deep, "deep.png", png_options(0.05)); }, {"deep.png", "8-bit"});
  cv::Mat empty(20, 20, CV_8UC1, cv::Scalar(255));
  expect_input_error([&] { import_png_image(empty, "free.png", png_options(0.05)); }, {"free.png", "every pixel is free"});
}

TEST(ImportPng, ColourImagesUseAllChannels) {
  cv::Mat img(40, 60, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::rectangle(img, cv::Point(5, 18), cv::Point(54, 21), cv::Scalar(255, 255, 0), cv::FILLED);  // red channel 0
  const ImportResult r = import_png_image(img, "c.png", png_options(0.1));
  ASSERT_EQ(r.plan.walls.size(), 1u);
  EXPECT_NEAR(r.plan.walls[0].length_m(), 5.0, 0.05);
  EXPECT_NEAR(r.plan.walls[0].thickness_m, 0.4, 0.05);
  EXPECT_NEAR(r.plan.walls[0].a_m.y(), 2.0, 0.026);  // rows 18..21 of 40 -> y 1.8 .. 2.2
}

}  // namespace
}  // namespace floorcast
