#include "floorcast/sim/clutter.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/core/random.hpp"
#include "floorcast/core/math.hpp"

namespace floorcast {
namespace {


struct Kind {
  const char* name;
  double w0, w1, d0, d1, h0, h1;  // width, depth, height ranges
};
// Desks, cabinets, shelves (typical office furniture sizes, metres).
constexpr Kind kKinds[] = {
    {"desk", 1.2, 1.8, 0.6, 0.8, 0.72, 0.76},
    {"cabinet", 0.8, 1.2, 0.4, 0.6, 1.0, 2.0},
    {"shelf", 0.8, 1.6, 0.3, 0.45, 1.8, 2.2},
};

std::vector<Vec2> box_polygon(const Vec2& c, double w, double d, double yaw) {
  const double cs = std::cos(yaw), sn = std::sin(yaw);
  const Vec2 ex = 0.5 * w * Vec2(cs, sn), ey = 0.5 * d * Vec2(-sn, cs);
  return {c - ex - ey, c + ex - ey, c + ex + ey, c - ex + ey};
}

double point_polygon_distance(const std::vector<Vec2>& poly, const Vec2& p) {
  if (point_in_convex_polygon(poly, p)) return 0.0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[(i + 1) % poly.size()];
    const Vec2 e = b - a;
    const double t = std::clamp((p - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (a + t * e - p).norm());
  }
  return best;
}

class Placer {
 public:
  Placer(const FloorPlan& plan, const ClutterParams& params) : params_(params) {
    grid_ = grid_for_plan(plan, params.resolution_m, 1.0);
    BlockingOptions walls;
    walls.closed_doors_block = true;
    walls.open_doors_block = false;
    walls.glass_blocks = true;
    walls.obstacles_block = false;
    walls.cut_height_m = 1.0;
    const cv::Mat occ_walls = rasterize_occupancy(plan, grid_, walls);
    dist_walls_ = distance_to_blocked_m(occ_walls, grid_);
    valid_ = valid_area_mask(plan, grid_, 0.5);
    BlockingOptions all = walls;
    all.obstacles_block = true;
    all.cut_height_m = 0.01;
    occupied_ = rasterize_occupancy(plan, grid_, all);
    for (const Door& d : plan.doors) doors_.push_back({d.center_m, 0.5 * d.width_m + params.door_clearance_m});
    for (const Vec2& p : params.keep_clear_m) doors_.push_back({p, params.keep_clear_radius_m});
  }

  /// True if the polygon's cells are all free interior and it keeps clear of doors and points.
  bool fits(const std::vector<Vec2>& poly) const {
    for (const auto& [c, r] : doors_) {
      if (point_polygon_distance(poly, c) < r) return false;
    }
    bool any = false;
    bool ok = true;
    for_cells(poly, [&](int row, int col) {
      any = true;
      if (row < 0 || !valid_.at<unsigned char>(row, col) || occupied_.at<unsigned char>(row, col)) ok = false;
    });
    return ok && any;
  }

  void occupy(const std::vector<Vec2>& poly) {
    for_cells(poly, [&](int row, int col) {
      if (row >= 0) occupied_.at<unsigned char>(row, col) = 255;
    });
  }

  /// Distance to walls at p (0 outside the grid).
  double wall_distance(const Vec2& p) const {
    int row, col;
    if (!grid_.world_to_cell(p, row, col)) return 0.0;
    return dist_walls_.at<float>(row, col);
  }

  /// Distance from a wall-face point to the ridge of the distance field along the normal n.
  double ridge_distance(const Vec2& face, const Vec2& n) const {
    const double step = params_.resolution_m;
    double best = 0.0, best_at = 0.0;
    for (double s = step; s < 20.0; s += step) {
      const double d = wall_distance(face + s * n);
      if (d > best + 1e-9) {
        best = d;
        best_at = s;
      } else if (d + 2.0 * step < best) {
        break;  // clearly past the ridge
      }
    }
    return best_at;
  }

  const cv::Mat& valid() const { return valid_; }
  const cv::Mat& dist_walls() const { return dist_walls_; }
  const GridSpec& grid() const { return grid_; }

 private:
  template <typename F>
  void for_cells(const std::vector<Vec2>& poly, F f) const {
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (const Vec2& p : poly) {
      x0 = std::min(x0, p.x());
      y0 = std::min(y0, p.y());
      x1 = std::max(x1, p.x());
      y1 = std::max(y1, p.y());
    }
    const double res = grid_.resolution_m_per_px;
    const int c0 = static_cast<int>(std::floor((x0 - grid_.origin_x_m) / res)) - 1;
    const int c1 = static_cast<int>(std::floor((x1 - grid_.origin_x_m) / res)) + 1;
    const int r0 = static_cast<int>(std::floor((y0 - grid_.origin_y_m) / res)) - 1;
    const int r1 = static_cast<int>(std::floor((y1 - grid_.origin_y_m) / res)) + 1;
    for (int r = r0; r <= r1; ++r) {
      for (int c = c0; c <= c1; ++c) {
        if (!point_in_convex_polygon(poly, grid_.cell_center_m(r, c))) continue;
        if (!grid_.contains(r, c)) {
          // Outside the raster cannot be interior; report as a cell that fails.
          f(-1, -1);
          continue;
        }
        f(r, c);
      }
    }
  }

  const ClutterParams& params_;
  GridSpec grid_;
  cv::Mat dist_walls_, valid_, occupied_;
  std::vector<std::pair<Vec2, double>> doors_;
};

void check(bool ok, const std::string& what) {
  if (!ok) throw InputError("clutter parameters: " + what);
}

}  // namespace

std::vector<Obstacle> generate_clutter(const FloorPlan& plan, const ClutterParams& params) {
  check(std::isfinite(params.density) && params.density >= 0.0 && params.density <= 1.0, "density must be in [0, 1]");
  check(params.slot_length_m >= 0.5 && params.slot_length_m <= 100.0, "slot_length_m must be in [0.5, 100]");
  check(params.resolution_m >= 0.01 && params.resolution_m <= 0.5, "resolution_m must be in [0.01, 0.5]");
  check(params.wall_gap_m >= 0.0 && params.door_clearance_m >= 0.0 && params.centerline_clearance_m >= 0.0 &&
            params.keep_clear_radius_m >= 0.0 && params.pillar_spacing_m >= 0.0,
        "gaps and clearances must be non-negative");
  check(params.pillar_area_m2 > 0.0 && params.pillar_min_wall_distance_m > 0.0 && params.pillar_height_m > 0.0,
        "pillar area, wall distance and height must be positive");
  std::vector<Obstacle> out;
  if (params.density <= 0.0) return out;

  Placer placer(plan, params);
  auto fits = [&](const std::vector<Vec2>& poly) {
    for (const Vec2& p : poly) {
      int r, c;
      if (!placer.grid().world_to_cell(p, r, c)) return false;
    }
    return placer.fits(poly);
  };

  // Boxes against solid wall faces.
  BlockingOptions faces;
  faces.closed_doors_block = true;
  faces.open_doors_block = true;  // no slot spans a doorway
  faces.glass_blocks = true;
  faces.cut_height_m = 1.0;
  const std::vector<LabeledSegment> outline = blocking_outline(plan, faces);
  int box_id = 0;
  for (std::size_t si = 0; si < outline.size(); ++si) {
    const LabeledSegment& seg = outline[si];
    if (seg.label != SurfaceLabel::kWall) continue;
    const Vec2 a = seg.segment_m.a_m, b = seg.segment_m.b_m;
    const double len = (b - a).norm();
    const Vec2 dir = (b - a) / len;
    const Vec2 n(-dir.y(), dir.x());  // free space on the left
    const int slots = static_cast<int>(std::floor(len / params.slot_length_m));
    for (int j = 0; j < slots; ++j) {
      const CounterRng rng(params.seed, kRngClutter, si, static_cast<std::uint64_t>(j));
      if (rng.uniform(0) >= params.density) continue;
      const double pick = rng.uniform(1);
      const Kind& kind = pick < 0.45 ? kKinds[0] : (pick < 0.75 ? kKinds[1] : kKinds[2]);
      const double w = kind.w0 + rng.uniform(2) * (kind.w1 - kind.w0);
      const double d = kind.d0 + rng.uniform(3) * (kind.d1 - kind.d0);
      const double h = kind.h0 + rng.uniform(4) * (kind.h1 - kind.h0);
      const double s0 = j * params.slot_length_m, s1 = s0 + params.slot_length_m;
      if (s1 - s0 < w) continue;
      const double t = s0 + 0.5 * w + rng.uniform(5) * (s1 - s0 - w);
      const Vec2 face = a + t * dir;
      if (placer.ridge_distance(face, n) < params.wall_gap_m + d + params.centerline_clearance_m) continue;
      const Vec2 centre = face + (params.wall_gap_m + 0.5 * d) * n;
      const double yaw = std::atan2(dir.y(), dir.x());
      const std::vector<Vec2> poly = box_polygon(centre, w, d, yaw);
      if (!fits(poly)) continue;
      placer.occupy(poly);
      Obstacle o;
      o.id = "clutter_box_" + std::to_string(box_id++);
      o.kind = ObstacleKind::kBox;
      o.center_m = centre;
      o.size_m = Vec2(w, d);
      o.yaw_rad = yaw;
      o.height_m = h;
      out.push_back(o);
    }
  }

  // Pillars in open areas.
  std::vector<std::pair<int, int>> open_cells;
  const cv::Mat& valid = placer.valid();
  const cv::Mat& dist = placer.dist_walls();
  for (int r = 0; r < valid.rows; ++r)
    for (int c = 0; c < valid.cols; ++c)
      if (valid.at<unsigned char>(r, c) && dist.at<float>(r, c) >= params.pillar_min_wall_distance_m) {
        open_cells.emplace_back(r, c);
      }
  const double res = placer.grid().resolution_m_per_px;
  const double open_area = static_cast<double>(open_cells.size()) * res * res;
  const int wanted = static_cast<int>(std::floor(params.density * open_area / params.pillar_area_m2 + 0.5));
  std::vector<Vec2> pillars;
  for (int attempt = 0; attempt < 20 * wanted && static_cast<int>(pillars.size()) < wanted; ++attempt) {
    const CounterRng rng(params.seed, kRngClutter, 0xF111A5ULL, static_cast<std::uint64_t>(attempt));
    const std::size_t k = std::min(open_cells.size() - 1,
                                   static_cast<std::size_t>(rng.uniform(0) * static_cast<double>(open_cells.size())));
    const Vec2 centre = placer.grid().cell_center_m(open_cells[k].first, open_cells[k].second);
    const double diameter = 0.3 + 0.3 * rng.uniform(1);
    bool spaced = true;
    for (const Vec2& q : pillars) spaced = spaced && (q - centre).norm() >= params.pillar_spacing_m;
    if (!spaced) continue;
    std::vector<Vec2> poly;
    for (int i = 0; i < 16; ++i) {
      const double ang = 2.0 * kPi * i / 16.0;
      poly.push_back(centre + 0.5 * diameter * Vec2(std::cos(ang), std::sin(ang)));
    }
    if (!fits(poly)) continue;
    placer.occupy(poly);
    pillars.push_back(centre);
    Obstacle o;
    o.id = "clutter_pillar_" + std::to_string(pillars.size() - 1);
    o.kind = ObstacleKind::kPillar;
    o.center_m = centre;
    o.size_m = Vec2(diameter, diameter);
    o.yaw_rad = 0.0;
    o.height_m = params.pillar_height_m;
    out.push_back(o);
  }
  return out;
}

FloorPlan with_clutter(const FloorPlan& plan, const ClutterParams& params) {
  FloorPlan p = plan;
  for (Obstacle& o : generate_clutter(plan, params)) p.obstacles.push_back(std::move(o));
  return p;
}

}  // namespace floorcast
