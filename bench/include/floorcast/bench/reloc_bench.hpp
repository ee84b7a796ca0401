// `floorcast bench reloc`: the cost of one plane relocalization (VoxelPlane-Reloc) from a scan,
// the plane matcher's map planes precomputed once per plan. Per scan, on one thread, CPU seconds
// of the calling thread:
//   - sensor preprocessing: back-projection, merging and voxelisation of the LiDAR path;
//   - plane extraction: the voxel-plane extractor, wall segments and plane patches;
//   - matching: the plane matcher's relocalization (triplets, evaluation, density, modes);
// and the whole observation module (observe_scan) for reference. Medians and 90th percentiles,
// with the share of scans localized within 1 m and 30 deg. Keys: results/planes.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "floorcast/core/params.hpp"
#include "floorcast/core/scan.hpp"
#include "floorcast/core/types.hpp"
#include "floorcast/floorplans/floor_plan.hpp"
#include "floorcast/observe/observation_module.hpp"

namespace floorcast {

struct RelocBenchScan {
  Scan scan;
  Pose2 truth;
};

struct RelocBenchParams {
  ObservationParams observe;  ///< the LiDAR path is used whatever observe.path says
  /// The experiment's shared quantities (range: the sensor's), then the matcher's own overrides.
  SharedParams shared;
  nlohmann::json matcher_overrides = nlohmann::json::object();
  int repeats = 3;  ///< timings per scan: the median of this many runs
};

/// A per-scan quantity over the scans of a plan.
struct RelocBenchStat {
  double median = 0.0;
  double p90 = 0.0;
  double max = 0.0;
};

/// One plan's measurements.
struct RelocBenchResult {
  std::string plan;  ///< the plan file (set by the caller)
  std::size_t scans = 0;
  double precompute_cpu_s = 0.0;   ///< map planes and pairs, once per plan
  double precompute_wall_s = 0.0;
  double map_planes = 0.0;
  double precompute_mb = 0.0;
  RelocBenchStat preprocess_cpu_s;      ///< back-projection, merge, voxelisation
  RelocBenchStat extraction_cpu_s;      ///< voxel planes, wall segments, plane patches
  RelocBenchStat match_cpu_s;           ///< the planes matcher
  RelocBenchStat relocalization_cpu_s;  ///< extraction + matching
  RelocBenchStat observe_module_cpu_s;  ///< observe_scan on the LiDAR path, for reference
  RelocBenchStat submap_planes;
  RelocBenchStat hypotheses_evaluated;
  int localized = 0;
  int within_1m_30deg = 0;
};

/// What `floorcast bench reloc --json` prints.
struct RelocBenchReport {
  std::string protocol =
      "per scan, one thread, CPU seconds of the calling thread, median of --repeats runs; "
      "relocalization = plane extraction (voxel planes, walls, patches) + planes matcher";
  std::string sensor;
  std::uint64_t seed = 0;
  std::vector<RelocBenchResult> plans;
};

/// Times every scan of one plan.
RelocBenchResult bench_reloc(const FloorPlan& plan, const std::vector<RelocBenchScan>& scans, const RelocBenchParams& params);

nlohmann::ordered_json to_json(const RelocBenchReport& report);

}  // namespace floorcast
