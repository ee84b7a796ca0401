// `floorcast bench reloc`: the cost of one plane relocalization (VoxelPlane-Reloc) from a scan,
// the plane matcher's map planes precomputed once per plan. Per scan, on one thread, CPU seconds
// of the calling thread:
//   - sensor preprocessing: back-projection, merging and voxelisation of the LiDAR path;
//   - plane extraction: the voxel-plane extractor, wall segments and plane patches;
//   - matching: the plane matcher's relocalization (triplets, evaluation, density, modes);
// and the whole observation module (observe_scan) for reference. Medians and 90th percentiles,
// with the share of scans localized within 1 m and 30 deg.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

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
  nlohmann::json matcher_overrides = nlohmann::json::object();
  int repeats = 3;  ///< timings per scan: the median of this many runs
};

/// Times every scan of one plan (keys documented in results/planes.md).
nlohmann::ordered_json bench_reloc(const FloorPlan& plan, const std::vector<RelocBenchScan>& scans,
                                   const RelocBenchParams& params);

}  // namespace floorcast
