// Matchers from outside floorcast's code, scored by the same engine as the built-in ones:
//
//   - registered at run time under a name (register_matcher: the Python API's
//     floorcast.register_matcher, tests);
//   - a shared module floorcast_matcher_<name>.so (C++, match/matcher_module.hpp), found like the
//     PCL and GL modules (core/module.hpp) the first time a scenario or command names <name>;
//   - an external program in any language, the built-in matcher "external" (file protocol below).
//
// Whatever they return is checked here (shapes, finite non-negative scores) and turned into the
// MatchResult every caller expects; a method that misbehaves (raises, crashes, hangs, returns a
// malformed result) throws ExternalMethodError, which the scenario runner reports for the unit it
// happened on while the run goes on.
//
// External program protocol ("floorcast-matcher/1"). For every observation floorcast creates a
// fresh folder and runs `COMMAND... REQUEST` where REQUEST is the path of request.json:
//   {"protocol": "floorcast-matcher/1",
//    "plan": "/abs/plan.json",                 // floorcast plan JSON (written once per plan)
//    "observation": "/abs/observation.json",   // floorcast-observation JSON (core/observation_io.hpp),
//                                              //   observer frame, no ground truth
//    "output_dir": "/abs/out",                 // exists and is empty; write the answer here
//    "grid": {"origin_x_m", "origin_y_m", "resolution_m", "width_px", "height_px",
//             "yaw_deg": [...]},              // the shared grid (cell (r, c) centre at
//                                              //   origin + (c + 0.5, r + 0.5) * resolution)
//    "top_k": 5,                               // modes floorcast will score
//    "params": {...}}                          // the scenario's `params` for the program, verbatim
// and reads from output_dir either
//   posterior.npy  float32/float64 (yaw, y, x) scores >= 0 (higher = better), on the shared grid
//                  or on the grid described by an optional grid.json (same keys as "grid"), or
//   top_k.json     {"poses": [{"x_m", "y_m", "yaw_deg", "score"}, ...]} (world frame, best first;
//                  an empty list = no pose).
// A non-zero exit, a signal, exceeding timeout_s, no answer, or a malformed answer is an
// ExternalMethodError quoting the program's last lines of standard error.
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "floorcast/core/fields.hpp"
#include "floorcast/match/matcher.hpp"

namespace floorcast {

/// A method outside floorcast's code misbehaved: reported for the work unit it happened on.
class ExternalMethodError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The grid external methods return posteriors on unless they describe their own:
/// grid_for_plan(plan, resolution_m, margin_m) and yaw_bins orientations yaw_k = 2 pi k / yaw_bins.
struct PosteriorGrid {
  GridSpec grid;
  std::vector<double> yaw_rad;
};
PosteriorGrid shared_posterior_grid(const FloorPlan& plan, double resolution_m = 0.1, int yaw_bins = 36,
                                    double margin_m = 1.0);

/// The grid as the protocol writes it (origin_x_m, origin_y_m, resolution_m, width_px, height_px,
/// yaw_deg): request.json "grid", an answer's grid.json, the grid Python's prepare() gets.
const FieldList<PosteriorGrid>& posterior_grid_fields();
nlohmann::ordered_json posterior_grid_to_json(const PosteriorGrid& grid);
/// Every key required, none unknown; throws ParameterError (an InputError) naming `source` and the key.
PosteriorGrid posterior_grid_from_json(const nlohmann::json& json, const std::string& source);

/// How an external method's shared grid is made (the keys every external method takes besides
/// its own: the external program matcher, Python-registered matchers).
struct PosteriorGridParams {
  double resolution_m = 0.1;   ///< cell size, m
  int yaw_bins = 36;           ///< orientations 2 pi k / yaw_bins
  double grid_margin_m = 1.0;  ///< free margin around the plan, m
  static const FieldList<PosteriorGridParams>& fields();
  PosteriorGrid make(const FloorPlan& plan) const { return shared_posterior_grid(plan, resolution_m, yaw_bins, grid_margin_m); }
};

/// What an external method returned: a posterior on `grid`, or poses.
struct ExternalMatchOutput {
  bool has_posterior = false;
  PosteriorGrid grid;                 ///< the posterior's grid
  std::vector<cv::Mat> scores;        ///< one CV_32F (height x width) map per yaw of `grid`
  std::vector<PoseHypothesis> poses;  ///< when !has_posterior (sorted by descending score here)
};

/// Checks an output (a map per yaw of the grid's size; finite, >= 0 scores; finite poses with
/// scores > 0) and makes the MatchResult `request` asks for. The best request.top_k poses become
/// the modes; a posterior asked of a poses-only output holds every pose's score in its cell of
/// `grid` (the nearest yaw slice) and 0 elsewhere. Throws ExternalMethodError naming `who`.
MatchResult finish_external_output(ExternalMatchOutput output, const PosteriorGrid& grid, const MatchRequest& request,
                                   const std::string& who);

/// Parses a matcher configuration from overrides and the experiment's shared quantities.
using MatcherConfigParser =
    std::function<std::shared_ptr<const MatcherConfig>(const nlohmann::json& overrides, const SharedParams& shared)>;

/// Makes `name` a matcher for make_matcher_config (and so for scenarios and commands) in this
/// process, replacing an earlier registration of that name. Throws InputError for the name of a
/// built-in matcher or a name that is not [A-Za-z0-9_-]+.
void register_matcher(const std::string& name, MatcherConfigParser parser);
/// Removes a run-time registration; false when there was none.
bool unregister_matcher(const std::string& name);
/// Names registered at run time (sorted).
std::vector<std::string> registered_matcher_names();

/// The run-time registry, then the module floorcast_matcher_<name>: the parser of `name`, or
/// null when neither knows it (`tried` then says where the module was looked for).
MatcherConfigParser find_external_matcher(const std::string& name, std::string* tried = nullptr);

/// The external program matcher's parameters (registry name "external").
struct ExternalProgramParams {
  /// The program and its first arguments; the request file's path is appended. Run as given
  /// (relative paths from the current directory; a bare name is searched on PATH).
  std::vector<std::string> command;
  /// Seconds per observation before the program (and its process group) is killed.
  double timeout_s = 60.0;
  /// The shared grid (shared_posterior_grid) sent to the program.
  PosteriorGridParams grid;
  /// What blocks in the map, for drawing its posteriors over the plan (the program decides how
  /// it uses the plan itself).
  BlockingOptions blocking = closed_door_map();
  /// Passed to the program verbatim (request.json "params").
  nlohmann::json program_params = nlohmann::json::object();
  /// Part of the configuration hash, as in Python's register_matcher: change it when the program
  /// changes what it answers, so a resumed run never mixes two versions' results. (The hash
  /// counts the program's files by name, never where they lie: scenarios/scenario.hpp
  /// scenario_hash; a fixed crash needs no new version, its units run again on resume.)
  std::string version = "1";

  static const FieldList<ExternalProgramParams>& fields();
  void apply_shared(const SharedParams& shared);
  void apply_overrides(const nlohmann::json& overrides);
  nlohmann::ordered_json to_json() const;
};

class ExternalProgramMatcher final : public Matcher {
 public:
  /// Writes the plan once into a private temporary folder (removed with the matcher).
  ExternalProgramMatcher(const FloorPlan& plan, ExternalProgramParams params);
  ~ExternalProgramMatcher() override;
  std::string name() const override { return "external"; }
  nlohmann::ordered_json parameters() const override { return params_.to_json(); }
  double precompute_s() const override { return precompute_s_; }
  std::size_t precompute_bytes() const override { return 0; }
  BlockingOptions blocking() const override { return params_.blocking; }
  /// Runs the program once; throws ExternalMethodError when it misbehaves.
  MatchResult match(const Observation2D& observation, const MatchRequest& request) const override;
  using Matcher::match;

 private:
  ExternalProgramParams params_;
  PosteriorGrid grid_;
  std::string folder_;
  double precompute_s_ = 0.0;
};

}  // namespace floorcast
