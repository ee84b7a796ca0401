#include "floorcast/bench/reloc_bench.hpp"

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "floorcast/core/math.hpp"
#include "floorcast/core/timing.hpp"
#include "floorcast/match/plane_matcher.hpp"

namespace floorcast {
namespace {

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

/// The LiDAR path's cloud: every kept view in the scan frame, voxelised, within range (as
/// observe_scan builds it).
PointCloud3f lidar_cloud(const Scan& scan, const LidarPathParams& lidar) {
  const BackProjectionResult bp = back_project_scan(scan, lidar.back_projection);
  PointCloud3f cloud;
  for (const ViewCloud& v : bp.views) {
    const PointCloud3f pts = view_points_scan(v, 1.0);
    cloud.insert(cloud.end(), pts.begin(), pts.end());
  }
  cloud = voxel_downsample(cloud, lidar.voxel_m);
  const double r2 = lidar.max_range_m * lidar.max_range_m;
  cloud.erase(std::remove_if(cloud.begin(), cloud.end(),
                             [r2](const Eigen::Vector3f& p) { return double(p.x()) * p.x() + double(p.y()) * p.y() > r2; }),
              cloud.end());
  return cloud;
}

}  // namespace

nlohmann::ordered_json bench_reloc(const FloorPlan& plan, const std::vector<RelocBenchScan>& scans, const RelocBenchParams& params) {
  // One thread: the CPU seconds of the calling thread are the whole cost.
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  ObservationParams op = params.observe;
  op.path = ObservationPath::kLidar;
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = thread_cpu_s();
  const std::unique_ptr<Matcher> matcher = make_matcher("planes", plan, params.matcher_overrides);
  const double precompute_cpu = thread_cpu_s() - c0;
  const double precompute_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<double> pre_s, extract_s, match_s, reloc_s, observe_s, planes_n, hyp_n;
  int localized = 0, correct = 0;
  double map_planes = 0.0;
  for (const RelocBenchScan& s : scans) {
    std::vector<double> pre, ext, mat, obs;
    Observation2D observation;
    MatchResult result;
    for (int r = 0; r < std::max(1, params.repeats); ++r) {
      double t = thread_cpu_s();
      const PointCloud3f cloud = lidar_cloud(s.scan, op.lidar);
      pre.push_back(thread_cpu_s() - t);
      t = thread_cpu_s();
      WallPlaneResult walls = extract_wall_segments(cloud, op.lidar);
      observation = Observation2D{};
      observation.max_range_m = op.lidar.max_range_m;
      observation.segments_m = std::move(walls.segments_m);
      observation.planes = plane_patches(cloud, walls.planes, op.planes);
      observation.plane_cell_m = op.planes.cell_m;
      ext.push_back(thread_cpu_s() - t);
      t = thread_cpu_s();
      result = matcher->match(observation, MatchRequest::modes(5));
      mat.push_back(thread_cpu_s() - t);
      t = thread_cpu_s();
      (void)observe_scan(s.scan, op);
      obs.push_back(thread_cpu_s() - t);
    }
    pre_s.push_back(median(pre));
    extract_s.push_back(median(ext));
    match_s.push_back(median(mat));
    reloc_s.push_back(median(ext) + median(mat));
    observe_s.push_back(median(obs));
    planes_n.push_back(static_cast<double>(observation.planes.size()));
    if (result.counters.count("map_planes")) map_planes = result.counters.at("map_planes");
    hyp_n.push_back(result.counters.count("hypotheses_evaluated") ? result.counters.at("hypotheses_evaluated") : 0.0);
    if (result.has_pose()) {
      ++localized;
      const PoseHypothesis& e = result.estimate();
      if (std::hypot(e.x_m - s.truth.x_m, e.y_m - s.truth.y_m) <= 1.0 &&
          angle_distance_rad(e.yaw_rad, s.truth.yaw_rad) <= deg_to_rad(30.0)) {
        ++correct;
      }
    }
  }
  auto stat = [](const std::vector<double>& v) {
    return nlohmann::ordered_json{{"median", percentile(v, 0.5)}, {"p90", percentile(v, 0.9)}, {"max", percentile(v, 1.0)}};
  };
  nlohmann::ordered_json j;
  j["scans"] = scans.size();
  j["precompute_cpu_s"] = precompute_cpu;
  j["precompute_wall_s"] = precompute_wall;
  j["map_planes"] = map_planes;
  j["precompute_mb"] = static_cast<double>(matcher->precompute_bytes()) / 1e6;
  j["preprocess_cpu_s"] = stat(pre_s);
  j["extraction_cpu_s"] = stat(extract_s);
  j["match_cpu_s"] = stat(match_s);
  j["relocalization_cpu_s"] = stat(reloc_s);
  j["observe_module_cpu_s"] = stat(observe_s);
  j["submap_planes"] = stat(planes_n);
  j["hypotheses_evaluated"] = stat(hyp_n);
  j["localized"] = localized;
  j["within_1m_30deg"] = correct;
  return j;
}

}  // namespace floorcast
