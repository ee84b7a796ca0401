// Observe 2D points of an L-shaped room and localize them on its plan, with the installed
// floorcast::observe and floorcast::match only; then find a floor with the observation module's
// ground-plane search (PCL, through the installed back-end module). Prints "ok ..." on success.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
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
  // A flat floor 1.4 m below the sensor, found by the PCL back-end module of the installed tree.
  setenv("FLOORCAST_MODULE_DIR", CONSUMER_MODULE_DIR, 0);
  PointCloud3f cloud;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  for (int i = 0; i < 4000; ++i) cloud.emplace_back(u(rng), u(rng), -1.4f);
  const GroundPlaneResult ground = detect_ground_plane(cloud, GroundPlaneParams{});
  const bool ok = err < 0.3 && ground.found && std::abs(ground.height_m + 1.4) < 0.02;
  std::printf("%s %zu segments, error %.3f m, ground %s at %.3f m\n", ok ? "ok" : "FAILED", obs.segments_m.size(), err,
              ground.found ? "found" : ground.reason.c_str(), ground.height_m);
  return ok ? 0 : 1;
}
