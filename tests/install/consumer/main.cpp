// Observe 2D points of an L-shaped room and localize them on its plan, with the installed
// floorcast::observe and floorcast::match only. Prints "ok <error_m>" on success.
#include <cmath>
#include <cstdio>
#include <vector>

#include "floorcast/floorplans/floor_plan.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/observe/observation_module.hpp"

int main() {
  using namespace floorcast;
  FloorPlan plan;
  const std::vector<Vec2> corners = {{0, 0}, {8, 0}, {8, 3}, {3, 3}, {3, 6}, {0, 6}};
  for (std::size_t i = 0; i < corners.size(); ++i) {
    Wall w;
    w.id = "w" + std::to_string(i);
    w.a_m = corners[i];
    w.b_m = corners[(i + 1) % corners.size()];
    plan.walls.push_back(w);
  }
  // The observer stands at (1.5, 1.2) facing +x: points on the wall surfaces (0.075 m inside the
  // centrelines) in its frame, every 5 cm.
  const Pose2 truth{1.5, 1.2, 0.0};
  std::vector<Eigen::Vector2d> points;
  const double t = 0.075;
  const std::vector<Vec2> inner = {{t, t}, {8 - t, t}, {8 - t, 3 - t}, {3 - t, 3 - t}, {3 - t, 6 - t}, {t, 6 - t}};
  for (std::size_t i = 0; i < inner.size(); ++i) {
    const Vec2 a = inner[i], b = inner[(i + 1) % inner.size()];
    const int n = static_cast<int>((b - a).norm() / 0.05);
    for (int k = 0; k <= n; ++k) points.push_back(truth.inverse_transform(a + (b - a) * (double(k) / n)));
  }
  const SegmentExtractionResult seg = extract_segments_2d(points, SegmentExtractionParams{}, 10.0);
  Observation2D obs;
  obs.segments_m = seg.segments_m;
  obs.ray_ranges_m = seg.ray_ranges_m;
  const PoseHypothesis best = make_matcher("kernel", plan)->match(obs).posterior.argmax();
  const double err = std::hypot(best.x_m - truth.x_m, best.y_m - truth.y_m);
  std::printf("%s %zu segments, error %.3f m\n", err < 0.3 ? "ok" : "FAILED", obs.segments_m.size(), err);
  return err < 0.3 ? 0 : 1;
}
