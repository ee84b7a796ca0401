// A simulated walk written as a walk folder (sim/walk_io.hpp): the walk, its odometry and the
// observations on its schedule (perfect observations, or simulated scans with optional colour
// views for a depth network to look at). `floorcast sim walk` and Python's floorcast.sim_walk are
// fronts on write_simulated_walk.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "floorcast/floorplans/floor_plan.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/scan_params.hpp"
#include "floorcast/sim/walk_io.hpp"

namespace floorcast {

struct WalkSimulationOptions {
  WalkParams walk;                 ///< the walk (its seed included)
  OdometryParams odometry;         ///< the odometry model and its seed
  ObservationSchedule schedule;    ///< when observations are made
  std::optional<Pose2> start;      ///< none: random_start_pose(plan, walk)
  /// Observations: perfect (exact visible walls) or simulated scans with `scan` (its seed is mixed
  /// with `scan_seed` and the step, so every step sees its own noise).
  bool perfect = true;
  PerfectObservationParams perfect_params;
  ScanParams scan;
  std::uint64_t scan_seed = 1;
  /// Scans: also render every view in colour (view_NNN_rgb.png, OpenGL module) from its true
  /// camera pose, as `sim scan --rgb` does; with setting single, F3Loc's one forward view per
  /// observation.
  bool rgb = false;
};

/// What was written.
struct SimulatedWalkFolder {
  WalkRecord record;
  std::vector<int> observation_steps;
  double render_s = 0.0;  ///< scans: simulation time, seconds
  double rgb_s = 0.0;     ///< colour rendering time, seconds
};

/// The folder name of the observation at `step` inside a walk folder: "observations/step_NNNN".
std::string walk_observation_folder(int step);

/// Simulates the walk, its odometry and observations and writes them into `dir` (created when
/// missing): walk.json, truth.tum, odometry.tum, steps.csv and observations/step_NNNN/ (an
/// observation.json or a scan folder). Throws InputError for options that cannot be simulated
/// (rgb with perfect observations, an unloadable OpenGL module with rgb, a start pose outside the
/// free space).
SimulatedWalkFolder write_simulated_walk(const FloorPlan& plan, const WalkSimulationOptions& options, const std::string& dir);

}  // namespace floorcast
