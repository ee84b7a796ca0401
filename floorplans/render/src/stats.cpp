// Structure measures of a floor plan (stats.hpp).
#include "floorcast/floorplans/stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <opencv2/imgproc.hpp>

#include "floorcast/core/box_index.hpp"
#include "floorcast/core/fields.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/floorplans/rooms.hpp"

namespace floorcast {
namespace {

/// Smallest distance between two closed polygons' outlines (0 if they cross or touch).
double outline_distance_m(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Segment2 sa{a[i], a[(i + 1) % a.size()]};
    for (std::size_t j = 0; j < b.size(); ++j) {
      const Segment2 sb{b[j], b[(j + 1) % b.size()]};
      best = std::min({best, point_segment_distance(sa.a_m, sb), point_segment_distance(sa.b_m, sb),
                       point_segment_distance(sb.a_m, sa), point_segment_distance(sb.b_m, sa)});
      if (best <= 0.0) return 0.0;
    }
  }
  return best;
}

struct Box {
  double xmin, ymin, xmax, ymax;
};
Box bounds(const std::vector<Vec2>& poly) {
  Box b{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const Vec2& p : poly) {
    b.xmin = std::min(b.xmin, p.x());
    b.ymin = std::min(b.ymin, p.y());
    b.xmax = std::max(b.xmax, p.x());
    b.ymax = std::max(b.ymax, p.y());
  }
  return b;
}

/// Widths along the ridge of a mask (CV_8U, 255 inside, zero border): twice the distance-transform
/// value at every pixel that is a local maximum of the transform (the medial axis), in metres.
std::vector<double> ridge_widths_m(const cv::Mat& mask, double res) {
  cv::Mat dt;
  cv::distanceTransform(mask, dt, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  std::vector<double> ridge;
  for (int r = 1; r + 1 < dt.rows; ++r) {
    for (int c = 1; c + 1 < dt.cols; ++c) {
      const float v = dt.at<float>(r, c);
      if (v <= 0.0f) continue;
      bool is_max = true;
      for (int dr = -1; dr <= 1 && is_max; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          if ((dr || dc) && dt.at<float>(r + dr, c + dc) > v) {
            is_max = false;
            break;
          }
        }
      }
      if (is_max) ridge.push_back(2.0 * static_cast<double>(v) * res);
    }
  }
  return ridge;
}

}  // namespace

Distribution describe(std::vector<double> values) {
  Distribution d;
  if (values.empty()) return d;
  std::sort(values.begin(), values.end());
  d.count = static_cast<int>(values.size());
  d.min = values.front();
  d.max = values.back();
  d.q1 = quantile(values, 0.25);
  d.median = quantile(values, 0.5);
  d.q3 = quantile(values, 0.75);
  double sum = 0.0;
  for (double v : values) sum += v;
  d.mean = sum / static_cast<double>(values.size());
  double var = 0.0;
  for (double v : values) var += (v - d.mean) * (v - d.mean);
  var /= static_cast<double>(values.size());
  d.cv = d.mean > 0.0 ? std::sqrt(var) / d.mean : 0.0;
  return d;
}

std::pair<double, double> min_area_rect_sides_m(const std::vector<Vec2>& points) {
  if (points.size() < 3) return {0.0, 0.0};
  Vec2 c = Vec2::Zero();
  for (const Vec2& p : points) c += p;
  c /= static_cast<double>(points.size());
  std::vector<cv::Point2f> pts;
  pts.reserve(points.size());
  for (const Vec2& p : points) pts.emplace_back(static_cast<float>(p.x() - c.x()), static_cast<float>(p.y() - c.y()));
  const cv::RotatedRect r = cv::minAreaRect(pts);
  const double a = r.size.width, b = r.size.height;
  return {std::min(a, b), std::max(a, b)};
}

PlanStats plan_stats(const FloorPlan& plan, const PlanStatsParams& params) {
  PlanStats s;
  s.name = plan.name;
  s.direction_bin_deg = params.direction_bin_deg;
  s.free_area_m2 = free_floor_area_m2(plan);

  // Walls: length, directions, thickness classes.
  const double bin = params.direction_bin_deg;
  const int nbins = std::max(1, static_cast<int>(std::lround(180.0 / bin)));
  s.direction_share.assign(static_cast<std::size_t>(nbins), 0.0);
  std::map<long, ThicknessClass> classes;
  for (const Wall& w : plan.walls) {
    const double len = w.length_m();
    ++s.walls;
    if (w.material == WallMaterial::kGlass) ++s.glass_walls;
    s.wall_length_m += len;
    double deg = std::atan2(w.b_m.y() - w.a_m.y(), w.b_m.x() - w.a_m.x()) * 180.0 / kPi;
    deg = std::fmod(deg + 360.0, 180.0);
    const int k = static_cast<int>(std::floor(deg / bin + 0.5)) % nbins;
    s.direction_share[static_cast<std::size_t>(k)] += len;
    const long cm = std::lround(w.thickness_m * 100.0);
    ThicknessClass& tc = classes[cm];
    tc.thickness_m = static_cast<double>(cm) / 100.0;
    ++tc.walls;
    tc.length_share += len;
  }
  if (s.wall_length_m > 0.0) {
    for (double& v : s.direction_share) {
      v /= s.wall_length_m;
      if (v >= params.direction_min_share) ++s.directions_used;
    }
    for (auto& [cm, tc] : classes) {
      (void)cm;
      tc.length_share /= s.wall_length_m;
      s.thickness_classes.push_back(tc);
    }
  }
  s.doors = static_cast<int>(plan.doors.size());
  s.doors_per_10m_wall = s.wall_length_m > 0.0 ? 10.0 * s.doors / s.wall_length_m : 0.0;
  for (const Obstacle& o : plan.obstacles) s.pillars += o.kind == ObstacleKind::kPillar ? 1 : 0;

  // Rooms.
  // Regions the source did not map ("unmapped", not floor) are no rooms.
  s.rooms = static_cast<int>(std::count_if(plan.rooms.begin(), plan.rooms.end(),
                                           [](const Room& r) { return !is_unmapped_kind(r.kind); }));
  std::vector<int> plain;  // non-transitional rooms large enough to count
  std::vector<double> areas, widths;
  std::vector<int> transitional;
  for (std::size_t i = 0; i < plan.rooms.size(); ++i) {
    const Room& r = plan.rooms[i];
    if (r.polygon_m.size() < 3 || is_unmapped_kind(r.kind)) continue;
    if (is_transitional_kind(r.kind)) {
      ++s.transitional_rooms;
      transitional.push_back(static_cast<int>(i));
      continue;
    }
    const double a = room_area_m2(r);
    if (a < params.min_room_area_m2) continue;
    plain.push_back(static_cast<int>(i));
    areas.push_back(a);
    widths.push_back(min_area_rect_sides_m(r.polygon_m).first);
  }
  s.room_area_m2 = describe(areas);
  s.room_width_m = describe(widths);

  // Repetition: a room whose width is within tolerance of a neighbour's.
  if (!plain.empty()) {
    std::vector<Box> boxes;
    for (int i : plain) boxes.push_back(bounds(plan.rooms[static_cast<std::size_t>(i)].polygon_m));
    int repeated = 0;
    const double gap = params.neighbour_gap_m;
    // Neighbours from an R-tree over the room boxes (every room against every room was quadratic).
    std::vector<IndexBox> room_boxes;
    room_boxes.reserve(boxes.size());
    for (const Box& b : boxes) room_boxes.push_back({b.xmin, b.ymin, b.xmax, b.ymax});
    const BoxIndex room_tree(room_boxes);
    std::vector<std::uint32_t> near;
    for (std::size_t i = 0; i < plain.size(); ++i) {
      bool rep = false;
      room_tree.query(room_boxes[i].grown(gap), near);
      for (std::size_t n = 0; n < near.size() && !rep; ++n) {
        const std::size_t j = near[n];
        if (i == j) continue;
        const Box& a = boxes[i];
        const Box& b = boxes[j];
        if (a.xmin > b.xmax + gap || b.xmin > a.xmax + gap || a.ymin > b.ymax + gap || b.ymin > a.ymax + gap) continue;
        const double wi = widths[i], wj = widths[j];
        if (std::abs(wi - wj) > params.repeat_tolerance * std::max(wi, wj)) continue;
        if (outline_distance_m(plan.rooms[static_cast<std::size_t>(plain[i])].polygon_m,
                               plan.rooms[static_cast<std::size_t>(plain[j])].polygon_m) > gap) {
          continue;
        }
        rep = true;
      }
      repeated += rep ? 1 : 0;
    }
    s.repeated_width_share = static_cast<double>(repeated) / static_cast<double>(plain.size());
  }

  // Corridor widths: per transitional room, the ridge of its distance transform (nested rooms
  // cut out: a cell belongs to the smallest room containing it).
  if (!transitional.empty()) {
    const double res = params.resolution_m_per_px;
    Box all = bounds(plan.rooms[static_cast<std::size_t>(transitional.front())].polygon_m);
    for (int i : transitional) {
      const Box b = bounds(plan.rooms[static_cast<std::size_t>(i)].polygon_m);
      all = {std::min(all.xmin, b.xmin), std::min(all.ymin, b.ymin), std::max(all.xmax, b.xmax),
             std::max(all.ymax, b.ymax)};
    }
    GridSpec grid;
    grid.resolution_m_per_px = res;
    grid.origin_x_m = all.xmin - 2.0 * res;
    grid.origin_y_m = all.ymin - 2.0 * res;
    grid.width_px = static_cast<int>(std::ceil((all.xmax - all.xmin) / res)) + 4;
    grid.height_px = static_cast<int>(std::ceil((all.ymax - all.ymin) / res)) + 4;
    const cv::Mat index = room_index_raster(plan.rooms, grid);
    // One mask for all transitional space: alcoves and corridor pieces labelled as separate rooms
    // measure as the circulation they form together.
    std::vector<char> is_transitional(plan.rooms.size(), 0);
    for (int i : transitional) is_transitional[static_cast<std::size_t>(i)] = 1;
    cv::Mat mask = cv::Mat::zeros(index.rows + 2, index.cols + 2, CV_8U);
    int inside = 0;
    for (int r = 0; r < index.rows; ++r) {
      for (int c = 0; c < index.cols; ++c) {
        const int k = index.at<int>(r, c);
        if (k >= 0 && is_transitional[static_cast<std::size_t>(k)]) {
          mask.at<unsigned char>(r + 1, c + 1) = 255;
          ++inside;
        }
      }
    }
    std::vector<double> corridor;
    if (inside >= 4) {
      for (double w : ridge_widths_m(mask, res)) {
        if (w >= params.min_corridor_width_m) corridor.push_back(w);
      }
    }
    s.corridor_width_m = describe(corridor);
  }
  return s;
}

namespace {

double r3(double x) { return std::round(x * 1000.0) / 1000.0; }

Distribution rounded(Distribution d) {
  for (double* v : {&d.min, &d.q1, &d.median, &d.q3, &d.max, &d.mean, &d.cv}) *v = r3(*v);
  return d;
}

const FieldList<Distribution>& distribution_fields() {
  constexpr double kAny = 1e300;
  static const FieldList<Distribution> f = FieldList<Distribution>("distribution")
                                               .integer("count", &Distribution::count, 0, 1 << 30, "samples")
                                               .number("min", &Distribution::min, -kAny, kAny, "smallest")
                                               .number("q1", &Distribution::q1, -kAny, kAny, "first quartile")
                                               .number("median", &Distribution::median, -kAny, kAny, "median")
                                               .number("q3", &Distribution::q3, -kAny, kAny, "third quartile")
                                               .number("max", &Distribution::max, -kAny, kAny, "largest")
                                               .number("mean", &Distribution::mean, -kAny, kAny, "mean")
                                               .number("cv", &Distribution::cv, -kAny, kAny, "standard deviation / mean");
  return f;
}

const FieldList<PlanStats>& plan_stats_fields() {
  using S = PlanStats;
  using T = ThicknessClass;
  constexpr double kAny = 1e300;
  constexpr int kMany = 1 << 30;
  static const FieldList<T> thickness = FieldList<T>("thickness class")
                                            .number("thickness_m", &T::thickness_m, 0.0, kAny, "wall thickness (1 cm), m")
                                            .integer("walls", &T::walls, 0, kMany, "walls of that thickness")
                                            .number("length_share", &T::length_share, 0.0, 1.0, "share of the wall length");
  static const FieldList<S> f =
      FieldList<S>("plan stats")
          .text("name", &S::name, "the plan's name")
          .number("free_area_m2", &S::free_area_m2, 0.0, kAny, "free floor area (doors open), m^2")
          .integer("walls", &S::walls, 0, kMany, "walls")
          .integer("glass_walls", &S::glass_walls, 0, kMany, "glass walls among them")
          .number("wall_length_m", &S::wall_length_m, 0.0, kAny, "sum of wall centreline lengths, m")
          .number("direction_bin_deg", &S::direction_bin_deg, 0.0, 180.0, "width of the direction bins, deg")
          .series("direction_share", &S::direction_share, "share of the wall length per direction bin")
          .integer("directions_used", &S::directions_used, 0, kMany, "bins holding at least direction_min_share")
          .list("thickness_classes", &S::thickness_classes, thickness)
          .integer("doors", &S::doors, 0, kMany, "doors")
          .number("doors_per_10m_wall", &S::doors_per_10m_wall, 0.0, kAny, "doors per 10 m of wall")
          .integer("pillars", &S::pillars, 0, kMany, "obstacles of kind pillar")
          .integer("rooms", &S::rooms, 0, kMany, "labelled rooms")
          .integer("transitional_rooms", &S::transitional_rooms, 0, kMany, "transitional rooms among them")
          .section("room_area_m2", &S::room_area_m2, distribution_fields())
          .section("room_width_m", &S::room_width_m, distribution_fields())
          .number("repeated_width_share", &S::repeated_width_share, 0.0, 1.0, "rooms whose width repeats a neighbour's")
          .section("corridor_width_m", &S::corridor_width_m, distribution_fields());
  return f;
}

}  // namespace

nlohmann::ordered_json to_json(const PlanStats& stats) {
  PlanStats s = stats;  // measures rounded to 0.001 (counts and the bin width as they are)
  s.free_area_m2 = r3(s.free_area_m2);
  s.wall_length_m = r3(s.wall_length_m);
  for (double& v : s.direction_share) v = r3(v);
  for (ThicknessClass& t : s.thickness_classes) t.length_share = r3(t.length_share);
  s.doors_per_10m_wall = r3(s.doors_per_10m_wall);
  s.room_area_m2 = rounded(s.room_area_m2);
  s.room_width_m = rounded(s.room_width_m);
  s.repeated_width_share = r3(s.repeated_width_share);
  s.corridor_width_m = rounded(s.corridor_width_m);
  return plan_stats_fields().write(s);
}

}  // namespace floorcast
