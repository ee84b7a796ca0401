// Test helper: compares extracted 2D segments with true walls.
#pragma once

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "floorcast/core/types.hpp"
#include "floorcast/core/math.hpp"

namespace floorcast::test {

constexpr double kSegPi = floorcast::kPi;

struct WallMatch {
  /// Extracted segments that lie on no wall (angle > max_angle or an endpoint > max_dist off
  /// the wall's line or beyond its ends), with details.
  std::vector<std::string> stray;
  /// Fraction of each wall's length covered by segments lying on it.
  std::vector<double> coverage;
  double worst_angle_deg = 0.0;  ///< over matched segments
  double worst_offset_m = 0.0;   ///< endpoint distance to the wall line, over matched segments
};

inline WallMatch match_walls(const std::vector<Segment2>& segments, const std::vector<Segment2>& walls,
                             double max_dist_m, double max_angle_deg, double min_length_m = 0.0) {
  WallMatch out;
  std::vector<std::vector<std::pair<double, double>>> covered(walls.size());
  for (const Segment2& s : segments) {
    if (s.length_m() < min_length_m) continue;
    int best = -1;
    double best_off = 1e9, best_ang = 1e9;
    for (std::size_t w = 0; w < walls.size(); ++w) {
      const Segment2& wall = walls[w];
      const Vec2 u = (wall.b_m - wall.a_m).normalized();
      const Vec2 n(-u.y(), u.x());
      const double len = wall.length_m();
      double ang = std::abs(std::remainder(s.direction_rad() - wall.direction_rad(), kSegPi)) * 180.0 / kSegPi;
      double off = std::max(std::abs((s.a_m - wall.a_m).dot(n)), std::abs((s.b_m - wall.a_m).dot(n)));
      const double ta = (s.a_m - wall.a_m).dot(u), tb = (s.b_m - wall.a_m).dot(u);
      if (std::min(ta, tb) < -max_dist_m || std::max(ta, tb) > len + max_dist_m) off = 1e9;
      if (off <= max_dist_m && ang <= max_angle_deg && off < best_off) {
        best = static_cast<int>(w);
        best_off = off;
        best_ang = ang;
      }
    }
    if (best < 0) {
      std::ostringstream m;
      m << "segment (" << s.a_m.x() << ", " << s.a_m.y() << ") -> (" << s.b_m.x() << ", " << s.b_m.y()
        << ") lies on no wall";
      out.stray.push_back(m.str());
      continue;
    }
    out.worst_angle_deg = std::max(out.worst_angle_deg, best_ang);
    out.worst_offset_m = std::max(out.worst_offset_m, best_off);
    const Segment2& wall = walls[best];
    const Vec2 u = (wall.b_m - wall.a_m).normalized();
    double ta = (s.a_m - wall.a_m).dot(u), tb = (s.b_m - wall.a_m).dot(u);
    if (ta > tb) std::swap(ta, tb);
    covered[best].push_back({std::max(0.0, ta), std::min(wall.length_m(), tb)});
  }
  for (std::size_t w = 0; w < walls.size(); ++w) {
    auto& iv = covered[w];
    std::sort(iv.begin(), iv.end());
    double total = 0.0, cur_a = -1e9, cur_b = -1e9;
    for (const auto& [a, b] : iv) {
      if (a > cur_b) {
        if (cur_b > cur_a) total += cur_b - cur_a;
        cur_a = a;
        cur_b = b;
      } else {
        cur_b = std::max(cur_b, b);
      }
    }
    if (cur_b > cur_a) total += cur_b - cur_a;
    out.coverage.push_back(total / walls[w].length_m());
  }
  return out;
}

/// Joins collinear truth segments that touch end to end (a wall, a door leaf and the next wall
/// piece form one straight surface), so an observed segment spanning them matches one piece.
inline std::vector<Segment2> join_collinear(std::vector<Segment2> segs, double tol_m = 0.01, double tol_deg = 0.5) {
  bool joined = true;
  while (joined) {
    joined = false;
    for (std::size_t i = 0; i < segs.size() && !joined; ++i) {
      for (std::size_t j = 0; j < segs.size() && !joined; ++j) {
        if (i == j) continue;
        const Segment2& a = segs[i];
        const Segment2& b = segs[j];
        const double ang = std::abs(std::remainder(a.direction_rad() - b.direction_rad(), kSegPi)) * 180.0 / kSegPi;
        if (ang > tol_deg) continue;
        // b continues a: b starts where a ends (either orientation).
        Segment2 merged;
        if ((a.b_m - b.a_m).norm() <= tol_m) {
          merged = {a.a_m, b.b_m};
        } else if ((a.b_m - b.b_m).norm() <= tol_m) {
          merged = {a.a_m, b.a_m};
        } else {
          continue;
        }
        if (merged.length_m() < std::max(a.length_m(), b.length_m())) continue;
        segs[i] = merged;
        segs.erase(segs.begin() + static_cast<std::ptrdiff_t>(j));
        joined = true;
      }
    }
  }
  return segs;
}

inline std::vector<Segment2> polygon_walls(const std::vector<Eigen::Vector2d>& corners) {
  std::vector<Segment2> w;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    Segment2 s;
    s.a_m = corners[i];
    s.b_m = corners[(i + 1) % corners.size()];
    w.push_back(s);
  }
  return w;
}

}  // namespace floorcast::test
