#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc.hpp>
#include <random>

#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/floorplans/rooms.hpp"
#include "test_plans.hpp"

namespace floorcast {
namespace {

/// Brute-force point-in-polygon by crossing number (independent of the convex test).
bool inside_by_crossings(const std::vector<Vec2>& poly, const Vec2& p) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2 &a = poly[i], &b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (p.x() < x) in = !in;
    }
  }
  return in;
}

bool segments_cross(const Vec2& p, const Vec2& q, const Vec2& r, const Vec2& s) {
  auto orient = [](const Vec2& a, const Vec2& b, const Vec2& c) {
    return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
  };
  const double d1 = orient(r, s, p), d2 = orient(r, s, q), d3 = orient(p, q, r), d4 = orient(p, q, s);
  return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0));
}

/// Brute force: every cell against every footprint, with independent predicates.
cv::Mat brute_force_occupancy(const FloorPlan& plan, const GridSpec& g, const BlockingOptions& o) {
  const auto fps = blocking_footprints(plan, o);
  cv::Mat occ(g.height_px, g.width_px, CV_8U, cv::Scalar(0));
  const double res = g.resolution_m_per_px;
  for (int r = 0; r < g.height_px; ++r)
    for (int c = 0; c < g.width_px; ++c) {
      const Vec2 center = g.cell_center_m(r, c);
      const Vec2 lo(g.origin_x_m + c * res, g.origin_y_m + r * res), hi = lo + Vec2(res, res);
      for (const auto& f : fps) {
        if (inside_by_crossings(f.polygon_m, center)) { occ.at<uint8_t>(r, c) = 255; break; }
        if (!f.has_axis) continue;
        const Vec2 a = f.axis_m.a_m, b = f.axis_m.b_m;
        auto in_box = [&](const Vec2& p) { return p.x() >= lo.x() && p.x() <= hi.x() && p.y() >= lo.y() && p.y() <= hi.y(); };
        const Vec2 corners[4] = {lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}};
        bool hit = in_box(a) || in_box(b);
        for (int k = 0; k < 4 && !hit; ++k) hit = segments_cross(a, b, corners[k], corners[(k + 1) % 4]);
        if (hit) { occ.at<uint8_t>(r, c) = 255; break; }
      }
    }
  return occ;
}

TEST(Raster, OccupancyEqualsBruteForceOnRandomPlans) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.3, 9.7), ang(0.0, 6.283), th(0.02, 0.4), len(0.3, 5.0);
  for (int trial = 0; trial < 6; ++trial) {
    FloorPlan p;
    for (int i = 0; i < 15; ++i) {
      const Vec2 a(u(rng), u(rng));
      const double t = ang(rng);
      p.walls.push_back({"w" + std::to_string(i), a, a + len(rng) * Vec2(std::cos(t), std::sin(t)), th(rng),
                         WallMaterial::kSolid, 0.0, {}});
    }
    const double res = trial % 2 ? 0.1 : 0.137;
    const GridSpec g = grid_for_plan(p, res, 0.5);
    const cv::Mat fast = rasterize_occupancy(p, g, {});
    const cv::Mat slow = brute_force_occupancy(p, g, {});
    EXPECT_EQ(cv::countNonZero(fast != slow), 0) << "trial " << trial;
    EXPECT_GT(cv::countNonZero(fast), 100);
  }
}

/// The rasterizer before issue 28: every cell of each footprint's bounding box (one cell of margin)
/// through the same predicates; the row-span painting must give the same cells.
cv::Mat bounding_box_occupancy(const FloorPlan& plan, const GridSpec& g, const BlockingOptions& o) {
  cv::Mat occ(g.height_px, g.width_px, CV_8U, cv::Scalar(0));
  const double res = g.resolution_m_per_px;
  for (const Footprint& f : blocking_footprints(plan, o)) {
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (const Vec2& p : f.polygon_m) {
      x0 = std::min(x0, p.x());
      y0 = std::min(y0, p.y());
      x1 = std::max(x1, p.x());
      y1 = std::max(y1, p.y());
    }
    const Vec2 g0 = g.world_to_grid({x0, y0}), g1 = g.world_to_grid({x1, y1});
    const int c0 = std::max(0, static_cast<int>(std::floor(g0.x())) - 1), r0 = std::max(0, static_cast<int>(std::floor(g0.y())) - 1);
    const int c1 = std::min(g.width_px - 1, static_cast<int>(std::floor(g1.x())) + 1);
    const int r1 = std::min(g.height_px - 1, static_cast<int>(std::floor(g1.y())) + 1);
    for (int r = r0; r <= r1; ++r) {
      for (int c = c0; c <= c1; ++c) {
        bool hit = point_in_convex_polygon(f.polygon_m, g.cell_center_m(r, c));
        if (!hit && f.has_axis) {
          Vec2 a = f.axis_m.a_m, b = f.axis_m.b_m;
          // The cell's box, starting just after the previous cell's box where that ends short of it.
          const double bx0 = g.origin_x_m + c * res, by0 = g.origin_y_m + r * res;
          const double ex = g.origin_x_m + (c - 1) * res + res, ey = g.origin_y_m + (r - 1) * res + res;
          hit = clip_segment_to_box(a, b, ex < bx0 ? std::nextafter(ex, bx0) : bx0, ey < by0 ? std::nextafter(ey, by0) : by0,
                                    bx0 + res, by0 + res);
        }
        if (hit) occ.at<std::uint8_t>(r, c) = 255;
      }
    }
  }
  return occ;
}

// Long diagonal walls (their bounding box is mostly empty: the rasterizer paints row spans, issue
// 28), thin ones painted by their axis, at resolutions that do not divide the coordinates, and
// walls on cell borders and cell centres: the same cells as the bounding-box scan, and (away from
// those ties, which the independent predicates may break the other way) as the brute force.
TEST(Raster, LongDiagonalAndThinWallsEqualTheBoundingBoxScan) {
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> u(0.0, 12.0), ang(0.0, 6.283), th(0.005, 0.3), len(4.0, 15.0);
  int painted = 0;
  for (int trial = 0; trial < 6; ++trial) {
    FloorPlan p;
    for (int i = 0; i < 12; ++i) {
      const Vec2 a(u(rng), u(rng));
      const double t = ang(rng);
      p.walls.push_back({"w" + std::to_string(i), a, a + len(rng) * Vec2(std::cos(t), std::sin(t)), th(rng),
                         WallMaterial::kSolid, 0.0, {}});
    }
    const double res = trial % 3 == 0 ? 0.1 : (trial % 3 == 1 ? 0.137 : 0.05);
    const GridSpec g = grid_for_plan(p, res, 0.5);
    const cv::Mat fast = rasterize_occupancy(p, g, {});
    EXPECT_EQ(cv::countNonZero(fast != brute_force_occupancy(p, g, {})), 0) << "trial " << trial;
    FloorPlan ties = p;
    ties.walls.push_back({"grid_aligned", {1.0, 1.0}, {3.0, 3.0}, 0.05, WallMaterial::kSolid, 0.0, {}});
    ties.walls.push_back({"flat", {0.25, 2.05}, {9.75, 2.05}, 0.01, WallMaterial::kSolid, 0.0, {}});
    ties.walls.push_back({"upright", {7.05, 0.5}, {7.05, 11.5}, 0.01, WallMaterial::kSolid, 0.0, {}});
    ties.walls.push_back({"point", {5.0, 5.0}, {5.0, 5.0}, 0.2, WallMaterial::kSolid, 0.0, {}});
    const GridSpec gt = grid_for_plan(ties, res, 0.5);
    const cv::Mat fast_ties = rasterize_occupancy(ties, gt, {});
    EXPECT_EQ(cv::countNonZero(fast_ties != bounding_box_occupancy(ties, gt, {})), 0) << "trial " << trial;
    painted += cv::countNonZero(fast) + cv::countNonZero(fast_ties);
  }
  EXPECT_GT(painted, 5000);
}

// A thin wall whose axis lies between where one cell's box ends (origin + c res + res) and where
// the next one's begins (origin + (c + 1) res), which differ by an ulp for some origins and
// resolutions: it must still be painted (it met neither box, and a generated campus lost its
// glass facade from the raster so). Searched over origins and columns for such gaps, both axes.
TEST(Raster, AWallBetweenTwoCellsBoxesIsPainted) {
  int gaps = 0;
  for (int k = 0; k < 200 && gaps < 20; ++k) {
    GridSpec g;  // origins as grid_for_plan makes them
    g.resolution_m_per_px = 0.1;
    g.origin_x_m = std::floor(-0.1 * k / 0.1) * 0.1;
    g.origin_y_m = std::floor((-0.1 * k - 3.0) / 0.1) * 0.1;
    g.width_px = g.height_px = 400;
    for (int c = 1; c < 399 && gaps < 20; ++c) {
      const double end = g.origin_x_m + (c - 1) * 0.1 + 0.1, begin = g.origin_x_m + c * 0.1;
      if (!(end < begin)) continue;
      const double x = std::nextafter(end, begin);  // in the gap (end, begin) when it holds a double
      if (!(x < begin)) continue;
      ++gaps;
      for (int axis = 0; axis < 2; ++axis) {
        FloorPlan p;
        const double y0 = g.origin_y_m + 1.0, y1 = g.origin_y_m + 5.0;
        // The flat wall on the grid with the origins swapped: its y lies in the same gap.
        p.walls.push_back(axis == 0 ? Wall{"upright", {x, y0}, {x, y1}, 0.01, WallMaterial::kSolid, 0.0, {}}
                                    : Wall{"flat", {y0, x}, {y1, x}, 0.01, WallMaterial::kSolid, 0.0, {}});
        GridSpec gg = g;
        std::swap(gg.origin_x_m, gg.origin_y_m);
        const cv::Mat occ = rasterize_occupancy(p, axis == 0 ? g : gg, {});
        // Every row (column) the wall spans has a painted cell: the wall is watertight.
        for (int i = 12; i < 48; ++i) {  // the wall spans cells 10-50
          const cv::Mat line = axis == 0 ? occ.row(i) : occ.col(i);
          EXPECT_GT(cv::countNonZero(line), 0) << "origin " << g.origin_x_m << " column " << c << (axis ? " (flat)" : " (upright)");
        }
      }
    }
  }
  EXPECT_GT(gaps, 0) << "no origin with a gap between cell boxes found: the test would not test anything";
}

// A box obstacle thinner than a cell (a 5 cm cubicle partition; at yaw 0 between two rows of cell
// centres, so it contains none), at four orientations: it is painted all along (its medial segment),
// so sampling keeps its clearance from it and never stands on it. A box thicker than a cell's
// diagonal rasterises exactly as by cell centres alone.
TEST(Raster, ABoxThinnerThanACellIsPainted) {
  GridSpec g;
  g.resolution_m_per_px = 0.1;
  g.origin_x_m = g.origin_y_m = 0.0;
  g.width_px = g.height_px = 100;
  BlockingOptions standing;
  standing.obstacles_block = true;
  standing.cut_height_m = 0.01;
  for (const double yaw : {0.0, kPi / 2.0, kPi / 6.0, kPi / 4.0}) {
    FloorPlan p;
    // Centre 0.05 m off the row of centres at y = 5.05 (0.0: between rows 49 and 50's centres).
    p.obstacles.push_back(Obstacle{"cubicle", ObstacleKind::kBox, Vec2(5.0, 5.0), Vec2(1.5, 0.05), yaw, 2.0});
    const cv::Mat occ = rasterize_occupancy(p, g, standing);
    const Vec2 u(std::cos(yaw), std::sin(yaw));
    for (double t = -0.7; t <= 0.7; t += 0.05) {  // along the partition, short of its ends
      const Vec2 q = Vec2(5.0, 5.0) + t * u;
      EXPECT_EQ(occ.at<std::uint8_t>(static_cast<int>(q.y() / 0.1), static_cast<int>(q.x() / 0.1)), 255)
          << "yaw " << yaw << " at " << t;
    }
  }
  // Thick boxes: the cells painted are exactly those whose centre lies in the box.
  for (const double yaw : {0.0, 0.3, kPi / 4.0, 1.2}) {
    FloorPlan p;
    p.obstacles.push_back(Obstacle{"desk", ObstacleKind::kBox, Vec2(5.03, 4.98), Vec2(1.6, 0.8), yaw, 0.75});
    const cv::Mat occ = rasterize_occupancy(p, g, standing);
    const Obstacle& o = p.obstacles.front();
    for (int r = 0; r < g.height_px; ++r) {
      for (int c = 0; c < g.width_px; ++c) {
        const Vec2 d = g.cell_center_m(r, c) - o.center_m;
        const double along = std::cos(yaw) * d.x() + std::sin(yaw) * d.y();
        const double across = -std::sin(yaw) * d.x() + std::cos(yaw) * d.y();
        const bool inside = std::abs(along) <= 0.8 && std::abs(across) <= 0.4;
        EXPECT_EQ(occ.at<std::uint8_t>(r, c) == 255, inside) << "yaw " << yaw << " cell " << r << "," << c;
      }
    }
  }
}

TEST(Raster, ZhangSuenThinningEqualsOpenCvXimgproc) {
  // Random blobs and bars (rectangles, discs, thick lines) on 0/255 images: floorcast's thinning
  // must give exactly OpenCV ximgproc's pixels, the reference it replaces.
  cv::RNG rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    cv::Mat img = cv::Mat::zeros(60 + trial, 80, CV_8UC1);
    for (int k = 0; k < 6; ++k) {
      const cv::Point a(rng.uniform(2, img.cols - 2), rng.uniform(2, img.rows - 2));
      const cv::Point b(rng.uniform(2, img.cols - 2), rng.uniform(2, img.rows - 2));
      switch (k % 3) {
        case 0: cv::rectangle(img, a, b, 255, cv::FILLED); break;
        case 1: cv::circle(img, a, rng.uniform(1, 12), 255, cv::FILLED); break;
        default: cv::line(img, a, b, 255, rng.uniform(1, 9)); break;
      }
    }
    if (trial % 4 == 0) img.row(0).setTo(255);  // foreground on the border stays untouched
    cv::Mat expected;
    cv::ximgproc::thinning(img, expected, cv::ximgproc::THINNING_ZHANGSUEN);
    const cv::Mat ours = thin_zhang_suen(img);
    ASSERT_EQ(cv::norm(expected, ours, cv::NORM_INF), 0.0) << "trial " << trial;
  }
}

TEST(Raster, ThinGlassStaysWatertightAndFlagsWork) {
  const FloorPlan p = test::furnished_room();
  const GridSpec g = grid_for_plan(p, 0.1);
  BlockingOptions glass_open;
  glass_open.glass_blocks = false;
  const cv::Mat with_glass = rasterize_occupancy(p, g, {});
  const cv::Mat without_glass = rasterize_occupancy(p, g, glass_open);
  EXPECT_GT(cv::countNonZero(with_glass), cv::countNonZero(without_glass));
  // Every row crossing the 5 cm glass wall at x = 6 has a blocked cell there.
  for (double y = 0.5; y < 3.5; y += 0.1) {
    int r, c;
    ASSERT_TRUE(g.world_to_cell({6.0, y}, r, c));
    EXPECT_TRUE(with_glass.at<uint8_t>(r, c) || with_glass.at<uint8_t>(r, c - 1)) << y;
  }
  // The closed door blocks by default; open_doors_block closes the open one too.
  BlockingOptions doors_free;
  doors_free.closed_doors_block = false;
  EXPECT_LT(cv::countNonZero(rasterize_occupancy(p, g, doors_free)), cv::countNonZero(with_glass));
  BlockingOptions all_closed;
  all_closed.open_doors_block = true;
  EXPECT_GT(cv::countNonZero(rasterize_occupancy(p, g, all_closed)), cv::countNonZero(with_glass));
}

TEST(Raster, ValidMaskIsTheRoomInterior) {
  FloorPlan p = test::box_room(5.0, 4.0, 0.2);
  p.doors.push_back({"d", "south", {2.5, 0.0}, 1.0, false});  // open door: the inside stays interior
  const PlanRasters r = make_plan_rasters(p, {});
  const double area = cv::countNonZero(r.valid) * 0.01;
  EXPECT_NEAR(area, 4.8 * 3.8, 0.6);  // within boundary cells
  int row, col;
  ASSERT_TRUE(r.grid.world_to_cell({2.5, 2.0}, row, col));
  EXPECT_TRUE(r.valid.at<uint8_t>(row, col));
  ASSERT_TRUE(r.grid.world_to_cell({2.5, -0.6}, row, col));
  EXPECT_FALSE(r.valid.at<uint8_t>(row, col));
}

TEST(Raster, DistanceTransformEqualsBruteForce) {
  const FloorPlan p = test::furnished_room();
  const PlanRasters r = make_plan_rasters(p, {});
  std::vector<cv::Point> blocked;
  cv::findNonZero(r.occupancy, blocked);
  ASSERT_FALSE(blocked.empty());
  for (int row = 0; row < r.grid.height_px; row += 3)
    for (int col = 0; col < r.grid.width_px; col += 3) {
      double best = 1e18;
      for (const cv::Point& b : blocked) best = std::min(best, std::hypot(b.x - col, b.y - row));
      EXPECT_NEAR(r.distance_m.at<float>(row, col), best * 0.1, 1e-4) << row << "," << col;
    }
}

TEST(Raster, FreeFloorAreaOfABoxRoom) {
  EXPECT_NEAR(free_floor_area_m2(test::box_room(5.0, 4.0, 0.2)), 4.8 * 3.8, 0.3);
  // Obstacles take floor area.
  FloorPlan p = test::box_room(5.0, 4.0, 0.2);
  p.obstacles.push_back({"b", ObstacleKind::kBox, {2.5, 2.0}, {2.0, 1.0}, 0.0, 0.8});
  EXPECT_NEAR(free_floor_area_m2(p), 4.8 * 3.8 - 2.0, 0.3);
}

TEST(Raster, GridsAlignAcrossPlans) {
  const GridSpec g = grid_for_plan(test::box_room(), 0.1);
  EXPECT_NEAR(std::remainder(g.origin_x_m, 0.1), 0.0, 1e-9);
  int r, c;
  EXPECT_TRUE(g.world_to_cell({0.0, 0.0}, r, c));
  EXPECT_FALSE(g.world_to_cell({100.0, 0.0}, r, c));
}

}  // namespace
}  // namespace floorcast

namespace floorcast {
namespace {

TEST(Raster, ValidMaskHasNoPatchesOutsideConcaveCorners) {
  // An L-shaped building: the closing radius fills the outside of the concave corner, which
  // must not become "interior".
  FloorPlan p;
  const double t = 0.3;
  const std::vector<Vec2> pts = {{0, 0}, {10, 0}, {10, 4}, {4, 4}, {4, 10}, {0, 10}};
  for (std::size_t i = 0; i < pts.size(); ++i)
    p.walls.push_back({"w" + std::to_string(i), pts[i], pts[(i + 1) % pts.size()], t, WallMaterial::kSolid, 0.0, {}});
  const PlanRasters r = make_plan_rasters(p, {});
  for (int row = 0; row < r.grid.height_px; ++row)
    for (int col = 0; col < r.grid.width_px; ++col) {
      if (!r.valid.at<uint8_t>(row, col)) continue;
      const Vec2 c = r.grid.cell_center_m(row, col);
      const bool inside = c.x() > 0 && c.y() > 0 && (c.x() < 4 || c.y() < 4) && c.x() < 10 && c.y() < 10;
      EXPECT_TRUE(inside) << "valid cell outside the building at " << c.transpose();
    }
  EXPECT_NEAR(cv::countNonZero(r.valid) * 0.01, 10 * 10 - 6 * 6 - (2 * 10 + 2 * 10 + 6 + 6) * t / 2 * 1.0, 3.0);
}

TEST(Plan, BoundingBoxOfRotatedBoxesIsExact) {
  FloorPlan p = test::box_room(5.0, 4.0, 0.2);
  p.obstacles.push_back({"b", ObstacleKind::kBox, {2.5, 2.0}, {2.0, 0.0001}, 0.0, 1.0});
  p.obstacles.push_back({"far", ObstacleKind::kBox, {8.0, 2.0}, {2.0, 1.0}, 1.5707963267948966, 1.0});
  const Eigen::Vector4d b = plan_bbox_m(p);
  EXPECT_NEAR(b[0], -0.1, 1e-9);
  EXPECT_NEAR(b[2], 8.5, 1e-9);  // rotated 90 deg: depth 1.0 along x
}


// room_index_raster is a scanline fill (a fuzzing finding: the per-cell point-in-polygon test cost
// cells x vertices); it must decide every cell exactly as the slow, obvious version does:
// room_at() of each cell centre (smallest containing room, holes excluded, ties to the first).
// Random non-convex and self-intersecting outlines, holes (some sticking out of the outline,
// some overlapping each other), nested rooms of equal area, vertices on cell centres and on
// cell edges, rooms partly off the grid and one far-away vertex.
TEST(RoomIndexRaster, EqualsRoomAtOfEveryCellCentre) {
  std::mt19937 rng(20261127);
  const GridSpec g{-3.0, -2.0, 0.25, 96, 80};  // origin x, y, resolution, width, height
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto snap = [&](double v, int mode) {
    // 0: free, 1: on a cell centre, 2: on a cell edge (of the grid above)
    if (mode == 0) return v;
    const double k = std::round(v / 0.25);
    return k * 0.25 + (mode == 1 ? 0.125 : 0.0);
  };
  auto ring = [&](double cx, double cy, double r, int n, int mode) {
    std::vector<Vec2> out;
    for (int k = 0; k < n; ++k) {
      const double a = 2.0 * M_PI * (k + 0.3 * u(rng)) / n;
      const double rr = r * (0.35 + 0.65 * u(rng));
      out.emplace_back(snap(cx + rr * std::cos(a), mode), snap(cy + rr * std::sin(a), mode));
    }
    return out;
  };
  int cells_in_rooms = 0, cells_in_holes = 0;
  for (int trial = 0; trial < 60; ++trial) {
    std::vector<Room> rooms;
    const int nrooms = 1 + trial % 6;
    for (int k = 0; k < nrooms; ++k) {
      Room room;
      room.id = "r" + std::to_string(k);
      room.kind = "office";
      const int mode = (trial + k) % 3;
      const double cx = -4.0 + 30.0 * u(rng), cy = -3.0 + 24.0 * u(rng);
      room.polygon_m = ring(cx, cy, 2.0 + 8.0 * u(rng), 3 + static_cast<int>(20 * u(rng)), mode);
      if (k % 4 == 3) std::shuffle(room.polygon_m.begin(), room.polygon_m.end(), rng);  // self-intersecting
      for (int h = 0; h < (k + trial) % 3; ++h) room.holes_m.push_back(ring(cx + 2.0 * (u(rng) - 0.5), cy, 2.5, 5, mode));
      rooms.push_back(room);
      if (k % 5 == 1) rooms.push_back(room);  // an identical room: equal area, the first wins
    }
    if (trial % 10 == 9) rooms.back().polygon_m.push_back(Vec2(3.0e5, 10.0));  // one far-away vertex
    const cv::Mat fast = room_index_raster(rooms, g);
    ASSERT_EQ(fast.type(), CV_32S);
    ASSERT_EQ(fast.rows, g.height_px);
    ASSERT_EQ(fast.cols, g.width_px);
    for (int r = 0; r < g.height_px; ++r) {
      for (int c = 0; c < g.width_px; ++c) {
        const Vec2 p = g.cell_center_m(r, c);
        const int expected = room_at(rooms, p);
        ASSERT_EQ(fast.at<int>(r, c), expected) << "trial " << trial << " cell (" << r << ", " << c << ")";
        if (expected >= 0) ++cells_in_rooms;
        for (const Room& room : rooms) {
          for (const auto& hole : room.holes_m) cells_in_holes += point_in_polygon(room.polygon_m, p) && point_in_polygon(hole, p);
        }
      }
    }
  }
  // The cases were not vacuous: many cells in rooms, many excluded by holes.
  EXPECT_GT(cells_in_rooms, 50000);
  EXPECT_GT(cells_in_holes, 2000);
}

}  // namespace
}  // namespace floorcast
