// `floorcast bench walls`: accuracy of the observation module's wall segments against the perfect
// observation of the same pose (visible walls within the sensor's range, doors as in the plan):
// recovered fraction of the visible wall length, precision, spurious segments, angle and offset
// errors, per configuration of the module, on simulated scans at sampled poses of one or more
// plans. Keys of the JSON: results/bench_walls.md.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "floorcast/eval/observation_accuracy.hpp"
#include "floorcast/floorplans/floor_plan.hpp"
#include "floorcast/observe/observation_module.hpp"

namespace floorcast {

/// One configuration of the observation module under a label, parsed before any work.
struct WallsBenchConfig {
  std::string label;
  nlohmann::json overrides = nlohmann::json::object();  ///< as given (written into the report)
  ObservationParams params;
};

/// Parses "LABEL=JSON" specs (observation-parameter overrides; a LiDAR sensor implies
/// "path": "lidar"); none: the default configurations of the sensor (lidar: the pcl and
/// voxelplane extractors; otherwise the mono path). Throws InputError naming the spec.
std::vector<WallsBenchConfig> walls_bench_configs(const std::vector<std::string>& specs, const std::string& sensor);

struct WallsBenchParams {
  int points = 12;                ///< poses per plan (sampled like `floorcast run`)
  std::uint64_t seed = 21;        ///< pose sampling seed (scan noise seed = seed + pose index)
  double clearance_m = 0.5;
  std::string sensor = "lidar";   ///< scan preset
  double range_m = 0.0;           ///< truth range; 0 = the preset's maximum range
  double reference_range_m = 10.0;
  std::vector<std::string> region_kinds;  ///< poses only in rooms of these kinds (empty: anywhere)
  bool pictures = false;          ///< draw one picture per scan and configuration
};

/// A plan with the rooms its poses may be restricted to.
struct WallsBenchPlan {
  std::string path;  ///< as given (reported)
  FloorPlan plan;
  std::vector<Room> rooms;
};

/// One scan seen by one configuration.
struct WallsBenchScan {
  std::string plan_name;
  int pose_index = 0;
  std::string label;
  SegmentAccuracy accuracy;
  double reference_truth_m = 0.0;   ///< wall length within the reference range
  int reference_segments = 0;
  /// LiDAR: coverage of the truth by any return, by the confident returns, by the band.
  double returns_coverage = 0.0, confident_coverage = 0.0, slice_coverage = 0.0;
};

struct WallsBenchConfigResult {
  WallsBenchConfig config;
  SegmentAccuracy total;
  SegmentAccuracy opaque;  ///< against the truth without glass (which the LiDAR barely returns)
  std::vector<double> recall_per_scan, segments_per_scan, time_s;
};

/// One configuration's numbers as reported.
struct WallsBenchConfigSummary {
  std::string label;
  nlohmann::ordered_json overrides = nlohmann::ordered_json::object();
  double recall = 0.0, recall_opaque = 0.0, recall_median_per_scan = 0.0, precision = 0.0, segments_median = 0.0;
  int segments_total = 0, spurious_segments = 0;
  double angle_error_median_deg = 0.0, angle_error_p90_deg = 0.0, offset_error_median_m = 0.0, offset_error_p90_m = 0.0;
  double time_median_s = 0.0;
};

/// Every number the bench reports (its JSON: results/bench_walls.md).
struct WallsBenchSummary {
  std::vector<std::string> plans;
  int points_per_plan = 0;
  std::uint64_t seed = 0;
  std::string sensor;
  double truth_range_m = 0.0;
  int scans = 0;
  double truth_length_m = 0.0;
  std::vector<std::string> region_kinds;
  double reference_range_m = 0.0;
  double reference_truth_length_m = 0.0;
  double reference_segments_median = 0.0;
  SegmentAccuracyParams match;
  bool lidar = false;
  /// LiDAR: coverage of the truth by the LiDAR points (per scan: median or mean).
  double slice_coverage_median = 0.0, slice_coverage_mean = 0.0, returns_coverage_mean = 0.0,
         confident_coverage_mean = 0.0;
  std::vector<WallsBenchConfigSummary> configs;
};
nlohmann::ordered_json to_json(const WallsBenchSummary& summary);

struct WallsBenchReport {
  std::vector<WallsBenchConfigResult> configs;
  std::vector<WallsBenchScan> per_scan;  ///< plan, pose, configuration order
  WallsBenchSummary summary;
};

/// Runs every configuration on simulated scans at sampled poses of every plan. `on_picture`
/// receives one picture per scan and configuration when params.pictures (file name, image).
WallsBenchReport run_walls_bench(const std::vector<WallsBenchPlan>& plans, const std::vector<WallsBenchConfig>& configs,
                                 const WallsBenchParams& params,
                                 const std::function<void(const std::string&, const cv::Mat&)>& on_picture = {});

}  // namespace floorcast
