// Trajectories in the TUM RGB-D format, which evo (evo_ape, evo_rpe, evo_traj) reads unchanged:
// one line per pose, "timestamp tx ty tz qx qy qz qw", space separated; lines starting with #
// are comments. Planar poses are written with z = 0 and the quaternion of a rotation about +z.
#pragma once

#include <string>
#include <vector>

#include "floorcast/core/types.hpp"

namespace floorcast {

struct StampedPose {
  double t_s = 0.0;
  Pose2 pose;
};

/// TUM text of a planar trajectory (17 significant digits: round-trips exactly).
std::string tum_text(const std::vector<StampedPose>& trajectory, const std::string& comment = "");
void save_tum(const std::string& path, const std::vector<StampedPose>& trajectory, const std::string& comment = "");

/// Parses TUM text; yaw is recovered from the quaternion (rotations about other axes are refused
/// as not planar, beyond 1e-6). Throws InputError naming `source`, the line and the reason.
std::vector<StampedPose> parse_tum(const std::string& text, const std::string& source);
std::vector<StampedPose> load_tum(const std::string& path);

}  // namespace floorcast
