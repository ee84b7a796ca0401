// The matcher interface: every layout matcher turns an observation into a Posterior over the
// plan, and is built by name so scenarios, benches and tests iterate over all of them.
#pragma once

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "floorcast/core/blocking.hpp"
#include "floorcast/core/observation.hpp"
#include "floorcast/core/fields.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/floorplans/floor_plan.hpp"
#include "floorcast/match/posterior.hpp"
#include "floorcast/match/posterior_query.hpp"

namespace floorcast {

/// What a caller needs from a match. Matchers compute and keep only that: a full posterior is one
/// float map per orientation slice (campus: 5 MB each, 10-180 slices), while the estimate and the
/// top-K modes can be found without one (the kernel matcher's exact branch-and-bound search).
enum class MatchOutput {
  kModes,       ///< the estimate and the top-K modes only
  kMaxOverYaw,  ///< the modes and the max-over-yaw map (one slice: heatmaps)
  kPosterior,   ///< the modes and the full posterior (filter initialisation, analyses)
};

struct MatchRequest {
  MatchOutput output = MatchOutput::kPosterior;
  /// Modes to return (>= 1), found as Posterior::top_k(top_k, mode_separation_m,
  /// mode_separation_rad) of the full posterior would find them.
  int top_k = 1;
  double mode_separation_m = 1.0;
  double mode_separation_rad = 0.5235987755982988;  // 30 deg

  /// Only the estimate and top-K modes.
  static MatchRequest modes(int k = 1, double separation_m = 1.0, double separation_rad = 0.5235987755982988) {
    return {MatchOutput::kModes, k, separation_m, separation_rad};
  }
};

struct MatchResult {
  /// Greedy non-maximum-suppression modes in descending score order (Posterior::top_k of the
  /// full posterior, whatever was computed): modes[0] is the estimate (Posterior::argmax when its
  /// score is > 0). Empty = no pose (every score is 0, e.g. no observed wall fits anywhere).
  std::vector<PoseHypothesis> modes;
  /// The full posterior (MatchOutput::kPosterior only; otherwise it has no slices).
  Posterior posterior;
  /// Max over orientation, CV_32F on `grid` (kMaxOverYaw only; with kPosterior it is
  /// posterior.max_over_yaw()).
  cv::Mat max_over_yaw;
  /// The (x, y) grid of the scores (set for every output).
  GridSpec grid;
  /// Wall-clock seconds of this match() call, and where they went (named stages; stages run on
  /// several threads are summed over threads, i.e. CPU seconds).
  double match_s = 0.0;
  std::map<std::string, double> stage_s;
  /// Counters of the search (e.g. nodes expanded by the kernel's branch and bound), for benches.
  std::map<std::string, double> counters;

  bool has_pose() const { return !modes.empty(); }
  /// modes[0]; throws std::logic_error when there is no pose.
  const PoseHypothesis& estimate() const;
};

/// Fills result.modes from result.posterior (top_k) and, when asked for, result.max_over_yaw;
/// drops the posterior's slices unless the request wants them. For matchers that compute the
/// full posterior anyway.
void finish_from_posterior(MatchResult& result, const MatchRequest& request);

class Matcher {
 public:
  virtual ~Matcher() = default;
  /// Registry name ("kernel", "ray", ...).
  virtual std::string name() const = 0;
  /// Every parameter with its resolved value (defaults filled in), for writing next to results.
  virtual nlohmann::ordered_json parameters() const = 0;
  /// Seconds spent preparing the plan once (map transforms, distance volumes, ...).
  virtual double precompute_s() const = 0;
  /// Memory held by the per-plan precomputation, bytes.
  virtual std::size_t precompute_bytes() const = 0;
  /// What blocks in the map this matcher compares observations with (for drawing posteriors
  /// over the plan as the matcher sees it).
  virtual BlockingOptions blocking() const = 0;
  /// What `request` asks for, for one observation (observer frame segments and/or rays).
  /// Thread-safe; uses TBB internally.
  virtual MatchResult match(const Observation2D& observation, const MatchRequest& request) const = 0;
  /// The full posterior and the estimate (match(observation, MatchRequest{})).
  MatchResult match(const Observation2D& observation) const { return match(observation, MatchRequest{}); }
  /// The matcher itself under any wrapper the registry adds (the min_score abstention): what a
  /// caller casts to a matcher type to read its typed parameters.
  virtual const Matcher& unwrapped() const { return *this; }
  /// What a user should know about this matcher on this plan, decided when it was built (e.g. the
  /// plan lies outside an assumption of the method); one sentence each, empty by default. The
  /// scenario runner writes them to the run log.
  virtual std::vector<std::string> notes() const { return {}; }
  /// The posterior of one observation as point queries (posterior_query.hpp): its grid, slices
  /// and maximum, and the scores of match(observation).posterior at the cells a caller asks for,
  /// computed only there (kernel: direct correlation at each asked cell and scale, within the
  /// FFT posterior's round-off; ray: each asked cell's L1, bit for bit). This default computes the
  /// full posterior and looks cells up (bev, external and run-time registered matchers). The
  /// query refers to this matcher: it must not outlive it.
  virtual PosteriorQuery query(const Observation2D& observation) const;
};

/// A matcher's parameters, parsed, validated and complete (every default filled in), before any
/// plan is involved: what scenarios and commands build when they load their input, so that a
/// misspelt or out-of-range parameter fails there, and what they write next to results.
class MatcherConfig {
 public:
  virtual ~MatcherConfig() = default;
  /// Registry name ("kernel", "ray", ...).
  virtual std::string name() const = 0;
  /// Every parameter with its value (keys as the overrides take them).
  virtual nlohmann::ordered_json parameters() const = 0;
  /// Builds the matcher for a plan (the per-plan precomputation happens here).
  virtual std::unique_ptr<Matcher> build(const FloorPlan& plan) const = 0;
};

/// Parses a matcher configuration: the defaults, then the experiment's shared quantities (range,
/// blocking flags), then `overrides` (a JSON object with keys of parameters(); explicit overrides
/// win over shared values). Throws ParameterError naming the matcher and the key for unknown keys,
/// wrong types and out-of-range values; InputError listing the known names for unknown matchers.
std::shared_ptr<const MatcherConfig> make_matcher_config(const std::string& name,
                                                         const nlohmann::json& overrides = nlohmann::json::object(),
                                                         const SharedParams& shared = {});

/// make_matcher_config(name, overrides)->build(plan).
std::unique_ptr<Matcher> make_matcher(const std::string& name, const FloorPlan& plan,
                                      const nlohmann::json& overrides = nlohmann::json::object());

/// Every parameter of matcher `name` with its default (shared quantities at their defaults), key,
/// type, range and meaning (from its field list): `floorcast params` and docs/parameters.md. For a
/// built-in matcher only (one from outside floorcast: InputError).
std::vector<FieldInfo> matcher_parameter_fields(const std::string& name);

/// Names of all matchers known in this process, sorted: the built-in ones ("external", "kernel",
/// "ray") and those registered at run time (match/external.hpp; modules are found by name when
/// first named and are not listed).
std::vector<std::string> matcher_names();
/// The built-in matchers only.
std::vector<std::string> builtin_matcher_names();

/// A matcher configuration under a label (e.g. "ray180" = ray with 180 directions), so
/// comparisons can run several configurations of one matcher.
struct MatcherSpec {
  std::string label;
  std::shared_ptr<const MatcherConfig> config;
};

}  // namespace floorcast
