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
#include "floorcast/core/params.hpp"
#include "floorcast/floorplans/floor_plan.hpp"
#include "floorcast/match/posterior.hpp"

namespace floorcast {

struct MatchResult {
  Posterior posterior;
  /// Wall-clock seconds of this match() call, and where they went (named stages; stages run on
  /// several threads are summed over threads, i.e. CPU seconds).
  double match_s = 0.0;
  std::map<std::string, double> stage_s;
};

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
  /// Posterior for one observation (observer frame segments and/or rays). Thread-safe; uses
  /// TBB internally.
  virtual MatchResult match(const Observation2D& observation) const = 0;
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

/// Names of all registered matchers, sorted ("kernel", "ray").
std::vector<std::string> matcher_names();

/// A matcher configuration under a label (e.g. "ray180" = ray with 180 directions), so
/// comparisons can run several configurations of one matcher.
struct MatcherSpec {
  std::string label;
  std::shared_ptr<const MatcherConfig> config;
};

}  // namespace floorcast
