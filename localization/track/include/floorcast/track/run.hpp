// Driving a tracker over a stream: the loop every front end (the `track` command, scenarios,
// benches) shares.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "floorcast/track/tracker.hpp"

namespace floorcast {

struct TrackRunStep {
  int step = 0;            ///< index into the odometry stream
  double t_s = 0.0;
  TrackEstimate estimate;
  bool updated = false;    ///< an observation's posterior was applied at this step
  double time_s = 0.0;     ///< tracker wall time of this step (predict + update + estimate)
};

struct TrackRun {
  /// false when the tracker could not start (e.g. an empty initial posterior); `failure` says why.
  bool started = false;
  std::string failure;
  double init_s = 0.0;
  std::vector<TrackRunStep> steps;  ///< from first_step (the initialisation) to the end
};

/// Initialises `tracker` with the (full) posterior of `first_step` (which must exist), then
/// predicts through odometry[first_step + 1 ..] and updates wherever `posterior_at(step)` returns
/// one (a point-query posterior: Matcher::query; the tracker asks it for what it needs).
/// `posterior_at` is called once per step, in order (callers compute posteriors lazily).
TrackRun run_tracker(Tracker& tracker, const std::vector<OdometryStep>& odometry, int first_step,
                     const std::function<std::optional<PosteriorQuery>(int step)>& posterior_at);

}  // namespace floorcast
