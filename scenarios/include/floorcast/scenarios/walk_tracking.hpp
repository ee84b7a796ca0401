// Sequential localization of a walk folder (sim/walk_io.hpp: `floorcast sim walk`, or a recording
// in the same layout): the first observation's posterior starts the tracker, the odometry moves
// it, later observations update it; scan observations go through the observation module, with
// their own depth or with depth maps made elsewhere (a depth network run on the colour views).
// `floorcast track` and Python's floorcast.track are fronts on track_walk_folder.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "floorcast/core/depth_io.hpp"
#include "floorcast/eval/sequential.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/observe/observation_module.hpp"
#include "floorcast/sim/walk_io.hpp"
#include "floorcast/track/run.hpp"
#include "floorcast/track/tracker.hpp"

namespace floorcast {

struct WalkTrackingOptions {
  /// The observation module's parameters for a scan observation (called per scan: a front may
  /// pick the path from the scan's sensor). Unset: ObservationParams{} with the path lidar for
  /// LiDAR scans.
  std::function<ObservationParams(const Scan&)> observation_params;
  /// Bring your own depth: a folder holding, for every scan observation of the walk, a folder of
  /// depth maps named as `floorcast observe --depth-dir` reads them (core/depth_io.hpp
  /// load_depth_directory). The folder of the observation at walk path "observations/step_NNNN" is
  /// DEPTH_DIR/observations/step_NNNN (the walk folder's layout mirrored) or DEPTH_DIR/step_NNNN.
  /// Empty: the scans' own depth.
  std::string depth_dir;
  DepthFileOptions depth_file;
  SequentialScoring scoring;
  /// Called after every observation used (observations done, observations in all).
  std::function<void(std::size_t done, std::size_t total)> progress;
};

struct WalkTrack {
  int first_step = 0;           ///< the step the tracker started at (the walk's first observation)
  int observations_used = 0;    ///< observations whose posteriors were applied (the first included)
  TrackRun run;
  SequentialRecord record;      ///< per step from first_step: errors against the walk's truth
  SequentialOutcome outcome;    ///< RMSE, success, convergence (options.scoring)
  /// What was repaired in depth maps made elsewhere, and observations that gave no wall
  /// (their step is no update), one sentence each.
  std::vector<std::string> notes;
  /// The depth folder used per observation step (with depth_dir).
  std::map<int, std::string> depth_folders;
};

/// The folder of depth maps for the observation at `observation.path` under `depth_dir` (see
/// WalkTrackingOptions::depth_dir). Throws InputError naming both candidates when neither or
/// both exist.
std::string walk_depth_folder(const std::string& depth_dir, const WalkObservation& observation);

/// Tracks the walk in `walk_dir` (read as `walk`) with `tracker`, posteriors from `matcher`.
/// Throws InputError for a walk without observations, depth_dir with perfect observations, or
/// depth maps that cannot be used (load_depth_directory's refusals, naming the file); a method
/// from outside floorcast that misbehaves throws ExternalMethodError. A tracker that cannot start
/// is a reported state (run.started false, run.failure).
WalkTrack track_walk_folder(const std::string& walk_dir, const WalkRecord& walk, const Matcher& matcher, Tracker& tracker,
                            const WalkTrackingOptions& options = {});

/// The track's metrics as `floorcast track` writes them into metrics.json (steps,
/// observations_used, rmse_m, rmse_last_m, end_error_m, success_<t>m per threshold, converged,
/// converged_means (what convergence means for `tracker`), convergence and stage-1 time and distance, within_1m_after_convergence, time_per_step_s,
/// init_s; undefined values null).
nlohmann::ordered_json walk_track_metrics(const WalkTrack& track, const SequentialScoring& scoring, const Tracker& tracker);

}  // namespace floorcast
