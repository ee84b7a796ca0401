// Small value types shared by every floorcast stage (core: no dependency beyond Eigen).
//
// Frames: world = floor-plan metres, x right, y up, yaw counter-clockwise from +x.
// Observer frame (2D): origin at the observer, +x along the observer's heading (yaw 0), +y to its
// left. A pose T_world_observer maps observer-frame points to world points.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "floorcast/core/math.hpp"

namespace floorcast {

using Vec2 = Eigen::Vector2d;

/// A 2D line segment in metres (frame given by context).
struct Segment2 {
  Vec2 a_m = Vec2::Zero();
  Vec2 b_m = Vec2::Zero();

  double length_m() const { return (b_m - a_m).norm(); }
  /// Direction angle of a->b in radians, in (-pi, pi].
  double direction_rad() const { return std::atan2(b_m.y() - a_m.y(), b_m.x() - a_m.x()); }
};

/// A planar pose: position in metres and heading (yaw) in radians, CCW from +x.
struct Pose2 {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;

  Vec2 position_m() const { return {x_m, y_m}; }
  /// Maps a point from this pose's local frame into the parent frame.
  Vec2 transform(const Vec2& p_local) const {
    const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
    return {x_m + c * p_local.x() - s * p_local.y(), y_m + s * p_local.x() + c * p_local.y()};
  }
  /// Maps a point from the parent frame into this pose's local frame.
  Vec2 inverse_transform(const Vec2& p_parent) const {
    const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
    const double dx = p_parent.x() - x_m, dy = p_parent.y() - y_m;
    return {c * dx + s * dy, -s * dx + c * dy};
  }
};

/// The largest coordinate any position may have, metres from the origin (plans, poses, walks,
/// trajectories): 100 km. Inputs beyond it are refused where they are read, so that squares and
/// sums of coordinates (errors, RMSE, odometry integrated over a walk) stay finite.
constexpr double kMaxAbsCoordinateM = 1.0e5;

/// Wraps an angle to (-pi, pi].
inline double wrap_angle_rad(double a) {
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a <= 0.0) a += 2.0 * kPi;
  return a - kPi;
}

/// Absolute angular difference in [0, pi].
inline double angle_distance_rad(double a, double b) { return std::abs(wrap_angle_rad(a - b)); }

/// Thrown for bad user input (files, parameters). The message names the source, the element and
/// the reason, e.g. "plan.json: walls[3] (id \"w3\"): wall has zero length".
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace floorcast
