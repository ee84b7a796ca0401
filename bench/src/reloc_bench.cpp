#include "floorcast/bench/reloc_bench.hpp"

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "floorcast/core/fields.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/timing.hpp"
#include "floorcast/match/plane_matcher.hpp"

namespace floorcast {
namespace {

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

RelocBenchResult bench_reloc(const FloorPlan& plan, const std::vector<RelocBenchScan>& scans, const RelocBenchParams& params) {
  // One thread: the CPU seconds of the calling thread are the whole cost.
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  ObservationParams op = params.observe;
  op.path = ObservationPath::kLidar;
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = thread_cpu_s();
  const std::unique_ptr<Matcher> matcher = make_matcher_config("planes", params.matcher_overrides, params.shared)->build(plan);
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
    return RelocBenchStat{quantile(v, 0.5), quantile(v, 0.9), quantile(v, 1.0)};
  };
  RelocBenchResult out;
  out.scans = scans.size();
  out.precompute_cpu_s = precompute_cpu;
  out.precompute_wall_s = precompute_wall;
  out.map_planes = map_planes;
  out.precompute_mb = static_cast<double>(matcher->precompute_bytes()) / 1e6;
  out.preprocess_cpu_s = stat(pre_s);
  out.extraction_cpu_s = stat(extract_s);
  out.match_cpu_s = stat(match_s);
  out.relocalization_cpu_s = stat(reloc_s);
  out.observe_module_cpu_s = stat(observe_s);
  out.submap_planes = stat(planes_n);
  out.hypotheses_evaluated = stat(hyp_n);
  out.localized = localized;
  out.within_1m_30deg = correct;
  return out;
}

nlohmann::ordered_json to_json(const RelocBenchReport& report) {
  constexpr double kAny = 1e300;
  using S = RelocBenchStat;
  static const FieldList<S> stat = FieldList<S>("statistic")
                                       .number("median", &S::median, 0.0, kAny, "median over the scans")
                                       .number("p90", &S::p90, 0.0, kAny, "90th percentile")
                                       .number("max", &S::max, 0.0, kAny, "largest");
  using R = RelocBenchResult;
  static const FieldList<R> plan =
      FieldList<R>("reloc bench plan")
          .text("plan", &R::plan, "the plan file")
          .unsigned_integer("scans", &R::scans, "simulated scans")
          .number("precompute_cpu_s", &R::precompute_cpu_s, 0.0, kAny, "map planes and pairs, once per plan, CPU s")
          .number("precompute_wall_s", &R::precompute_wall_s, 0.0, kAny, "the same, wall s")
          .number("map_planes", &R::map_planes, 0.0, kAny, "planes of the map")
          .number("precompute_mb", &R::precompute_mb, 0.0, kAny, "memory of the map, MB")
          .section("preprocess_cpu_s", &R::preprocess_cpu_s, stat)
          .section("extraction_cpu_s", &R::extraction_cpu_s, stat)
          .section("match_cpu_s", &R::match_cpu_s, stat)
          .section("relocalization_cpu_s", &R::relocalization_cpu_s, stat)
          .section("observe_module_cpu_s", &R::observe_module_cpu_s, stat)
          .section("submap_planes", &R::submap_planes, stat)
          .section("hypotheses_evaluated", &R::hypotheses_evaluated, stat)
          .integer("localized", &R::localized, 0, 1 << 30, "scans with a pose")
          .integer("within_1m_30deg", &R::within_1m_30deg, 0, 1 << 30, "scans localized within 1 m and 30 deg");
  using P = RelocBenchReport;
  static const FieldList<P> f = FieldList<P>("reloc bench")
                                    .text("protocol", &P::protocol, "what is timed")
                                    .text("sensor", &P::sensor, "scan preset")
                                    .unsigned_integer("seed", &P::seed, "pose sampling seed")
                                    .list("plans", &P::plans, plan);
  return f.write(report);
}

}  // namespace floorcast
