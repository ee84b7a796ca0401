// `floorcast bench observe`: wall-clock time of the observation module per scan, for each path
// (mono on the PALMS+ "mono" preset scan, LiDAR on the PALMS "lidar" preset scan), medians over
// scans at several poses of a plan and repeats.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

struct ObserveBenchParams {
  int scans = 5;    ///< poses per path
  int repeats = 3;  ///< per scan (median over all)
};

/// One path's numbers.
struct ObserveBenchPath {
  std::string name;    ///< mono, lidar
  std::string preset;  ///< the scan preset
  int views = 0;
  std::string resolution;  ///< "WxH"
  double median_s = 0.0, max_s = 0.0, median_cpu_s = 0.0;
  std::map<std::string, double> stage_median_s;
  double median_segments = 0.0, median_points = 0.0;
  nlohmann::ordered_json params;  ///< the observation module's parameters
};

struct ObserveBenchResult {
  double mono_scan_s = 0.0, lidar_scan_s = 0.0, mono_scan_cpu_s = 0.0, lidar_scan_cpu_s = 0.0;
  int threads = 0;
  std::optional<double> load_average_1min;
  std::string plan;
  int scans = 0, repeats = 0;
  std::vector<ObserveBenchPath> paths;  ///< mono, lidar
};

ObserveBenchResult bench_observe(const FloorPlan& plan, const std::string& plan_name, const ObserveBenchParams& params);

nlohmann::ordered_json to_json(const ObserveBenchResult& result);

}  // namespace floorcast
