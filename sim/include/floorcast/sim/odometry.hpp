// Odometry models: what a phone reports about a simulated walk (sim/walk.hpp).
//
//   exact  the true relative motions;
//   vio    ARKit-like visual-inertial odometry: a per-walk scale error with a slow random walk, a
//          per-walk yaw-rate bias with a slow random walk, a small rotation-scale error and white
//          noise on every increment; it keeps reporting (small) motion while the user stands;
//          defaults give ~0.02 m of position drift per second of walking (sensors.md: "ARKit VIO:
//          ~0.02 m drift per second");
//   pdr    pedestrian dead reckoning: step detection (missed steps, false steps while standing),
//          step length with a per-walk bias and per-step noise, a heading with a per-walk bias and
//          a random walk; each detected step moves along the estimated heading.
//
// All noise comes from CounterRng streams of the odometry seed: same walk, same seed, same bytes.
#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "floorcast/core/fields.hpp"

#include "floorcast/core/odometry.hpp"
#include "floorcast/sim/walk.hpp"

namespace floorcast {

enum class OdometryModel { kExact, kVio, kPdr };

struct VioNoise {
  double scale_sigma = 0.01;                ///< per-walk scale error, relative (1%)
  double scale_random_walk_per_sqrt_s = 0.001;  ///< scale drift, relative per sqrt(second)
  double yaw_bias_sigma_dps = 0.03;         ///< per-walk yaw-rate bias, deg/s
  double yaw_random_walk_deg_per_sqrt_s = 0.05;  ///< heading random walk
  /// Relative error of measured rotations (8.6 deg after 3.5 turns: ~0.7%; sensors.md).
  double rotation_scale_sigma = 0.005;
  double translation_noise_mps = 0.02;      ///< white noise on each increment, per axis, m/s x dt
};

struct PdrNoise {
  double miss_probability = 0.02;           ///< a true step is not detected
  double false_step_probability = 0.01;     ///< a step is detected while standing
  double step_length_bias_sigma = 0.02;     ///< per-walk relative step-length bias
  double step_length_sigma_m = 0.05;        ///< per-step length noise
  double heading_bias_sigma_deg = 2.0;      ///< per-walk heading offset
  double heading_random_walk_deg_per_sqrt_step = 0.2;
};

struct OdometryParams {
  OdometryModel model = OdometryModel::kVio;
  VioNoise vio;
  PdrNoise pdr;
  std::uint64_t seed = 1;

  /// The field list (core/fields.hpp): keys, ranges, docs; to_json and apply_overrides use it.
  static const FieldList<OdometryParams>& fields();
  nlohmann::ordered_json to_json() const;
  /// Strict overrides (keys as in to_json); throws ParameterError naming the key.
  void apply_overrides(const nlohmann::json& overrides);
};

const std::vector<std::pair<const char*, OdometryModel>>& odometry_model_names();

struct OdometryTrack {
  /// One increment per walk sample (steps[0] is the identity at t = 0).
  std::vector<OdometryStep> steps;
  /// The increments chained from the walk's true start pose (the odometry frame coincides with
  /// the world at the start, as after evo's alignment of the first pose); trackers use only the
  /// increments.
  std::vector<Pose2> poses;
};

/// The error a tracker should assume for odometry of this model (what a walk folder states for its
/// odometry): exact -> all 0; vio -> scale_sigma per metre, translation_noise_mps per second,
/// rotation_scale_sigma per radian, the yaw-rate bias sigma per second and the yaw random walk
/// (the scale random walk, <= 0.01 over a walk of 100 s, is left out); pdr -> step_length_bias_sigma
/// per metre, per step sqrt(step_length_sigma^2 + miss_probability x (0.7 m)^2) (a missed step of
/// a typical length, sensors.md: ~2 steps/s at 1.0-1.4 m/s) and the heading random walk per step
/// (the per-walk heading offset does not enter relative increments).
OdometryUncertainty odometry_uncertainty(const OdometryParams& params);

/// The odometry a phone would report for the walk.
OdometryTrack simulate_odometry(const Walk& walk, const OdometryParams& params);

}  // namespace floorcast
