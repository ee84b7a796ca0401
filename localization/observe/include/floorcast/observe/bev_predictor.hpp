// A simulated BEV predictor: stands in for the thesis' network (seed paper 004, sec. 3.3) the way
// the monocular depth model stands in for a depth network. From each view's column semantics
// (DepthView::column_semantics: what the horizontal ray of every image column meets, the truth a
// network is trained on) it makes the BEV the network would output: per column and log-spaced
// depth bin a distribution over wall, window, door and empty (and the 2-class occupancy BEV of the
// no-semantics model from the same draws), through a parameterised error model:
//
// - per element (a run of neighbouring columns meeting one class at a continuous range), class
//   confusion: a window predicted as a wall (which stops the ray), a wall predicted as a window
//   (a painting, Fig. 5.2), a door missed, a closed door leaf predicted as a wall (the camera sees
//   a surface, the thesis' plan rays pass it), furniture predicted as a wall at its range
//   (Fig. 5.2's wardrobe) instead of being masked;
// - depth: each element's predicted range is its true range times a per-view scale error and a
//   per-element offset (log-normal), spread over the bins as a log-normal whose sigma grows with
//   range (the balanced cross-entropy's soft distributions, sec. 3.3.5 and 5.1);
// - occlusion: what lies behind masked furniture or a passed closed door is not seen: a share
//   occluded_spread of its mass is spread evenly over the bins beyond the occluder (Fig. 5.4's
//   "likelihood behind closed doors");
// - confidence: each element's class holds peak_mass over its bins (the rest stays empty), and
//   floor_mass of every (column, bin) is spread evenly over all classes (Fig. 5.4's diffuse
//   predictions).
//
// Presets are named after the thesis' good and bad examples (Figs. 5.1-5.4); their values are
// assumptions read off those qualitative figures (the thesis publishes no error statistics),
// meant to be swept. "perfect" is the upper bound: the one-hot rendering of the truth, which at
// the true pose equals the plan's own (render_bev_column).
//
// A view with a BEV of its own (DepthView::bev: a network's output brought as a .npy) replaces
// the prediction for that view. Deterministic: every draw is a CounterRng stream of the seed and
// a hash of the annotation (the same scan gives the same BEV at any thread count).
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "floorcast/core/bev.hpp"
#include "floorcast/core/scan.hpp"

namespace floorcast {

/// The error model (values of the default preset, structured3d_good).
struct BevErrorModel {
  double depth_sigma_ln = 0.05;         ///< spread of a predicted range (log sigma) at 0 m
  double depth_sigma_ln_per_m = 0.01;   ///< ... growing by this per metre of range
  double view_scale_sigma_ln = 0.05;    ///< per view: every range times exp(N(0, s^2))
  double element_offset_sigma_ln = 0.03;  ///< per element: its range times exp(N(0, s^2))
  double window_as_wall = 0.05;         ///< P(a window is predicted as a wall and stops the ray)
  double wall_as_window = 0.01;         ///< P(a wall is predicted as a window)
  double door_missed = 0.1;             ///< P(a door is not predicted)
  double closed_door_as_wall = 0.3;     ///< P(a closed door leaf is predicted as a wall)
  double furniture_as_wall = 0.1;       ///< P(furniture at camera height is predicted as a wall)
  double occluded_spread = 0.7;         ///< share of an unseen element's mass spread beyond its occluder
  double peak_mass = 0.9;               ///< class mass of an element over its bins
  double floor_mass = 0.02;             ///< mass of every (column, bin) spread over all classes
};

/// Preset names: "perfect", "structured3d_good" (default), "structured3d_bad", "custom_good",
/// "custom_bad" (the thesis' Figs. 5.1-5.4).
const std::vector<std::string>& bev_predictor_presets();
/// Throws InputError for an unknown name.
BevErrorModel bev_error_preset(const std::string& name);

struct BevPredictorParams {
  /// Make the BEVs (the observation's `bev`): from each view's own BEV file, else from its column
  /// semantics; views with neither are skipped (a warning).
  bool enabled = false;
  /// Name of the preset the error model was set from (other keys of the same overrides then
  /// change single values of it; every value is written beside results).
  std::string preset = "structured3d_good";
  BevErrorModel error;
  /// Log-spaced depth bins (the BEV matcher's must be the same): min .. max (the range).
  int depth_bins = 32;
  double min_depth_m = 0.3;
  double max_depth_m = 10.0;
  /// Columns every this many degrees of observer-frame azimuth, each taken from the kept view
  /// whose heading is nearest among the views that see it (a perspective view: its field of
  /// view; a rotating scan: the full circle). The BEV matcher renders along 5 deg directions by
  /// default.
  double column_step_deg = 5.0;
  std::uint64_t seed = 1;

  BevDepthBins bins() const { return {depth_bins, min_depth_m, max_depth_m}; }
};

struct BevPredictionResult {
  /// The semantic and the occupancy BEV (empty when no view could give one).
  std::vector<BevPrediction> bev;
  std::vector<int> views_used;           ///< views that gave columns
  std::vector<int> views_brought;        ///< ... of them with a BEV of their own
  int columns = 0;
  /// Draw counts of the error model, for diagnostics ("window_as_wall", "door_missed", ...).
  std::map<std::string, int> events;
  std::vector<std::string> warnings;
};

/// The BEVs of a scan (observer frame = scan frame).
BevPredictionResult predict_bev(const Scan& scan, const BevPredictorParams& params);

/// One column's predicted distributions (D x C, row-major by bin) from its truth hits, with the
/// element draws given (the building block; exposed for tests). `rng_key` seeds this column's
/// element decisions when `elements` is empty.
struct BevColumnElement {
  SemanticClass truth = SemanticClass::kWall;
  double range_m = 0.0;
  /// Decisions (filled by predict_bev from the element's draws).
  bool as_wall = false;     ///< window, closed door or furniture predicted as a wall
  bool as_window = false;   ///< wall predicted as a window
  bool missed = false;      ///< door not predicted
  double range_factor = 1.0;  ///< exp(view scale + element offset)
};
/// Distributions of one column (D x C floats, (d * C + c)) for `classes` from its elements, the
/// model's spreads and masses.
std::vector<float> predict_bev_column(const std::vector<BevColumnElement>& elements, BevClasses classes,
                                      const BevDepthBins& bins, const BevErrorModel& model);

}  // namespace floorcast
