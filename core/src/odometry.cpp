#include "floorcast/core/odometry.hpp"

#include <cmath>

namespace floorcast {

Pose2 relative_pose(const Pose2& a, const Pose2& b) {
  const Vec2 d = a.inverse_transform(b.position_m());
  return {d.x(), d.y(), wrap_angle_rad(b.yaw_rad - a.yaw_rad)};
}

Pose2 compose(const Pose2& a, const Pose2& ab) {
  const Vec2 p = a.transform(ab.position_m());
  return {p.x(), p.y(), wrap_angle_rad(a.yaw_rad + ab.yaw_rad)};
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
