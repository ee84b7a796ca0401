// Odometry as a tracker receives it: one relative motion per sample, in the previous body frame.
// Produced by the simulator's odometry models (sim/odometry.hpp) or by a phone (ARKit VIO, a
// step counter); consumed by the trackers (track/).
#pragma once

#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "floorcast/core/fields.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {

class ParamReader;

struct OdometryStep {
  double t_s = 0.0;  ///< time of the sample
  /// Motion since the previous sample, expressed in the previous body frame: translation
  /// (x forward, y left) and heading change. Identity for the first sample.
  Pose2 T_prev_curr;
  /// false when the odometry reports standing still (no step detected, no motion).
  bool moving = true;
};

/// What a tracker knows of an odometry source's error: the 1-sigma error of its increments as it
/// grows with the metres travelled, the radians turned, the seconds elapsed and the steps reported.
/// Sensor metadata, not a simulator type: a walk folder states it for its odometry (a simulated
/// walk derives it from its odometry model, sim/odometry.hpp; a recording states its sensor's
/// figures), and trackers turn it into motion noise per increment (increment_noise()).
///
/// Two kinds of terms. Per-walk biases (a scale error, a turn-scale error, a yaw-rate bias: the
/// same all walk) make the odometry's error grow linearly with what was travelled: sigma =
/// translation_per_m x distance, rotation_per_rad x turned, rotation_rad_per_s x time (how a
/// tracker spreads them over increments: BiasGrowth). White terms are independent per increment:
/// translation_m_per_s x dt per increment (velocity noise, per axis), rotation_rad_per_sqrt_s x
/// sqrt(dt), and per reported step translation_m_per_step (along the step) and
/// rotation_rad_per_step.
///
/// The defaults are for odometry nobody characterised: PALMS' particle-filter motion noise per
/// step (step length N(0, 0.356 m), heading N(0, 0.05 rad); ../shared/reference/sensors.md), the
/// one published figure for a phone's uncharacterised step odometry, plus ARKit VIO's ~0.02 m of
/// drift per second, and no bias.
struct OdometryUncertainty {
  double translation_per_m = 0.0;        ///< bias: relative error of the distance travelled (scale)
  double translation_m_per_s = 0.02;     ///< white: error per axis of an increment, per second of it
  double translation_m_per_step = 0.356; ///< white: along-track error of each reported step
  double rotation_per_rad = 0.0;         ///< bias: relative error of measured turns
  double rotation_rad_per_s = 0.0;       ///< bias: heading error per second (yaw-rate bias)
  double rotation_rad_per_sqrt_s = 0.0;  ///< white: heading random walk, rad per sqrt(second)
  double rotation_rad_per_step = 0.05;   ///< white: heading error of each reported step

  static const FieldList<OdometryUncertainty>& fields();
  nlohmann::ordered_json to_json() const;
  /// Strict overrides (keys as in to_json); throws ParameterError naming the key.
  void apply_overrides(const nlohmann::json& overrides);
};

/// How a tracker spreads a bias term of OdometryUncertainty over the increments.
enum class BiasGrowth {
  /// Each increment gets the bias's error over that increment (b x its metres, radians, seconds)
  /// as independent noise: the spread after n equal increments is b E / sqrt(n), not b E. Most
  /// filters' constant per-step noise (PALMS, F3Loc) is of this kind.
  kPerIncrement,
  /// Each increment adds what the bias's linear growth adds over it, (b (E + e))^2 - (b E)^2 for
  /// what had elapsed E (since the start or the last measurement update) and the increment's e:
  /// a tracker that convolves its belief with every increment's noise then ends with the bias's
  /// spread b E_total (a Markov tracker cannot keep the bias's correlation between increments,
  /// only its size).
  kLinear,
};

const std::vector<std::pair<const char*, BiasGrowth>>& bias_growth_names();

/// What the odometry travelled since the tracker last knew its pose (its start, or its last
/// measurement update): BiasGrowth::kLinear's clock.
struct OdometryElapsed {
  double distance_m = 0.0;
  double turned_rad = 0.0;
  double time_s = 0.0;
};

/// 1-sigma error of one odometry increment.
struct IncrementNoise {
  double along_m = 0.0;     ///< along the motion (length error)
  double across_m = 0.0;    ///< across the motion
  double rotation_rad = 0.0;
};

/// The error `step` (of duration dt_s) adds under `u`, after `elapsed`, which it then advances.
/// Variances add; bias terms per `growth` (g_b below: (b e)^2 per increment, or
/// b^2 ((E + e)^2 - E^2) for kLinear):
///   along^2    = g(translation_per_m; distance) + (translation_m_per_s dt)^2
///                + translation_m_per_step^2 [a reported step]
///   across^2   = (translation_m_per_s dt)^2
///   rotation^2 = g(rotation_per_rad; |turn|) + g(rotation_rad_per_s; dt)
///                + rotation_rad_per_sqrt_s^2 dt + rotation_rad_per_step^2 [a reported step]
/// A reported step is a moving increment with a translation; a standing one (moving = false) has
/// only the time terms.
IncrementNoise increment_noise(const OdometryUncertainty& u, const OdometryStep& step, double dt_s, BiasGrowth growth,
                               OdometryElapsed& elapsed);

/// Chains increments from a start pose: poses[0] = start, poses[i] = poses[i-1] * steps[i].
std::vector<Pose2> integrate_odometry(const Pose2& start, const std::vector<OdometryStep>& steps);

/// The relative motion T_a^-1 * T_b.
Pose2 relative_pose(const Pose2& T_world_a, const Pose2& T_world_b);

/// T_a * T_ab.
Pose2 compose(const Pose2& T_world_a, const Pose2& T_a_b);

}  // namespace floorcast
