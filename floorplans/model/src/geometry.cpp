#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/core/box_index.hpp"
#include "floorcast/core/math.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace floorcast {
namespace {


double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

struct Interval {
  double t0, t1;
  SurfaceLabel label;
  bool blocking;
};

std::vector<Vec2> oriented_rectangle(const Vec2& a, const Vec2& b, double half_width) {
  const Vec2 d = (b - a).normalized();
  const Vec2 n(-d.y(), d.x());
  // Counter-clockwise: a-right, b-right, b-left, a-left.
  return {a - half_width * n, b - half_width * n, b + half_width * n, a + half_width * n};
}

}  // namespace

bool point_in_convex_polygon(const std::vector<Vec2>& polygon_m, const Vec2& p) {
  const std::size_t n = polygon_m.size();
  if (n < 3) return false;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = polygon_m[i];
    const Vec2& b = polygon_m[(i + 1) % n];
    const Vec2 e = b - a;
    const double len = e.norm();
    if (len == 0.0) continue;
    if (cross(e, p - a) / len < -1e-9) return false;
  }
  return true;
}

double point_segment_distance(const Vec2& p, const Segment2& segment) {
  const Vec2 d = segment.b_m - segment.a_m;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - segment.a_m).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (p - (segment.a_m + t * d)).norm();
}

double ray_segment_distance(const Vec2& origin, const Vec2& direction, const Segment2& segment) {
  const Vec2 e = segment.b_m - segment.a_m;
  const double denom = cross(direction, e);
  if (std::abs(denom) < 1e-15) return -1.0;
  const Vec2 w = segment.a_m - origin;
  const double t = cross(w, e) / denom;
  const double u = cross(w, direction) / denom;
  if (t < 0.0 || u < 0.0 || u > 1.0) return -1.0;
  return t;
}

std::vector<Segment2> outline_segments(const std::vector<LabeledSegment>& outline) {
  std::vector<Segment2> out;
  out.reserve(outline.size());
  for (const LabeledSegment& l : outline) out.push_back(l.segment_m);
  return out;
}

WallJoins::WallJoins(const FloorPlan& plan) : plan_(&plan) {
  std::vector<IndexBox> centre_lines;
  centre_lines.reserve(plan.walls.size());
  double max_thickness = 0.0;
  for (const Wall& w : plan.walls) {
    centre_lines.push_back({std::min(w.a_m.x(), w.b_m.x()), std::min(w.a_m.y(), w.b_m.y()), std::max(w.a_m.x(), w.b_m.x()),
                            std::max(w.a_m.y(), w.b_m.y())});
    max_thickness = std::max(max_thickness, w.thickness_m);
  }
  tree_ = BoxIndex(centre_lines);
  reach_m_ = 0.5 * max_thickness + 0.01 + 1e-9;
  doors_.resize(plan.walls.size());
  windows_.resize(plan.walls.size());
  const WallIdIndex ids(plan);
  for (std::size_t i = 0; i < plan.doors.size(); ++i) {
    const int wi = ids.find(plan.doors[i].wall_id);
    if (wi >= 0) doors_[static_cast<std::size_t>(wi)].push_back(i);
  }
  for (std::size_t i = 0; i < plan.windows.size(); ++i) {
    const int wi = ids.find(plan.windows[i].wall_id);
    if (wi >= 0) windows_[static_cast<std::size_t>(wi)].push_back(i);
  }
}

bool WallJoins::end_joined(std::size_t self, const Vec2& p) const {
  const FloorPlan& plan = *plan_;
  thread_local std::vector<std::uint32_t> near;
  tree_.query({p.x() - reach_m_, p.y() - reach_m_, p.x() + reach_m_, p.y() + reach_m_}, near);
  for (const std::uint32_t j : near) {
    if (j == self) continue;
    const Wall& w = plan.walls[j];
    const Vec2 d = w.b_m - w.a_m;
    const double len2 = d.squaredNorm();
    if (len2 <= 0.0) continue;
    const double t = std::clamp((p - w.a_m).dot(d) / len2, 0.0, 1.0);
    const double tol = 0.5 * std::max(w.thickness_m, plan.walls[self].thickness_m) + 0.01;
    if ((w.a_m + t * d - p).norm() <= tol) return true;
  }
  return false;
}

std::vector<Footprint> blocking_footprints(const FloorPlan& plan, const BlockingOptions& options) {
  std::vector<Footprint> out;
  const double h = options.cut_height_m;

  const WallJoins joins(plan);  // each wall used to scan every wall and opening: quadratic
  for (std::size_t wi = 0; wi < plan.walls.size(); ++wi) {
    const Wall& wall = plan.walls[wi];
    const double len = wall.length_m();
    const Vec2 dir = wall.direction();

    // What a horizontal cut at h meets where there is no opening.
    SurfaceLabel body = SurfaceLabel::kWall;
    bool body_blocks = true;
    if (wall.material == WallMaterial::kGlass) {
      const double head = wall.glass_head_m.value_or(std::numeric_limits<double>::infinity());
      if (h >= wall.glass_sill_m && h < head) {
        body = SurfaceLabel::kGlass;
        body_blocks = options.glass_blocks;
      }
    }

    // Openings on this wall at the cut height.
    std::vector<Interval> openings;
    for (const std::size_t di : joins.doors_on(wi)) {
      const Door& d = plan.doors[di];
      const OpeningSpan s = opening_span(plan, static_cast<int>(wi), d.center_m, d.width_m);
      const bool blocks = d.closed ? options.closed_doors_block : options.open_doors_block;
      openings.push_back({s.t0_m, s.t1_m, SurfaceLabel::kDoorClosed, blocks});
    }
    for (const std::size_t wni : joins.windows_on(wi)) {
      const Window& win = plan.windows[wni];
      const OpeningSpan s = opening_span(plan, static_cast<int>(wi), win.center_m, win.width_m);
      if (h >= win.sill_m && h < win.head_m) {
        openings.push_back({s.t0_m, s.t1_m, SurfaceLabel::kGlass, options.glass_blocks});
      }
    }
    std::sort(openings.begin(), openings.end(),
              [](const Interval& x, const Interval& y) { return x.t0 < y.t0; });

    // Square caps at joined ends close corners.
    const double cap = 0.5 * wall.thickness_m;
    const double t_begin = joins.end_joined(wi, wall.a_m) ? -cap : 0.0;
    const double t_end = joins.end_joined(wi, wall.b_m) ? len + cap : len;

    std::vector<Interval> pieces;
    double cursor = t_begin;
    for (const Interval& o : openings) {
      const double t0 = std::max(o.t0, 0.0), t1 = std::min(o.t1, len);
      if (t0 > cursor) pieces.push_back({cursor, t0, body, body_blocks});
      pieces.push_back({t0, t1, o.label, o.blocking});
      cursor = std::max(cursor, t1);
    }
    if (t_end > cursor) pieces.push_back({cursor, t_end, body, body_blocks});

    for (const Interval& p : pieces) {
      if (!p.blocking || p.t1 - p.t0 <= 1e-9) continue;
      Footprint f;
      const Vec2 a = wall.a_m + p.t0 * dir;
      const Vec2 b = wall.a_m + p.t1 * dir;
      f.polygon_m = oriented_rectangle(a, b, 0.5 * wall.thickness_m);
      f.label = p.label;
      f.source_index = static_cast<int>(wi);
      f.axis_m = {a, b};
      f.has_axis = true;
      out.push_back(std::move(f));
    }
  }

  if (options.obstacles_block) {
    for (std::size_t oi = 0; oi < plan.obstacles.size(); ++oi) {
      const Obstacle& o = plan.obstacles[oi];
      if (o.height_m <= h) continue;
      Footprint f;
      f.label = SurfaceLabel::kObstacle;
      f.source_index = static_cast<int>(oi);
      if (o.kind == ObstacleKind::kPillar) {
        const double r = 0.5 * o.size_m.x();
        for (int k = 0; k < 16; ++k) {
          const double a = o.yaw_rad + 2.0 * kPi * k / 16.0;
          f.polygon_m.push_back(o.center_m + r * Vec2(std::cos(a), std::sin(a)));
        }
      } else {
        const double c = std::cos(o.yaw_rad), s = std::sin(o.yaw_rad);
        const Vec2 ex = 0.5 * o.size_m.x() * Vec2(c, s);
        const Vec2 ey = 0.5 * o.size_m.y() * Vec2(-s, c);
        f.polygon_m = {o.center_m - ex - ey, o.center_m + ex - ey, o.center_m + ex + ey, o.center_m - ex + ey};
        // The box's medial segment (its long midline inset by half its short side): rasters draw
        // it like a wall's axis, so a box thinner than a cell (a 5 cm cubicle partition) is
        // painted where no cell centre falls inside it. Every cell it meets has its centre in the
        // box once the box is thicker than a cell's diagonal, so such boxes rasterise as before.
        const bool long_x = o.size_m.x() >= o.size_m.y();
        const double half_long = 0.5 * std::max(o.size_m.x(), o.size_m.y());
        const double half_short = 0.5 * std::min(o.size_m.x(), o.size_m.y());
        const Vec2 u = long_x ? Vec2(c, s) : Vec2(-s, c);
        const double reach = std::max(half_long - half_short, 0.0);
        f.axis_m = {o.center_m - reach * u, o.center_m + reach * u};
        f.has_axis = true;
      }
      out.push_back(std::move(f));
    }
  }
  return out;
}

std::vector<LabeledSegment> footprint_outline(const std::vector<Footprint>& footprints) {
  struct Box { double x0, y0, x1, y1; };
  std::vector<Box> boxes;
  boxes.reserve(footprints.size());
  for (const Footprint& f : footprints) {
    Box b{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    for (const Vec2& p : f.polygon_m) {
      b.x0 = std::min(b.x0, p.x());
      b.y0 = std::min(b.y0, p.y());
      b.x1 = std::max(b.x1, p.x());
      b.y1 = std::max(b.y1, p.y());
    }
    boxes.push_back(b);
  }
  if (footprints.empty()) return {};

  // Neighbours from an R-tree over the footprint boxes (a bucket grid sized by the largest
  // footprint put every piece of a plan with one long wall into a few buckets: quadratic).
  std::vector<IndexBox> index_boxes;
  index_boxes.reserve(boxes.size());
  for (const Box& b : boxes) index_boxes.push_back({b.x0, b.y0, b.x1, b.y1});
  const BoxIndex tree(index_boxes);
  auto neighbours = [&](const Box& b) { return tree.query({b.x0 - 1e-6, b.y0 - 1e-6, b.x1 + 1e-6, b.y1 + 1e-6}); };

  constexpr double kOffset = 1e-6;  // probe distance off the edge, metres
  std::vector<LabeledSegment> pieces;
  for (std::size_t fi = 0; fi < footprints.size(); ++fi) {
    const Footprint& f = footprints[fi];
    const std::vector<std::uint32_t> near = neighbours(boxes[fi]);
    const std::size_t n = f.polygon_m.size();
    for (std::size_t k = 0; k < n; ++k) {
      const Vec2 p = f.polygon_m[k];
      const Vec2 q = f.polygon_m[(k + 1) % n];
      const Vec2 e = q - p;
      const double len = e.norm();
      if (len < 1e-12) continue;
      const Vec2 u = e / len;
      const Vec2 outward(u.y(), -u.x());  // CCW polygon: interior on the left of p->q

      std::vector<double> cuts{0.0, 1.0};
      for (const std::uint32_t g : near) {
        if (static_cast<std::size_t>(g) == fi) continue;
        const auto& poly = footprints[static_cast<std::size_t>(g)].polygon_m;
        for (std::size_t m = 0; m < poly.size(); ++m) {
          const Vec2 r = poly[m];
          const Vec2 s = poly[(m + 1) % poly.size()];
          const Vec2 fdir = s - r;
          const double denom = cross(e, fdir);
          const double scale = len * fdir.norm();
          if (std::abs(denom) > 1e-12 * scale) {
            const double t = cross(r - p, fdir) / denom;
            const double v = cross(r - p, e) / denom;
            if (t > 0.0 && t < 1.0 && v >= -1e-12 && v <= 1.0 + 1e-12) cuts.push_back(t);
          } else if (std::abs(cross(e, r - p)) <= 1e-9 * len) {
            // Collinear: the other edge's endpoints split this one.
            for (const Vec2& x : {r, s}) {
              const double t = (x - p).dot(e) / (len * len);
              if (t > 0.0 && t < 1.0) cuts.push_back(t);
            }
          }
        }
      }
      std::sort(cuts.begin(), cuts.end());
      for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
        const double t0 = cuts[c], t1 = cuts[c + 1];
        if ((t1 - t0) * len < 1e-9) continue;
        const Vec2 mid = p + 0.5 * (t0 + t1) * e;
        const Vec2 probe = mid + kOffset * outward;
        bool covered = false;
        for (const std::uint32_t g : near) {
          if (static_cast<std::size_t>(g) == fi) continue;
          if (point_in_convex_polygon(footprints[static_cast<std::size_t>(g)].polygon_m, probe)) {
            covered = true;
            break;
          }
        }
        if (covered) continue;
        // Blocked region on the right: traverse q->p direction (the polygon lies left of p->q).
        LabeledSegment s;
        s.segment_m = {p + t1 * e, p + t0 * e};
        s.label = f.label;
        pieces.push_back(s);
      }
    }
  }

  // Merge collinear, same-orientation, touching or overlapping pieces with the same label.
  struct Keyed {
    int label;
    long long angle_key, offset_key;
    double t0, t1;
    Vec2 d, origin;
  };
  std::vector<Keyed> keyed;
  keyed.reserve(pieces.size());
  for (const LabeledSegment& s : pieces) {
    const Vec2 d = (s.segment_m.b_m - s.segment_m.a_m).normalized();
    const Vec2 nrm(-d.y(), d.x());
    const double angle = std::atan2(d.y(), d.x());
    const double offset = nrm.dot(s.segment_m.a_m);
    Keyed k;
    k.label = static_cast<int>(s.label);
    k.angle_key = std::llround(angle * 1e9);
    k.offset_key = std::llround(offset * 1e7);
    k.t0 = d.dot(s.segment_m.a_m);
    k.t1 = d.dot(s.segment_m.b_m);
    k.d = d;
    k.origin = s.segment_m.a_m - k.t0 * d;
    keyed.push_back(k);
  }
  std::sort(keyed.begin(), keyed.end(), [](const Keyed& x, const Keyed& y) {
    if (x.label != y.label) return x.label < y.label;
    if (x.angle_key != y.angle_key) return x.angle_key < y.angle_key;
    if (x.offset_key != y.offset_key) return x.offset_key < y.offset_key;
    return x.t0 < y.t0;
  });
  std::vector<LabeledSegment> merged;
  for (std::size_t i = 0; i < keyed.size();) {
    std::size_t j = i;
    double t0 = keyed[i].t0, t1 = keyed[i].t1;
    const Keyed& first = keyed[i];
    auto flush = [&]() {
      LabeledSegment s;
      s.segment_m = {first.origin + t0 * first.d, first.origin + t1 * first.d};
      s.label = static_cast<SurfaceLabel>(first.label);
      merged.push_back(s);
    };
    ++j;
    while (j < keyed.size() && keyed[j].label == first.label && keyed[j].angle_key == first.angle_key &&
           keyed[j].offset_key == first.offset_key) {
      if (keyed[j].t0 <= t1 + 1e-9) {
        t1 = std::max(t1, keyed[j].t1);
      } else {
        flush();
        t0 = keyed[j].t0;
        t1 = keyed[j].t1;
      }
      ++j;
    }
    flush();
    i = j;
  }
  return merged;
}

std::vector<LabeledSegment> blocking_outline(const FloorPlan& plan, const BlockingOptions& options) {
  return footprint_outline(blocking_footprints(plan, options));
}

bool clip_segment_to_box(Vec2& a, Vec2& b, double x0, double y0, double x1, double y1) {
  double t0 = 0.0, t1 = 1.0;
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {a.x() - x0, x1 - a.x(), a.y() - y0, y1 - a.y()};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
    } else {
      const double r = q[i] / p[i];
      if (p[i] < 0.0) t0 = std::max(t0, r);
      else t1 = std::min(t1, r);
      if (t0 > t1) return false;
    }
  }
  const Vec2 a0 = a;
  a = a0 + t0 * Vec2(dx, dy);
  b = a0 + t1 * Vec2(dx, dy);
  return true;
}

FloorPlan rotate_plan(const FloorPlan& plan, double yaw_rad) {
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  auto R = [&](const Vec2& v) { return Vec2(c * v.x() - s * v.y(), s * v.x() + c * v.y()); };
  FloorPlan out = plan;
  for (Wall& w : out.walls) {
    w.a_m = R(w.a_m);
    w.b_m = R(w.b_m);
  }
  for (Door& d : out.doors) d.center_m = R(d.center_m);
  for (Window& w : out.windows) w.center_m = R(w.center_m);
  for (Obstacle& o : out.obstacles) {
    o.center_m = R(o.center_m);
    o.yaw_rad += yaw_rad;
  }
  for (Room& room : out.rooms) {
    for (Vec2& v : room.polygon_m) v = R(v);
    for (std::vector<Vec2>& hole : room.holes_m)
      for (Vec2& v : hole) v = R(v);
  }
  return out;
}

}  // namespace floorcast
