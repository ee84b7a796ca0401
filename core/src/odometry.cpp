#include "floorcast/core/odometry.hpp"

#include <algorithm>
#include <cmath>

#include "floorcast/core/params.hpp"

namespace floorcast {

Pose2 relative_pose(const Pose2& a, const Pose2& b) {
  const Vec2 d = a.inverse_transform(b.position_m());
  return {d.x(), d.y(), wrap_angle_rad(b.yaw_rad - a.yaw_rad)};
}

Pose2 compose(const Pose2& a, const Pose2& ab) {
  const Vec2 p = a.transform(ab.position_m());
  return {p.x(), p.y(), wrap_angle_rad(a.yaw_rad + ab.yaw_rad)};
}

const std::vector<std::pair<const char*, BiasGrowth>>& bias_growth_names() {
  static const std::vector<std::pair<const char*, BiasGrowth>> n = {{"increment", BiasGrowth::kPerIncrement},
                                                                    {"linear", BiasGrowth::kLinear}};
  return n;
}

const FieldList<OdometryUncertainty>& OdometryUncertainty::fields() {
  using U = OdometryUncertainty;
  static const FieldList<U> f =
      FieldList<U>("odometry uncertainty")
          .number("translation_per_m", &U::translation_per_m, 0.0, 10.0, "bias: relative error of the distance travelled")
          .number("translation_m_per_s", &U::translation_m_per_s, 0.0, 100.0,
                  "white: error per axis of an increment, m per second of it")
          .number("translation_m_per_step", &U::translation_m_per_step, 0.0, 100.0,
                  "white: along-track error of each reported step, m")
          .number("rotation_per_rad", &U::rotation_per_rad, 0.0, 10.0, "bias: relative error of measured turns")
          .number("rotation_rad_per_s", &U::rotation_rad_per_s, 0.0, 10.0, "bias: heading error per second (yaw-rate bias), rad/s")
          .number("rotation_rad_per_sqrt_s", &U::rotation_rad_per_sqrt_s, 0.0, 10.0,
                  "white: heading random walk, rad per sqrt(second)")
          .number("rotation_rad_per_step", &U::rotation_rad_per_step, 0.0, 10.0, "white: heading error of each reported step, rad");
  return f;
}

nlohmann::ordered_json OdometryUncertainty::to_json() const { return fields().write(*this); }

void OdometryUncertainty::apply_overrides(const nlohmann::json& overrides) { fields().read(*this, overrides); }

IncrementNoise increment_noise(const OdometryUncertainty& u, const OdometryStep& step, double dt_s, BiasGrowth growth,
                               OdometryElapsed& elapsed) {
  const double dt = std::max(0.0, dt_s);
  const double d = step.moving ? step.T_prev_curr.position_m().norm() : 0.0;
  const double turn = std::abs(step.T_prev_curr.yaw_rad);
  const bool reported_step = step.moving && d > 0.0;
  const auto sq = [](double v) { return v * v; };
  // What a bias of b adds over this increment: b e, or (linear) its spread grows from b E to
  // b (E + e).
  const bool linear = growth == BiasGrowth::kLinear;
  const auto grown = [&](double b, double before, double add) {
    return linear ? sq(b) * (sq(before + add) - sq(before)) : sq(b * add);
  };
  const double white = sq(u.translation_m_per_s * dt);
  IncrementNoise n;
  n.along_m = std::sqrt(grown(u.translation_per_m, elapsed.distance_m, d) + white +
                        (reported_step ? sq(u.translation_m_per_step) : 0.0));
  n.across_m = std::sqrt(white);
  n.rotation_rad = std::sqrt(grown(u.rotation_per_rad, elapsed.turned_rad, turn) + grown(u.rotation_rad_per_s, elapsed.time_s, dt) +
                             sq(u.rotation_rad_per_sqrt_s) * dt + (reported_step ? sq(u.rotation_rad_per_step) : 0.0));
  elapsed.distance_m += d;
  elapsed.turned_rad += turn;
  elapsed.time_s += dt;
  return n;
}

std::vector<Pose2> integrate_odometry(const Pose2& start, const std::vector<OdometryStep>& steps) {
  std::vector<Pose2> poses;
  poses.reserve(steps.size());
  Pose2 p = start;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (i > 0) p = compose(p, steps[i].T_prev_curr);
    poses.push_back(p);
  }
  return poses;
}

}  // namespace floorcast
