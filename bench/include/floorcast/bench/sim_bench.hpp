// `floorcast bench sim`: throughput of the scan renderer against raw Embree streams on the same
// scene and rays, measured in one run (interleaved, medians), the time of the default mono, LiDAR
// and phone scans, and the OpenGL (OSMesa) views. Keys: results/bench_sim.md.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "floorcast/core/types.hpp"
#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast {

struct SimBenchParams {
  int repeats = 9;  ///< per measurement (median reported)
};

struct SimBenchResult {
  double scan_ms = 0.0;               ///< default mono scan, median wall
  double renderer_mrays_per_s = 0.0;  ///< the scan renderer (exact depth)
  double embree_raw_mrays_per_s = 0.0;  ///< rtcIntersect1M on the same rays, 256-ray chunks
  double ratio = 0.0;                 ///< renderer / raw
  std::string plan;                   ///< the plan file's name
  std::size_t triangles = 0;
  int threads = 0;
  std::size_t rays_per_scan = 0;
  double hit_fraction = 0.0;
  double scene_build_ms = 0.0;
  double scan_cpu_ms = 0.0;           ///< default mono scan, median process CPU (all threads)
  double load_average_1min = 0.0;     ///< before the measurements (-1: unknown)
  double lidar_scan_ms = 0.0;
  double phone_scan_ms = 0.0;
  double osmesa_6_views_ms = 0.0;     ///< OSMesa depth of the six views
  double rgb_6_views_ms = 0.0;        ///< colour + depth + labels of the six views
  double rgb_frames_per_s_640x480 = 0.0;
  double gl_first_use_ms = 0.0;       ///< module load, context, shaders, mesh upload
  std::string gl_renderer;
  int repeats = 0;
  Pose2 pose;                         ///< the most open interior point (not in the JSON)
};

/// Runs the measurements on `plan` (named `plan_name` in the result).
SimBenchResult bench_sim(const FloorPlan& plan, const std::string& plan_name, const SimBenchParams& params);

nlohmann::ordered_json to_json(const SimBenchResult& result);

}  // namespace floorcast
