// Runs a scenario's work units: simulate -> observe -> match (every matcher) -> errors.
//
// Every unit is a pure function of the scenario and its (cell, building, point) index: points
// are sampled once per building (same points in every cell), scans are seeded by
// (observation seed, building, point), so a unit gives the same result whenever and wherever it
// runs — which is what makes runs resumable, shardable and mergeable. File writing goes through
// a UnitSink (the run directory); the runner itself prints nothing.
#pragma once

#include <functional>
#include <optional>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>

#include "floorcast/scenarios/sampling.hpp"
#include "floorcast/scenarios/units.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/simulated_scan.hpp"

namespace floorcast {

/// Where finished units (and sampled heatmap images) go.
class UnitSink {
 public:
  virtual ~UnitSink() = default;
  virtual bool has_unit(const WorkUnit& unit) const = 0;
  /// Called from worker threads, one call at a time (the runner serialises them).
  virtual void write_unit(const UnitResult& result) = 0;
  virtual void write_image(const std::string& relative_path, const cv::Mat& image) = 0;
  /// Other files that go with the images (a heatmap's posterior as .npy and its grid as .json);
  /// ignored unless the sink keeps them.
  virtual void write_file(const std::string& relative_path, const std::string& bytes) {
    (void)relative_path;
    (void)bytes;
  }
};

struct RunProgress {
  std::size_t finished = 0;  ///< units executed so far in this invocation
  std::size_t to_run = 0;    ///< units this invocation executes
  std::size_t skipped = 0;   ///< units already present (resumed)
  double elapsed_s = 0.0;
};

struct RunOptions {
  int jobs = 0;  ///< concurrent units; 0 = all cores
  ShardSpec shard;
  /// Called after every finished unit (serialised).
  std::function<void(const RunProgress&)> on_progress;
};

struct RunOutcome {
  std::size_t units_total = 0;     ///< in the whole scenario
  std::size_t units_in_shard = 0;
  std::size_t skipped = 0;
  std::size_t executed = 0;
  double wall_s = 0.0;
  double reference_s = 0.0;        ///< reference workload measured at the start of this run
};

/// Where a unit's scan at `step` lies in a folder laid out as `floorcast export` writes scans (and
/// where observation.depth_dir's depth maps for it are read): "<cell>/<building>/scans/pNNNN",
/// at later walk steps "<cell>/<building>/scans/pNNNN/step_SSSS".
std::string unit_scan_folder(const Scenario& scenario, const WorkUnit& unit, int step = 0);

class ScenarioRunner {
 public:
  /// Loads or generates every building, samples the observation points, builds every matcher
  /// configuration (per building) and resolves every parameter. `log` receives one line per
  /// preparation step (optional). Throws InputError on bad matcher/sensor/observation parameters.
  explicit ScenarioRunner(const Scenario& scenario, const std::function<void(const std::string&)>& log = {});
  ~ScenarioRunner();

  /// The scenario's resolved configuration plus, per cell, every matcher's, sensor's and
  /// observation module's resolved parameters (the defaults of the code that runs).
  const nlohmann::ordered_json& resolved_full() const;

  /// Runs the units of options.shard that the sink does not have yet.
  RunOutcome run(UnitSink& sink, const RunOptions& options) const;

  /// One unit (exposed for tests). Heatmaps for sampled points go to `images` when given.
  UnitResult run_unit(const WorkUnit& unit, UnitSink* images) const;

  /// The simulated scan a unit observes at `step` (0 = its single-shot observation; later steps
  /// along its walk, at the walk's true pose), exactly as run_unit makes it (same seed). Throws
  /// InputError for a cell with perfect observations or a step its walk does not have.
  SimulatedScan unit_scan(const WorkUnit& unit, int step = 0) const;
  /// The steps a unit observes at: {0} for single-shot cells, the walk's schedule (0 first) for
  /// sequential ones.
  std::vector<int> unit_observation_steps(const WorkUnit& unit) const;
  /// Building b as the runner uses it: its plan (loaded or generated), its observation points and
  /// its 3D mesh (only when some cell simulates scans; null otherwise).
  const FloorPlan& building_plan(int b) const;
  const std::vector<Pose2>& building_points(int b) const;
  /// Where building b's points were drawn: its resolved sampling region, or for
  /// transitional_or_uniform "transitional" or "uniform (fallback: <why transitional failed>)".
  const std::string& building_sampling_region(int b) const;
  /// What building b's points cover (points per room kind, distinct 2 m cells, warnings).
  const SamplingCoverage& building_sampling_coverage(int b) const;
  const Mesh* building_mesh(int b) const;

 private:
  /// Sequential scenarios: the walk from the unit's start, its odometry and observations, every
  /// tracker (results into r.walk and r.tracks). `observe` makes the observation at a step's true
  /// pose (nullopt when it fails).
  void run_sequential(const WorkUnit& unit, UnitResult& r,
                      const std::function<std::optional<Observation2D>(const Pose2&, int)>& observe) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace floorcast
