#include "floorcast/scenarios/walk_tracking.hpp"

#include <filesystem>
#include <map>
#include <cmath>
#include <optional>

#include "floorcast/core/observation_io.hpp"
#include "floorcast/core/scan_io.hpp"
#include "floorcast/eval/metrics.hpp"
#include "floorcast/scenarios/track_scoring.hpp"

namespace floorcast {

namespace fs = std::filesystem;

std::string walk_depth_folder(const std::string& depth_dir, const WalkObservation& observation) {
  const fs::path mirrored = fs::path(depth_dir) / observation.path;
  const fs::path flat = fs::path(depth_dir) / fs::path(observation.path).filename();
  std::error_code ec;
  const bool has_mirrored = fs::is_directory(mirrored, ec);
  const bool has_flat = mirrored != flat && fs::is_directory(flat, ec);
  if (has_mirrored && has_flat) {
    throw InputError(depth_dir + ": both " + mirrored.string() + " and " + flat.string() +
                     " hold depth maps for the observation at step " + std::to_string(observation.step) + ": keep one");
  }
  if (!has_mirrored && !has_flat) {
    throw InputError(depth_dir + ": no depth maps for the observation at step " + std::to_string(observation.step) +
                     " (looked for the folders " + mirrored.string() + " and " + flat.string() + ")");
  }
  return (has_mirrored ? mirrored : flat).string();
}

WalkTrack track_walk_folder(const std::string& walk_dir, const WalkRecord& walk, const Matcher& matcher, Tracker& tracker,
                            const WalkTrackingOptions& options) {
  if (walk.observations.empty()) throw InputError(walk_dir + ": the walk has no observation to start from");
  std::map<int, const WalkObservation*> by_step;
  for (const WalkObservation& w : walk.observations) by_step[w.step] = &w;
  WalkTrack out;
  if (!options.depth_dir.empty()) {
    // Every folder is found before any work: a missing one is refused now, not after minutes.
    for (const auto& [step, w] : by_step) {
      if (w->kind != "scan") {
        throw InputError(walk_dir + ": the observation at step " + std::to_string(step) + " is a " + w->kind +
                         " observation; depth maps made elsewhere replace the depth of scans (simulate the walk "
                         "with a sensor preset, e.g. `sim walk --sensor mono --rgb`)");
      }
      out.depth_folders[step] = walk_depth_folder(options.depth_dir, *w);
    }
  }

  auto observe = [&](const WalkObservation& w) -> std::optional<Observation2D> {
    const std::string path = walk_dir + "/" + w.path;
    if (w.kind == "perfect") return load_observation(path + "/observation.json").observation;
    ScanLoadOptions lo;
    lo.require_depth = options.depth_dir.empty();
    Scan scan = load_scan(path, lo);
    ObservationParams params;
    if (options.observation_params) {
      params = options.observation_params(scan);
    } else if (scan.sensor == "lidar") {
      params.path = ObservationPath::kLidar;  // the default path follows the scan's sensor
    }
    if (!options.depth_dir.empty()) {
      const std::string folder = out.depth_folders.at(w.step);
      const DepthDirectoryReport report = load_depth_directory(scan, folder, options.depth_file);
      for (const std::string& r : report.repairs) out.notes.push_back("step " + std::to_string(w.step) + ": " + r);
      scan.sensor += (scan.sensor.empty() ? "" : ", ") + std::string("depth from ") + folder;
    }
    const ObservationResult r = observe_scan(scan, params);
    if (r.observation.segments_m.empty()) {
      // As in scenario runs: an observation without walls is no update.
      out.notes.push_back("step " + std::to_string(w.step) + ": no wall observed (" +
                          (r.diagnostics.warnings.empty() ? std::string("no segments") : r.diagnostics.warnings.front()) +
                          "); no update");
      return std::nullopt;
    }
    return r.observation;
  };

  out.first_step = by_step.begin()->first;
  std::size_t done = 0;
  out.run = run_tracker(tracker, walk.odometry.steps, out.first_step, [&](int step) -> std::optional<PosteriorQuery> {
    auto it = by_step.find(step);
    if (it == by_step.end()) return std::nullopt;
    const std::optional<Observation2D> observation = observe(*it->second);
    std::optional<PosteriorQuery> post;
    if (observation) {
      post = matcher.query(*observation);
      ++out.observations_used;
    }
    ++done;
    if (options.progress) options.progress(done, by_step.size());
    return post;
  });
  if (!out.run.started) return out;
  out.record = track_record(out.run, walk.walk.steps, out.first_step);
  out.outcome = score_track(out.record, options.scoring);
  return out;
}

nlohmann::ordered_json walk_track_metrics(const WalkTrack& track, const SequentialScoring& scoring, const Tracker& tracker) {
  auto num = [](double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr); };
  const SequentialOutcome& out = track.outcome;
  nlohmann::ordered_json m;
  m["steps"] = track.run.steps.size();
  m["observations_used"] = track.observations_used;
  m["rmse_m"] = num(out.rmse_m);
  m["rmse_last_m"] = num(out.rmse_last_m);
  m["end_error_m"] = num(out.end_error_m);
  for (std::size_t k = 0; k < scoring.success_thresholds_m.size() && k < out.success.size(); ++k) {
    m["success_" + threshold_name(scoring.success_thresholds_m[k])] = static_cast<bool>(out.success[k]);
  }
  m["converged"] = out.converged;
  m["converged_means"] = describe_convergence(tracker.name(), tracker.parameters());
  m["convergence_time_s"] = num(out.convergence_time_s);
  m["convergence_distance_m"] = num(out.convergence_distance_m);
  m["stage1_time_s"] = num(out.stage1_time_s);
  m["stage1_distance_m"] = num(out.stage1_distance_m);
  m["within_1m_after_convergence"] = num(out.within_after_convergence);
  m["time_per_step_s"] = track.record.time_per_step_s;
  m["init_s"] = track.run.init_s;
  return m;
}

}  // namespace floorcast
