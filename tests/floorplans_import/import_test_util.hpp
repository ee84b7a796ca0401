// Helpers shared by the importer tests (and the tests that run on the real development plans).
#pragma once

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <limits>
#include <string>

#include "floorcast/floorplans/floor_plan.hpp"

namespace floorcast::test {

inline std::string data_path(const std::string& relative) { return std::string(FLOORCAST_TEST_DATA_DIR) + "/" + relative; }

inline bool is_dir(const std::string& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

/// The real development plans (../shared/realplans; not part of the repository, so absent on a
/// clean clone): FLOORCAST_REALPLANS_DIR, else ../shared/realplans next to the source tree (or one
/// level up, for worktrees under wt/); empty if none exists.
inline std::string realplans_dir() {
  if (const char* env = std::getenv("FLOORCAST_REALPLANS_DIR")) return is_dir(env) ? env : "";
  for (const char* rel : {"/../shared/realplans", "/../../shared/realplans"}) {
    const std::string p = std::string(FLOORCAST_SOURCE_DIR) + rel;
    if (is_dir(p)) return p;
  }
  return "";
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// WGS84 radii of curvature, the reference formulas the geographic tests check the importers'
/// projection (PROJ) against: meridional M(lat) = a (1 - e^2) / (1 - e^2 sin^2)^1.5 and prime
/// vertical N(lat) = a / sqrt(1 - e^2 sin^2).
inline double meridian_radius_m(double lat_deg) {
  const double a = 6378137.0, f = 1.0 / 298.257223563, e2 = f * (2.0 - f);
  const double s = std::sin(lat_deg * M_PI / 180.0);
  return a * (1.0 - e2) / std::pow(1.0 - e2 * s * s, 1.5);
}
inline double prime_vertical_radius_m(double lat_deg) {
  const double a = 6378137.0, f = 1.0 / 298.257223563, e2 = f * (2.0 - f);
  const double s = std::sin(lat_deg * M_PI / 180.0);
  return a / std::sqrt(1.0 - e2 * s * s);
}

/// Distance from p to segment ab.
inline double point_segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm();
}

/// Distance from p to the nearest wall centreline of the plan.
inline double distance_to_walls(const FloorPlan& plan, const Vec2& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Wall& w : plan.walls) best = std::min(best, point_segment_distance(p, w.a_m, w.b_m));
  return best;
}

/// The wall whose endpoints are {a, b} (either order) within tol, or nullptr.
inline const Wall* find_wall(const FloorPlan& plan, const Vec2& a, const Vec2& b, double tol) {
  for (const Wall& w : plan.walls) {
    if (((w.a_m - a).norm() <= tol && (w.b_m - b).norm() <= tol) || ((w.a_m - b).norm() <= tol && (w.b_m - a).norm() <= tol)) {
      return &w;
    }
  }
  return nullptr;
}

/// Index of the wall with this id (or -1).
inline const Wall* wall_by_id(const FloorPlan& plan, const std::string& id) {
  const int i = plan.wall_index(id);
  return i < 0 ? nullptr : &plan.walls[static_cast<std::size_t>(i)];
}

inline const Door* door_by_id(const FloorPlan& plan, const std::string& id) {
  for (const Door& d : plan.doors) {
    if (d.id == id) return &d;
  }
  return nullptr;
}

/// Sorted wall lengths.
inline std::vector<double> wall_lengths(const FloorPlan& plan) {
  std::vector<double> out;
  for (const Wall& w : plan.walls) out.push_back(w.length_m());
  std::sort(out.begin(), out.end());
  return out;
}

/// Expects `what()` of the thrown InputError to contain every fragment.
template <typename F>
void expect_input_error(F&& f, std::initializer_list<std::string> fragments) {
  try {
    f();
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const std::string& frag : fragments) EXPECT_NE(msg.find(frag), std::string::npos) << "message: " << msg << "\nmissing: " << frag;
  }
}

}  // namespace floorcast::test
