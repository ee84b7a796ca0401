// `floorcast bench observe`: wall-clock time of the observation module per scan, for each path
// (mono on the PALMS+ "mono" preset scan, LiDAR on the PALMS "lidar" preset scan), medians over
// scans at several poses of a shipped building and repeats.
#include <tbb/info.h>

#include <cstdlib>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/observe/observation_module.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "floorcast/sim/scan_sim.hpp"

namespace floorcast::cli {
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

std::string default_plan() {
  for (const char* name : {"campus.json", "office.json", "two_rooms.json"}) {
    const std::string p = source_dir() + "/floorplans/buildings/" + name;
    if (std::filesystem::exists(p)) return p;
  }
  throw InputError("bench observe: no shipped building found under floorplans/buildings/ (use --plan)");
}

void register_bench_observe(CLI::App& root) {
  CLI::App& bench = group(root, "bench", "Benchmarks (medians over repeats, same-run ratios)");
  struct Options {
    std::string plan;
    int scans = 5;
    int repeats = 3;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = bench.add_subcommand("observe", "Observation module time per scan: mono (PALMS+) and LiDAR (PALMS) paths");
  cmd->add_option("--plan", o->plan, "Floor plan (default: the first shipped of campus, office, two_rooms)");
  cmd->add_option("--scans", o->scans, "Scans (poses) per path")->capture_default_str()->check(CLI::Range(1, 100));
  cmd->add_option("--repeats", o->repeats, "Repeats per scan (median over all)")->capture_default_str()->check(CLI::Range(1, 100));
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->callback([o] {
    const std::string plan_path = o->plan.empty() ? default_plan() : o->plan;
    const FloorPlan plan = load_floor_plan(plan_path);
    const RayScene scene(extrude_plan(plan));
    const std::vector<Pose2> poses = bench_poses(plan, o->scans, 0.6);

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
        for (int rep = 0; rep < o->repeats; ++rep) {
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
    nlohmann::ordered_json j;
    j["mono_scan_s"] = median(runs[0].total_s);
    j["lidar_scan_s"] = median(runs[1].total_s);
    j["mono_scan_cpu_s"] = median(runs[0].cpu_s);
    j["lidar_scan_cpu_s"] = median(runs[1].cpu_s);
    j["threads"] = tbb::info::default_concurrency();
    {
      double load[3] = {0.0, 0.0, 0.0};
      if (getloadavg(load, 3) == 3) j["load_average_1min"] = load[0];
    }
    j["plan"] = plan_path;
    j["scans"] = o->scans;
    j["repeats"] = o->repeats;
    for (const PathRun& run : runs) {
      nlohmann::ordered_json d;
      const ScanParams sp = scan_preset(run.preset);
      d["preset"] = run.preset;
      d["views"] = sp.geometry.num_views;
      d["resolution"] = std::to_string(sp.geometry.width_px) + "x" + std::to_string(sp.geometry.height_px);
      d["median_s"] = median(run.total_s);
      d["max_s"] = *std::max_element(run.total_s.begin(), run.total_s.end());
      d["median_cpu_s"] = median(run.cpu_s);
      for (const auto& [stage, v] : run.stage_s) d["stage_median_s"][stage] = median(v);
      d["median_segments"] = median(run.segments);
      d["median_points"] = median(run.points);
      d["params"] = to_json(run.params);
      j[run.name] = d;
    }
    if (o->json) {
      std::cout << j.dump(2) << "\n";
      return;
    }
    std::cout << std::fixed << std::setprecision(3) << "bench observe: " << plan_path << ", " << o->scans << " scans x "
              << o->repeats << " repeats, " << j["threads"] << " threads, load average "
              << j.value("load_average_1min", 0.0) << "\n";
    for (const PathRun& run : runs) {
      const auto& d = j[run.name];
      std::cout << "  " << std::left << std::setw(6) << run.name << std::right << d["preset"].get<std::string>() << " "
                << d["views"] << " views " << d["resolution"].get<std::string>() << ": median "
                << d["median_s"].get<double>() << " s wall (max " << d["max_s"].get<double>() << " s), "
                << d["median_cpu_s"].get<double>() << " s CPU, "
                << d["median_segments"].get<double>() << " segments\n    stages:";
      for (const auto& [stage, v] : d["stage_median_s"].items()) std::cout << " " << stage << " " << v.get<double>();
      std::cout << "\n";
    }
    std::cout << "  PALMS+ reports 20.4 s for point cloud reconstruction + scale alignment (Apple M2, Python); "
                 "target here <= 0.5 s per default mono scan on 2 cores\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_bench_observe);
}  // namespace floorcast::cli
