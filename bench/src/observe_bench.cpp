#include "floorcast/bench/observe_bench.hpp"

#include <tbb/info.h>

#include <algorithm>
#include <cstdlib>
#include <ctime>

#include "floorcast/core/fields.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/observe/observation_module.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "floorcast/sim/scan_sim.hpp"

namespace floorcast {
namespace {

/// CPU seconds of the whole process (all threads): a load-independent companion of wall time.
double process_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// `count` observer poses spread over the interior: cells at least `clearance_m` from any wall,
/// taken at evenly spaced ranks of a fixed pseudo-random order (deterministic).
std::vector<Pose2> bench_poses(const FloorPlan& plan, int count, double clearance_m) {
  RasterOptions ro;
  ro.resolution_m_per_px = 0.25;
  const PlanRasters r = make_plan_rasters(plan, ro);
  std::vector<std::pair<std::uint64_t, Vec2>> cells;
  for (int row = 0; row < r.valid.rows; ++row)
    for (int col = 0; col < r.valid.cols; ++col) {
      if (!r.valid.at<unsigned char>(row, col) || r.distance_m.at<float>(row, col) < clearance_m) continue;
      std::uint64_t h = (static_cast<std::uint64_t>(row) << 32) ^ static_cast<std::uint64_t>(col);
      h = (h ^ (h >> 31)) * 0x7fb5d329728ea185ULL;
      h = (h ^ (h >> 27)) * 0x81dadef4bc2dd44dULL;
      cells.push_back({h ^ (h >> 33), r.grid.cell_center_m(row, col)});
    }
  if (cells.empty()) throw InputError("bench observe: the plan has no interior point " + std::to_string(clearance_m) + " m from the walls");
  std::sort(cells.begin(), cells.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Pose2> poses;
  for (int k = 0; k < count; ++k) {
    const Vec2 c = cells[(cells.size() * static_cast<std::size_t>(k)) / static_cast<std::size_t>(count)].second;
    poses.push_back({c.x(), c.y(), 0.7 * k});
  }
  return poses;
}

}  // namespace

ObserveBenchResult bench_observe(const FloorPlan& plan, const std::string& plan_name, const ObserveBenchParams& params) {
  const RayScene scene(extrude_plan(plan));
  const std::vector<Pose2> poses = bench_poses(plan, params.scans, 0.6);

  struct PathRun {
    std::string name, preset;
    ObservationParams params;
    std::vector<double> total_s, cpu_s;
    std::map<std::string, std::vector<double>> stage_s;
    std::vector<double> segments, points;
  };
  std::vector<PathRun> runs(2);
  runs[0].name = "mono";
  runs[0].preset = "mono";
  runs[0].params.path = ObservationPath::kMono;
  runs[1].name = "lidar";
  runs[1].preset = "lidar";
  runs[1].params.path = ObservationPath::kLidar;
  for (PathRun& run : runs) {
    ScanParams sp = scan_preset(run.preset);
    for (std::size_t k = 0; k < poses.size(); ++k) {
      sp.seed = 1000 + k;
      const Scan scan = simulate_scan(scene, poses[k], sp).scan;
      for (int rep = 0; rep < params.repeats; ++rep) {
        const double cpu0 = process_cpu_s();
        const ObservationResult r = observe_scan(scan, run.params);
        run.cpu_s.push_back(process_cpu_s() - cpu0);
        run.total_s.push_back(r.total_s);
        for (const auto& [stage, s] : r.stage_s) run.stage_s[stage].push_back(s);
        if (rep == 0) {
          run.segments.push_back(static_cast<double>(r.observation.segments_m.size()));
          run.points.push_back(static_cast<double>(r.diagnostics.points_back_projected));
        }
      }
    }
  }
  ObserveBenchResult out;
  out.mono_scan_s = median(runs[0].total_s);
  out.lidar_scan_s = median(runs[1].total_s);
  out.mono_scan_cpu_s = median(runs[0].cpu_s);
  out.lidar_scan_cpu_s = median(runs[1].cpu_s);
  out.threads = tbb::info::default_concurrency();
  double load[3] = {0.0, 0.0, 0.0};
  if (getloadavg(load, 3) == 3) out.load_average_1min = load[0];
  out.plan = plan_name;
  out.scans = params.scans;
  out.repeats = params.repeats;
  for (const PathRun& run : runs) {
    ObserveBenchPath d;
    const ScanParams sp = scan_preset(run.preset);
    d.name = run.name;
    d.preset = run.preset;
    d.views = sp.geometry.num_views;
    d.resolution = std::to_string(sp.geometry.width_px) + "x" + std::to_string(sp.geometry.height_px);
    d.median_s = median(run.total_s);
    d.max_s = *std::max_element(run.total_s.begin(), run.total_s.end());
    d.median_cpu_s = median(run.cpu_s);
    for (const auto& [stage, v] : run.stage_s) d.stage_median_s[stage] = median(v);
    d.median_segments = median(run.segments);
    d.median_points = median(run.points);
    d.params = to_json(run.params);
    out.paths.push_back(std::move(d));
  }
  return out;
}

nlohmann::ordered_json to_json(const ObserveBenchResult& r) {
  using R = ObserveBenchResult;
  using P = ObserveBenchPath;
  constexpr double kAny = 1e300;
  auto no_read = [](ParamReader&, auto&) {};
  static const FieldList<P> path =
      FieldList<P>("observe bench path")
          .text("preset", &P::preset, "the scan preset")
          .integer("views", &P::views, 0, 1 << 20, "views per scan")
          .text("resolution", &P::resolution, "view size, WxH")
          .number("median_s", &P::median_s, 0.0, kAny, "observation module, median wall s per scan")
          .number("max_s", &P::max_s, 0.0, kAny, "the slowest scan, s")
          .number("median_cpu_s", &P::median_cpu_s, 0.0, kAny, "median CPU s per scan (all threads)")
          .custom(
              "stage_median_s",
              [](nlohmann::ordered_json& j, const P& p) {
                for (const auto& [stage, v] : p.stage_median_s) j["stage_median_s"][stage] = v;
              },
              no_read, "{stage: s}", "median wall s per stage")
          .number("median_segments", &P::median_segments, 0.0, kAny, "segments per scan, median")
          .number("median_points", &P::median_points, 0.0, kAny, "back-projected points per scan, median")
          .json("params", &P::params, "the observation module's parameters");
  static const FieldList<R> f =
      FieldList<R>("observe bench")
          .number("mono_scan_s", &R::mono_scan_s, 0.0, kAny, "mono path, median wall s per scan")
          .number("lidar_scan_s", &R::lidar_scan_s, 0.0, kAny, "LiDAR path, median wall s per scan")
          .number("mono_scan_cpu_s", &R::mono_scan_cpu_s, 0.0, kAny, "mono path, median CPU s")
          .number("lidar_scan_cpu_s", &R::lidar_scan_cpu_s, 0.0, kAny, "LiDAR path, median CPU s")
          .integer("threads", &R::threads, 0, 1 << 20, "TBB threads")
          .custom(
              "load_average_1min",
              [](nlohmann::ordered_json& j, const R& r) {
                if (r.load_average_1min) j["load_average_1min"] = *r.load_average_1min;
              },
              no_read, "number", "load average after the measurements (when known)")
          .text("plan", &R::plan, "the plan")
          .integer("scans", &R::scans, 0, 1 << 20, "scans per path")
          .integer("repeats", &R::repeats, 0, 1 << 20, "repeats per scan")
          .custom(
              "paths",
              [](nlohmann::ordered_json& j, const R& r) {
                for (const P& p : r.paths) j[p.name] = path.write(p);
              },
              no_read, "{mono: {...}, lidar: {...}}", "per path (written under its name)");
  return f.write(r);
}

}  // namespace floorcast
