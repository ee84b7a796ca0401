#include "floorcast/core/trajectory_io.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/json_text.hpp"

namespace floorcast {

std::string tum_text(const std::vector<StampedPose>& trajectory, const std::string& comment) {
  std::string out = "# timestamp tx ty tz qx qy qz qw";
  if (!comment.empty()) out += " (" + comment + ")";
  out += "\n";
  char buf[256];
  for (const StampedPose& s : trajectory) {
    const double h = 0.5 * s.pose.yaw_rad;
    std::snprintf(buf, sizeof(buf), "%.17g %.17g %.17g 0 0 0 %.17g %.17g\n", s.t_s, s.pose.x_m, s.pose.y_m,
                  std::sin(h), std::cos(h));
    out += buf;
  }
  return out;
}

void save_tum(const std::string& path, const std::vector<StampedPose>& trajectory, const std::string& comment) {
  write_text_file_atomic(path, tum_text(trajectory, comment));
}

std::vector<StampedPose> parse_tum(const std::string& text_in, const std::string& source) {
  std::vector<StampedPose> out;
  std::string text = text_in;
  strip_utf8_bom(text);
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    double v[8];
    int n = 0;
    while (n < 8 && fields >> v[n]) ++n;
    std::string rest;
    const std::string where = source + ":" + std::to_string(number);
    if (n != 8 || (fields >> rest)) throw InputError(where + ": expected 8 numbers: timestamp tx ty tz qx qy qz qw");
    for (double x : v) {
      if (!std::isfinite(x)) throw InputError(where + ": not a finite number");
    }
    // Positions within the plans' coordinate range (a pose at 1e308 m makes every error inf/NaN).
    for (int k = 1; k <= 3; ++k) {
      if (std::abs(v[k]) > kMaxAbsCoordinateM) {
        std::ostringstream os;
        os << where << ": position " << v[k] << " m is beyond +-" << kMaxAbsCoordinateM << " m of the origin";
        throw InputError(os.str());
      }
    }
    const double norm = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
    if (std::abs(norm - 1.0) > 1e-3) throw InputError(where + ": quaternion is not of unit length");
    if (std::abs(v[4]) / norm > 1e-6 || std::abs(v[5]) / norm > 1e-6) {
      throw InputError(where + ": rotation is not about the vertical axis (not a planar pose)");
    }
    if (!out.empty() && v[0] < out.back().t_s) throw InputError(where + ": timestamps go backwards");
    StampedPose s;
    s.t_s = v[0];
    s.pose = {v[1], v[2], wrap_angle_rad(2.0 * std::atan2(v[6], v[7]))};
    out.push_back(s);
  }
  return out;
}

std::vector<StampedPose> load_tum(const std::string& path) { return parse_tum(read_text_file(path), path); }

}  // namespace floorcast
