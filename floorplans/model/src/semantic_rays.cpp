#include "floorcast/floorplans/semantic_rays.hpp"

#include <algorithm>
#include <cmath>

namespace floorcast {
namespace {

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

BlockingOptions cut(double height_m) {
  BlockingOptions b;
  b.closed_doors_block = false;
  b.open_doors_block = false;
  b.glass_blocks = false;
  b.obstacles_block = false;
  b.cut_height_m = height_m;
  return b;
}

}  // namespace

SemanticPlanLines semantic_plan_lines(const FloorPlan& plan, BevClasses classes, double cut_height_m) {
  SemanticPlanLines out;
  BlockingOptions stops = cut(cut_height_m);
  if (classes == BevClasses::kOccupancy) {
    stops.glass_blocks = true;
    out.stops = outline_segments(blocking_outline(plan, stops));
    return out;
  }
  out.stops = outline_segments(blocking_outline(plan, stops));
  BlockingOptions all = cut(cut_height_m);
  all.closed_doors_block = all.open_doors_block = all.glass_blocks = true;
  BlockingOptions open_only = cut(cut_height_m);
  open_only.open_doors_block = true;
  std::vector<Footprint> open_leaves;
  for (Footprint& f : blocking_footprints(plan, open_only)) {
    if (f.label == SurfaceLabel::kDoorClosed) open_leaves.push_back(std::move(f));
  }
  for (const LabeledSegment& s : blocking_outline(plan, all)) {
    if (s.label == SurfaceLabel::kGlass) {
      out.permeable.push_back(s.segment_m);
      out.permeable_labels.push_back(SemanticClass::kWindow);
    } else if (s.label == SurfaceLabel::kDoorClosed) {
      const Vec2 mid = 0.5 * (s.segment_m.a_m + s.segment_m.b_m);
      const bool open = std::any_of(open_leaves.begin(), open_leaves.end(),
                                    [&](const Footprint& f) { return point_in_convex_polygon(f.polygon_m, mid); });
      out.permeable.push_back(s.segment_m);
      out.permeable_labels.push_back(open ? SemanticClass::kDoorOpen : SemanticClass::kDoorClosed);
    }
  }
  return out;
}

std::vector<SemanticHit> semantic_ray_hits(const SemanticPlanLines& lines, const Vec2& origin_m, double angle_rad,
                                           double max_range_m) {
  const Vec2 u(std::cos(angle_rad), std::sin(angle_rad));
  double stop = max_range_m;
  bool stopped = false;
  for (const Segment2& s : lines.stops) {
    const double t = ray_segment_distance(origin_m, u, s);
    if (t >= 0.0 && t < stop) {
      stop = t;
      stopped = true;
    }
  }
  std::vector<SemanticHit> hits;
  for (std::size_t i = 0; i < lines.permeable.size(); ++i) {
    const Segment2& s = lines.permeable[i];
    if (!(cross(u, s.b_m - s.a_m) > 0.0)) continue;  // entered from its free (left) side only
    const double t = ray_segment_distance(origin_m, u, s);
    if (t >= 0.0 && t < stop) hits.push_back({lines.permeable_labels[i], t});
  }
  std::sort(hits.begin(), hits.end(), [](const SemanticHit& a, const SemanticHit& b) {
    return a.range_m != b.range_m ? a.range_m < b.range_m : a.label < b.label;
  });
  if (stopped) hits.push_back({SemanticClass::kWall, stop});
  return hits;
}

}  // namespace floorcast
