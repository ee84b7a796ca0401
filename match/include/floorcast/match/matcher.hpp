// The matcher interface: every layout matcher turns an observation into a Posterior over the
// plan, and is built by name so scenarios, benches and tests iterate over all of them.
#pragma once

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "floorcast/core/observation.hpp"
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
  /// Posterior for one observation (observer frame segments and/or rays). Thread-safe; uses
  /// TBB internally.
  virtual MatchResult match(const Observation2D& observation) const = 0;
};

/// Builds a matcher for a plan. `overrides` is a JSON object of parameter overrides (keys as in
/// parameters()); unknown keys or bad values throw InputError naming the matcher and key.
/// Unknown names throw InputError listing the known ones.
std::unique_ptr<Matcher> make_matcher(const std::string& name, const FloorPlan& plan,
                                      const nlohmann::json& overrides = nlohmann::json::object());

/// Names of all registered matchers, sorted ("kernel", "ray").
std::vector<std::string> matcher_names();

/// A matcher under a label: a registered name plus overrides (e.g. "ray180" = ray with 180
/// directions), so comparisons can run several configurations of one matcher.
struct MatcherSpec {
  std::string label;
  std::string name;
  nlohmann::json overrides = nlohmann::json::object();
};

}  // namespace floorcast
