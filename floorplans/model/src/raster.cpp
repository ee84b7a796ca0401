#include "floorcast/floorplans/raster.hpp"

#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/rooms.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>
#include <opencv2/imgproc.hpp>

namespace floorcast {
namespace {

/// Does segment a-b meet the closed box [x0,x1]x[y0,y1]?
bool segment_meets_box(Vec2 a, Vec2 b, double x0, double y0, double x1, double y1) {
  return clip_segment_to_box(a, b, x0, y0, x1, y1);
}

void clamp_cell_range(const GridSpec& grid, double x0, double y0, double x1, double y1, int& c0, int& r0,
                      int& c1, int& r1) {
  const Vec2 g0 = grid.world_to_grid({x0, y0});
  const Vec2 g1 = grid.world_to_grid({x1, y1});
  c0 = std::max(0, static_cast<int>(std::floor(g0.x())) - 1);
  r0 = std::max(0, static_cast<int>(std::floor(g0.y())) - 1);
  c1 = std::min(grid.width_px - 1, static_cast<int>(std::floor(g1.x())) + 1);
  r1 = std::min(grid.height_px - 1, static_cast<int>(std::floor(g1.y())) + 1);
}

/// Widens [lo, hi] by the x of every point of the edges of `pts` (a closed polygon, or the open
/// segment pts[0]-pts[1] when `closed` is false) whose y lies in [ya, yb].
void widen_by_strip(const std::vector<Vec2>& pts, bool closed, double ya, double yb, double& lo, double& hi) {
  const std::size_t n = pts.size();
  const std::size_t edges = closed ? n : (n >= 2 ? n - 1 : 0);
  for (std::size_t i = 0; i < edges; ++i) {
    const Vec2& a = pts[i];
    const Vec2& b = pts[(i + 1) % n];
    const double dy = b.y() - a.y();
    double t0 = 0.0, t1 = 1.0;
    if (dy == 0.0) {
      if (!(a.y() >= ya && a.y() <= yb)) continue;
    } else {
      const double ta = (ya - a.y()) / dy, tb = (yb - a.y()) / dy;
      t0 = std::max(t0, std::min(ta, tb));
      t1 = std::min(t1, std::max(ta, tb));
      if (!(t0 <= t1)) continue;
    }
    for (const double t : {t0, t1}) {
      const double x = a.x() + t * (b.x() - a.x());
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
  }
}

/// Paints the cells whose centre lies in the footprint's polygon, and (walls, doors, glass) every
/// cell its axis passes through. Row by row, only over the columns where the polygon or the axis
/// meets the row (widened by a row above and below and a column either side, so rounding never
/// loses a cell): the work follows the footprint's area, not its bounding box (a long diagonal
/// wall's box is ~its length squared; issue 28). The same cells as testing every cell of the box.
void paint_footprint(cv::Mat& occ, const GridSpec& grid, const Footprint& f) {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const Vec2& p : f.polygon_m) {
    x0 = std::min(x0, p.x());
    y0 = std::min(y0, p.y());
    x1 = std::max(x1, p.x());
    y1 = std::max(y1, p.y());
  }
  int c0, r0, c1, r1;
  clamp_cell_range(grid, x0, y0, x1, y1, c0, r0, c1, r1);
  const double res = grid.resolution_m_per_px;
  const std::vector<Vec2> axis = f.has_axis ? std::vector<Vec2>{f.axis_m.a_m, f.axis_m.b_m} : std::vector<Vec2>{};
  for (int r = r0; r <= r1; ++r) {
    const double ya = grid.origin_y_m + (r - 1) * res, yb = grid.origin_y_m + (r + 2) * res;
    double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
    widen_by_strip(f.polygon_m, true, ya, yb, lo, hi);
    widen_by_strip(axis, false, ya, yb, lo, hi);
    if (!(lo <= hi)) continue;
    const double g_lo = std::floor((lo - grid.origin_x_m) / res) - 1.0, g_hi = std::floor((hi - grid.origin_x_m) / res) + 1.0;
    const int ca = g_lo > c0 ? static_cast<int>(std::min<double>(g_lo, c1 + 1)) : c0;
    const int cb = g_hi < c1 ? static_cast<int>(std::max<double>(g_hi, c0 - 1)) : c1;
    std::uint8_t* row = occ.ptr<std::uint8_t>(r);
    for (int c = ca; c <= cb; ++c) {
      if (row[c]) continue;
      if (point_in_convex_polygon(f.polygon_m, grid.cell_center_m(r, c))) {
        row[c] = 255;
        continue;
      }
      if (f.has_axis) {
        // The cell's box: [origin + c res, origin + c res + res]. Where the previous cell's box
        // ends short of it (origin + (c - 1) res + res can round a few ulps below origin + c res),
        // the box starts just after that end instead: an axis in the gap met neither box, and a
        // wall on a grid line went missing from the raster (a generated campus lost its glass
        // facade so). Nothing else changes: an axis at the previous box's end stays in that cell.
        const double bx0 = grid.origin_x_m + c * res, by0 = grid.origin_y_m + r * res;
        const double end_x = grid.origin_x_m + (c - 1) * res + res, end_y = grid.origin_y_m + (r - 1) * res + res;
        const double near_x = end_x < bx0 ? std::nextafter(end_x, bx0) : bx0;
        const double near_y = end_y < by0 ? std::nextafter(end_y, by0) : by0;
        if (segment_meets_box(f.axis_m.a_m, f.axis_m.b_m, near_x, near_y, bx0 + res, by0 + res)) row[c] = 255;
      }
    }
  }
}

}  // namespace

GridSpec grid_for_plan(const FloorPlan& plan, double resolution_m_per_px, double margin_m) {
  if (!(std::isfinite(resolution_m_per_px) && resolution_m_per_px > 0.0)) {
    throw InputError("raster over plan \"" + plan.name + "\": resolution " + std::to_string(resolution_m_per_px) +
                     " m/px is not a positive finite number");
  }
  if (!(std::isfinite(margin_m) && margin_m >= 0.0)) {
    throw InputError("raster over plan \"" + plan.name + "\": margin " + std::to_string(margin_m) +
                     " m is not a non-negative finite number");
  }
  const Eigen::Vector4d box = plan_bbox_m(plan);
  if (!box.allFinite()) throw InputError("raster over plan \"" + plan.name + "\": the plan has no finite extent");
  GridSpec g;
  g.resolution_m_per_px = resolution_m_per_px;
  g.origin_x_m = std::floor((box[0] - margin_m) / resolution_m_per_px) * resolution_m_per_px;
  g.origin_y_m = std::floor((box[1] - margin_m) / resolution_m_per_px) * resolution_m_per_px;
  const double width = std::max(1.0, std::ceil((box[2] + margin_m - g.origin_x_m) / resolution_m_per_px));
  const double height = std::max(1.0, std::ceil((box[3] + margin_m - g.origin_y_m) / resolution_m_per_px));
  // Checked in doubles, before the sizes are cast to int or anything is allocated.
  check_raster_budget(width, height, resolution_m_per_px, kPlanRasterBytesPerCell,
                      "plan \"" + plan.name + "\"");
  if (width > 2.0e9 || height > 2.0e9) throw InputError("raster over plan \"" + plan.name + "\": side too long");
  g.width_px = static_cast<int>(width);
  g.height_px = static_cast<int>(height);
  return g;
}

cv::Mat rasterize_occupancy(const FloorPlan& plan, const GridSpec& grid, const BlockingOptions& blocking) {
  cv::Mat occ(grid.height_px, grid.width_px, CV_8U, cv::Scalar(0));
  for (const Footprint& f : blocking_footprints(plan, blocking)) paint_footprint(occ, grid, f);
  return occ;
}

namespace {

/// Free cells of `occupancy` enclosed by `envelope`: not reachable from the grid border through
/// free envelope cells. The morphological closing that bridges envelope gaps also fills concave
/// outside corners; cells there are free in `occupancy` yet unreached. They touch the outside
/// through free cells, so everything within the closing radius (geodesically, through free
/// cells) of the reached outside is removed again.
cv::Mat enclosed_free_cells(const cv::Mat& envelope, const cv::Mat& occupancy, int radius_px) {
  cv::Mat padded;
  cv::copyMakeBorder(envelope, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::floodFill(padded, cv::Point(0, 0), cv::Scalar(128), nullptr, cv::Scalar(0), cv::Scalar(0), 4);
  cv::Mat outside;
  cv::compare(padded(cv::Rect(1, 1, envelope.cols, envelope.rows)), 128, outside, cv::CMP_EQ);
  cv::Mat free_cells;
  cv::compare(occupancy, 0, free_cells, cv::CMP_EQ);
  const cv::Mat cross = cv::getStructuringElement(cv::MORPH_CROSS, cv::Size(3, 3));
  for (int i = 0; i < radius_px + 1; ++i) {
    cv::Mat grown;
    cv::dilate(outside, grown, cross);
    cv::bitwise_and(grown, free_cells, grown);
    cv::bitwise_or(outside, grown, outside);
  }
  cv::Mat enclosed;
  cv::bitwise_not(outside, enclosed);
  cv::bitwise_and(enclosed, free_cells, enclosed);
  return enclosed;
}

cv::Mat valid_mask_with(const FloorPlan& plan, const GridSpec& grid, double gap_close_m,
                        const BlockingOptions& free_blocking) {
  BlockingOptions envelope_opts;
  envelope_opts.closed_doors_block = true;
  envelope_opts.open_doors_block = true;
  envelope_opts.glass_blocks = true;
  envelope_opts.obstacles_block = false;
  envelope_opts.cut_height_m = free_blocking.cut_height_m;
  cv::Mat envelope = rasterize_occupancy(plan, grid, envelope_opts);
  const int radius_px = static_cast<int>(std::ceil(0.5 * gap_close_m / grid.resolution_m_per_px));
  if (radius_px > 0) {
    const cv::Mat kernel =
        cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius_px + 1, 2 * radius_px + 1));
    cv::Mat padded;
    const int pad = radius_px + 1;
    cv::copyMakeBorder(envelope, padded, pad, pad, pad, pad, cv::BORDER_CONSTANT, cv::Scalar(0));
    cv::morphologyEx(padded, padded, cv::MORPH_CLOSE, kernel, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT,
                     cv::Scalar(0));
    envelope = padded(cv::Rect(pad, pad, envelope.cols, envelope.rows)).clone();
  }
  cv::Mat valid = enclosed_free_cells(envelope, rasterize_occupancy(plan, grid, free_blocking), radius_px);
  // Regions the source mapped as no space are not floor, however enclosed.
  const auto unmapped = [](const Room& r) { return is_unmapped_kind(r.kind); };
  if (std::any_of(plan.rooms.begin(), plan.rooms.end(), unmapped)) valid.setTo(0, rooms_mask(plan.rooms, grid, unmapped));
  return valid;
}

}  // namespace

cv::Mat valid_area_mask(const FloorPlan& plan, const GridSpec& grid, double gap_close_m) {
  return valid_mask_with(plan, grid, gap_close_m, BlockingOptions{});
}

cv::Mat distance_to_blocked_m(const cv::Mat& occupancy, const GridSpec& grid) {
  cv::Mat free_cells;
  cv::compare(occupancy, 0, free_cells, cv::CMP_EQ);
  cv::Mat dist;
  cv::distanceTransform(free_cells, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  dist *= grid.resolution_m_per_px;
  return dist;
}

PlanRasters make_plan_rasters(const FloorPlan& plan, const RasterOptions& options) {
  PlanRasters r;
  r.grid = grid_for_plan(plan, options.resolution_m_per_px, options.margin_m);
  r.occupancy = rasterize_occupancy(plan, r.grid, options.blocking);
  r.valid = valid_mask_with(plan, r.grid, 0.5, options.blocking);
  r.distance_m = distance_to_blocked_m(r.occupancy, r.grid);
  return r;
}

double free_floor_area_m2(const FloorPlan& plan, double resolution_m_per_px) {
  const GridSpec grid = grid_for_plan(plan, resolution_m_per_px, 1.0);
  BlockingOptions blocking;
  blocking.closed_doors_block = true;
  blocking.glass_blocks = true;
  blocking.obstacles_block = true;
  blocking.cut_height_m = 0.01;  // any obstacle standing on the floor takes floor area
  const cv::Mat valid = valid_mask_with(plan, grid, 0.5, blocking);
  return cv::countNonZero(valid) * resolution_m_per_px * resolution_m_per_px;
}

FreeRegionSummary free_region_summary(const FloorPlan& plan, const FreeRegionOptions& options) {
  // Resolution: the requested one, coarser for plans whose raster would exceed max_cells.
  const Eigen::Vector4d box = plan_bbox_m(plan);
  const double extent_area = std::max(1.0, (box[2] - box[0] + 2.0) * (box[3] - box[1] + 2.0));
  const double res = std::max(options.resolution_m_per_px, std::sqrt(extent_area / options.max_cells));
  const GridSpec grid = grid_for_plan(plan, res, 1.0);
  const cv::Mat valid = valid_area_mask(plan, grid);  // open doors free, closed doors and glass block
  FreeRegionSummary s;
  s.resolution_m_per_px = res;
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(valid, labels, stats, centroids, 8, CV_32S);
  cv::Mat distance;
  cv::distanceTransform(valid, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  std::vector<float> widest(static_cast<std::size_t>(n), 0.0f);
  for (int r = 0; r < labels.rows; ++r) {
    const int* l = labels.ptr<int>(r);
    const float* d = distance.ptr<float>(r);
    for (int c = 0; c < labels.cols; ++c) {
      if (l[c] > 0) widest[static_cast<std::size_t>(l[c])] = std::max(widest[static_cast<std::size_t>(l[c])], d[c]);
    }
  }
  const double cell = res * res;
  for (int k = 1; k < n; ++k) {
    const double area = stats.at<int>(k, cv::CC_STAT_AREA) * cell;
    // distanceTransform measures to the nearest zero cell centre: the free width through a cell
    // is about twice that less one cell.
    const double width = std::max(0.0, 2.0 * widest[static_cast<std::size_t>(k)] * res - res);
    ++s.regions;
    s.free_area_m2 += area;
    if (area > s.largest_region_m2) s.largest_region_m2 = area;
    s.widest_m = std::max(s.widest_m, width);
    if (area >= options.min_area_m2 && width >= options.min_width_m) {
      ++s.room_sized_regions;
      s.largest_room_sized_m2 = std::max(s.largest_room_sized_m2, area);
    }
  }
  return s;
}

void require_room_sized_free_region(const FloorPlan& plan, const std::string& source, const FreeRegionOptions& options) {
  const FreeRegionSummary s = free_region_summary(plan, options);
  if (s.room_sized_regions > 0) return;
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(2);
  os << source << ": no room-sized free region: ";
  if (s.regions == 0) {
    os << "the plan has no free floor enclosed by its walls";
  } else {
    os << s.free_area_m2 << " m^2 of free floor in " << s.regions << " region" << (s.regions == 1 ? "" : "s")
       << ", the largest " << s.largest_region_m2 << " m^2, the widest " << s.widest_m << " m across";
  }
  os << " (a room needs at least " << options.min_area_m2 << " m^2 and " << options.min_width_m
     << " m of width; measured at " << s.resolution_m_per_px << " m/px with doors open)";
  throw InputError(os.str());
}

namespace {

// One Zhang-Suen sub-iteration over the 0/1 image; returns whether a pixel was removed. Neighbours
// p2..p9 run clockwise from north; a pixel is removed when it has 2-6 neighbours, exactly one 0->1
// transition around it, and (sub-iteration 0) p2*p4*p6 = p4*p6*p8 = 0 or (1) p2*p4*p8 = p2*p6*p8 = 0.
// Marks are collected first and applied after the pass, as in the original algorithm.
bool zhang_suen_pass(cv::Mat& img, int sub_iteration, std::vector<std::size_t>& marked) {
  marked.clear();
  const int cols = img.cols;
  for (int i = 1; i + 1 < img.rows; ++i) {
    const std::uint8_t* up = img.ptr<std::uint8_t>(i - 1);
    const std::uint8_t* row = img.ptr<std::uint8_t>(i);
    const std::uint8_t* down = img.ptr<std::uint8_t>(i + 1);
    for (int j = 1; j + 1 < cols; ++j) {
      if (row[j] == 0) continue;
      const int p2 = up[j], p3 = up[j + 1], p4 = row[j + 1], p5 = down[j + 1];
      const int p6 = down[j], p7 = down[j - 1], p8 = row[j - 1], p9 = up[j - 1];
      const int a = (p2 == 0 && p3 == 1) + (p3 == 0 && p4 == 1) + (p4 == 0 && p5 == 1) + (p5 == 0 && p6 == 1) +
                    (p6 == 0 && p7 == 1) + (p7 == 0 && p8 == 1) + (p8 == 0 && p9 == 1) + (p9 == 0 && p2 == 1);
      const int b = p2 + p3 + p4 + p5 + p6 + p7 + p8 + p9;
      const int m1 = sub_iteration == 0 ? p2 * p4 * p6 : p2 * p4 * p8;
      const int m2 = sub_iteration == 0 ? p4 * p6 * p8 : p2 * p6 * p8;
      if (a == 1 && b >= 2 && b <= 6 && m1 == 0 && m2 == 0) {
        marked.push_back(static_cast<std::size_t>(i) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(j));
      }
    }
  }
  for (const std::size_t k : marked) img.data[k] = 0;
  return !marked.empty();
}

}  // namespace

cv::Mat thin_zhang_suen(const cv::Mat& binary) {
  if (binary.type() != CV_8UC1) throw std::invalid_argument("thin_zhang_suen: expects a CV_8UC1 image");
  cv::Mat img;
  cv::compare(binary, 0, img, cv::CMP_NE);  // 0/255
  img /= 255;                               // 0/1, continuous
  std::vector<std::size_t> marked;
  for (;;) {
    const bool removed0 = zhang_suen_pass(img, 0, marked);
    const bool removed1 = zhang_suen_pass(img, 1, marked);
    if (!removed0 && !removed1) break;
  }
  img *= 255;
  return img;
}

}  // namespace floorcast
