// Odometry as a tracker receives it: one relative motion per sample, in the previous body frame.
// Produced by the simulator's odometry models (sim/odometry.hpp) or by a phone (ARKit VIO, a
// step counter); consumed by the trackers (track/).
#pragma once

#include <vector>

#include "floorcast/core/types.hpp"

namespace floorcast {

struct OdometryStep {
  double t_s = 0.0;  ///< time of the sample
  /// Motion since the previous sample, expressed in the previous body frame: translation
  /// (x forward, y left) and heading change. Identity for the first sample.
  Pose2 T_prev_curr;
  /// false when the odometry reports standing still (no step detected, no motion).
  bool moving = true;
};

/// Chains increments from a start pose: poses[0] = start, poses[i] = poses[i-1] * steps[i].
std::vector<Pose2> integrate_odometry(const Pose2& start, const std::vector<OdometryStep>& steps);

/// The relative motion T_a^-1 * T_b.
Pose2 relative_pose(const Pose2& T_world_a, const Pose2& T_world_b);

/// T_a * T_ab.
Pose2 compose(const Pose2& T_world_a, const Pose2& T_a_b);

}  // namespace floorcast
