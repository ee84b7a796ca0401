// Sequential localization: a tracker starts from a matcher posterior (the initial scan: PALMS'
// "scan, then walk"), follows the odometry, optionally takes further posteriors as observations
// arrive, and reports an estimate after every step.
//
//   auto config = make_tracker_config("pf", overrides);   // or "hist"; checked before any work
//   auto t = config->build(plan);
//   t->initialise(posterior_of_first_scan, odometry.steps[0]);
//   for (k = 1 ..) { t->predict(odometry.steps[k]); if (observation at k) t->update(posterior_k);
//                    TrackEstimate e = t->estimate(); }
//
// Trackers depend on the plan (walls, valid area) and on posteriors (match/), never on the
// simulator: real odometry and real scans run through them unchanged.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "floorcast/core/fields.hpp"
#include "floorcast/core/odometry.hpp"
#include "floorcast/floorplans/floor_plan.hpp"
#include "floorcast/match/posterior.hpp"
#include "floorcast/match/posterior_query.hpp"

namespace floorcast {

/// Where a tracker's motion noise per odometry increment comes from.
enum class MotionNoiseSource {
  /// From the odometry's stated error (the tracker's `odometry` parameters, an
  /// OdometryUncertainty: per metre, radian, second and step), so a filter diffuses as much as
  /// its odometry drifts. Scenarios and `floorcast track` fill it from the walk's odometry.
  kOdometry,
  /// The same sigmas every increment, whatever the odometry (the papers' constants: F3Loc 0.1 m
  /// and 0.1 rad per frame, PALMS 0.356 m, 0.05 rad and 0.015 rad per step).
  kFixed,
};

const std::vector<std::pair<const char*, MotionNoiseSource>>& motion_noise_names();

struct TrackEstimate {
  Pose2 pose;            ///< world position and heading
  /// Convergence stage: 0 = spread out, 1 = one orientation hypothesis dominates (particle filter
  /// stage 1), 2 = converged (the estimate is a well-supported mode). Each tracker defines it
  /// (describe_convergence): PALMS' two stages for the particle filter, the belief mass near the
  /// estimate for the histogram filter.
  int stage = 0;
  /// Share of the belief supporting the estimate (particle filter: the dominant cluster's share of
  /// all particles; histogram filter: belief mass within 1 m and 30 deg of the mode).
  double support = 0.0;
  /// True when the last update found no support at all (every hypothesis zeroed): the tracker
  /// kept its prior instead and says so, never inventing a pose.
  bool degenerate = false;
  /// The belief's best peaks, best first, when the tracker was asked for them (histogram filter:
  /// `modes` > 0; the thesis' top-K over frames, Fig. 5.7); empty otherwise.
  std::vector<Pose2> modes;
};

class Tracker {
 public:
  virtual ~Tracker() = default;
  /// Registry name ("pf", "hist").
  virtual std::string name() const = 0;
  /// Every parameter with its value.
  virtual nlohmann::ordered_json parameters() const = 0;
  /// Starts from a posterior over (x, y, yaw) (initialisation modes that ignore it, such as the
  /// uniform baselines, still take its orientation slices where they need candidates). `first` is
  /// the odometry sample at the posterior's time (its motion is ignored).
  virtual void initialise(const Posterior& posterior, const OdometryStep& first) = 0;
  /// Moves the belief by one odometry increment.
  virtual void predict(const OdometryStep& step) = 0;
  /// Weighs the belief with the posterior of an observation made at the current step, asking it
  /// only for the cells the belief needs (point queries) or for the full posterior
  /// (PosteriorQuery::full), as the tracker sees fit: same results either way where the matcher's
  /// point queries are exact.
  virtual void update(const PosteriorQuery& posterior) = 0;
  /// update() with a full posterior at hand.
  void update(const Posterior& posterior) { update(PosteriorQuery(posterior)); }
  virtual TrackEstimate estimate() const = 0;
  /// Memory held by the tracker's state and precomputation, bytes.
  virtual std::size_t state_bytes() const = 0;
};

/// A tracker's parameters, parsed, validated and complete (every default filled in), before any
/// plan is involved (like MatcherConfig): what scenarios and commands build when they load their
/// input, so that a misspelt or out-of-range parameter fails there, and what they write next to
/// results.
class TrackerConfig {
 public:
  virtual ~TrackerConfig() = default;
  /// Registry name ("pf", "hist").
  virtual std::string name() const = 0;
  /// Every parameter with its value (keys as the overrides take them).
  virtual nlohmann::ordered_json parameters() const = 0;
  /// The seed of a tracker that draws random numbers; nullopt for deterministic ones.
  virtual std::optional<std::uint64_t> seed() const = 0;
  /// The same configuration with another seed (a tracker without a seed: unchanged): the
  /// scenario runner gives every work unit its own stream.
  virtual std::shared_ptr<const TrackerConfig> with_seed(std::uint64_t seed) const = 0;
  /// Builds the tracker for a plan.
  virtual std::unique_ptr<Tracker> build(const FloorPlan& plan) const = 0;
};

/// Parses a tracker configuration by name ("pf": PALMS particle filter, "hist": F3Loc histogram
/// filter): the defaults, then `overrides` (a JSON object with keys of parameters()). Throws
/// ParameterError naming the key for bad parameters, InputError listing the known names for
/// unknown trackers.
std::shared_ptr<const TrackerConfig> make_tracker_config(const std::string& name,
                                                         const nlohmann::json& overrides = nlohmann::json::object());

/// make_tracker_config(name, overrides)->build(plan).
std::unique_ptr<Tracker> make_tracker(const std::string& name, const FloorPlan& plan,
                                      const nlohmann::json& overrides = nlohmann::json::object());

/// Every parameter of tracker `name` with its default, key, type, range and meaning (from its
/// field list): `floorcast params` and docs/parameters.md.
std::vector<FieldInfo> tracker_parameter_fields(const std::string& name);

/// What "converged" (TrackEstimate::stage 2) means for tracker `name` with these parameters, in
/// words for reports: PALMS' two stages for the particle filter, the mass near the estimate for
/// the histogram filter. Throws like make_tracker.
std::string describe_convergence(const std::string& name, const nlohmann::json& overrides = nlohmann::json::object());

/// Tracker overrides with a walk's stated odometry error as their `odometry` section, the
/// overrides' own `odometry` keys on top (how scenarios and `floorcast track` hand a walk's
/// odometry to a tracker). A non-object `odometry` is left for make_tracker to refuse.
nlohmann::json with_odometry(const nlohmann::json& overrides, const OdometryUncertainty& odometry);

/// Names of all registered trackers, sorted.
std::vector<std::string> tracker_names();

/// The matcher a tracker is paired with where none is named (its paper's: kernel for pf, ray for
/// the histogram filters). Throws InputError for an unknown tracker.
std::string default_tracker_matcher(const std::string& name);

}  // namespace floorcast
