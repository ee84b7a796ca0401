// Simulated walks and odometry: walks never cross a wall, closed door, glass or furniture; gait in
// human ranges; same seed, same walk; odometry statistics match their parameters; files round-trip.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "floorcast/core/math.hpp"
#include "floorcast/core/trajectory_io.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/sim/odometry.hpp"
#include "floorcast/sim/walk.hpp"
#include "floorcast/sim/walk_io.hpp"

namespace floorcast {
namespace {

const FloorPlan& building(const std::string& name) {
  static std::map<std::string, FloorPlan> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    it = cache.emplace(name, load_floor_plan(std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/" + name + ".json")).first;
  }
  return it->second;
}

/// Does segment ab cross (or touch) the convex polygon? Exact: an endpoint inside, or an
/// intersection with one of its edges.
bool segment_hits_polygon(const Vec2& a, const Vec2& b, const std::vector<Vec2>& poly) {
  if (point_in_convex_polygon(poly, a) || point_in_convex_polygon(poly, b)) return true;
  auto cross = [](const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); };
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2 c = poly[i], d = poly[(i + 1) % poly.size()];
    const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a), d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
    if (((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0))) return true;
  }
  return false;
}

Walk walk_in(const std::string& name, std::uint64_t seed, int steps = 120) {
  WalkParams p;
  p.seed = seed;
  p.steps = steps;
  const FloorPlan& plan = building(name);
  return simulate_walk(plan, random_start_pose(plan, p), p);
}

TEST(Walk, NeverCrossesWallsClosedDoorsGlassOrFurniture) {
  for (const std::string name : {"apartment", "office", "campus", "angled"}) {
    const std::vector<Footprint> blocking = blocking_footprints(building(name), walker_blocking());
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
      const Walk w = walk_in(name, seed);
      ASSERT_EQ(w.steps.size(), 120u);
      for (std::size_t i = 1; i < w.steps.size(); ++i) {
        const Vec2 a = w.steps[i - 1].T_world_body.position_m(), b = w.steps[i].T_world_body.position_m();
        for (const Footprint& f : blocking) {
          ASSERT_FALSE(segment_hits_polygon(a, b, f.polygon_m))
              << name << " seed " << seed << " step " << i << " crosses element " << f.source_index;
        }
      }
    }
  }
}

TEST(Walk, HumanGait) {
  double longest_straight = 0.0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const Walk w = walk_in(seed % 2 ? "office" : "campus", seed, 200);
    const WalkSummary& s = w.summary;
    EXPECT_GE(s.speed_mps, 1.0);
    EXPECT_LE(s.speed_mps, 1.4);
    EXPECT_GE(s.cadence_hz, 1.8);
    EXPECT_LE(s.cadence_hz, 2.0);
    // Steps of speed / cadence (+-5% per step), at the cadence; turns within the human rate.
    for (std::size_t i = 1; i < w.steps.size(); ++i) {
      const WalkStep& a = w.steps[i - 1];
      const WalkStep& b = w.steps[i];
      const double dt = b.t_s - a.t_s;
      ASSERT_GT(dt, 0.0);
      EXPECT_LE(dt, 1.0 / 1.8 * 1.25);
      if (b.moving) {
        EXPECT_LE(b.step_length_m, 1.4 / 1.8 * 1.25);
      }
      EXPECT_LE(angle_distance_rad(a.T_world_body.yaw_rad, b.T_world_body.yaw_rad), deg_to_rad(120.0) * dt + 1e-9);
    }
    const double walked_speed = s.length_m / s.duration_s;
    EXPECT_GT(walked_speed, 0.6);  // pauses and the final stretch included
    EXPECT_LT(walked_speed, 1.5);
    EXPECT_GT(s.transitional_share, 0.3) << "seed " << seed;  // corridors, lobbies, junctions
    longest_straight = std::max(longest_straight, s.longest_straight_m);
  }
  EXPECT_GT(longest_straight, 15.0);  // long homogeneous corridors occur
}

TEST(Walk, SameSeedSameWalkOtherSeedOtherWalk) {
  const Walk a = walk_in("office", 7), b = walk_in("office", 7), c = walk_in("office", 8);
  ASSERT_EQ(a.steps.size(), b.steps.size());
  for (std::size_t i = 0; i < a.steps.size(); ++i) {
    EXPECT_EQ(a.steps[i].T_world_body.x_m, b.steps[i].T_world_body.x_m);
    EXPECT_EQ(a.steps[i].T_world_body.yaw_rad, b.steps[i].T_world_body.yaw_rad);
    EXPECT_EQ(a.steps[i].t_s, b.steps[i].t_s);
  }
  EXPECT_NE(a.steps.back().T_world_body.x_m, c.steps.back().T_world_body.x_m);
}

TEST(Walk, StartOutsideFreeSpaceIsRefused) {
  WalkParams p;
  EXPECT_THROW(simulate_walk(building("apartment"), {-50.0, -50.0, 0.0}, p), InputError);
  EXPECT_THROW(p.apply_overrides({{"speed_min_mps", 2.0}, {"speed_max_mps", 1.0}}), InputError);
  EXPECT_THROW(p.apply_overrides({{"stepz", 3}}), InputError);
}

TEST(Walk, ObservationSchedule) {
  const Walk w = walk_in("office", 3);
  EXPECT_EQ(schedule_observations(w, {true, 0, 0.0}), std::vector<int>{0});
  const std::vector<int> every10 = schedule_observations(w, {true, 10, 0.0});
  ASSERT_EQ(every10.size(), 1u + (w.steps.size() - 1) / 10);
  EXPECT_EQ(every10[1], 10);
  const std::vector<int> every5m = schedule_observations(w, {false, 0, 5.0});
  ASSERT_GT(every5m.size(), 3u);
  double since = 0.0;
  std::size_t k = 0;
  for (std::size_t i = 1; i < w.steps.size() && k < every5m.size(); ++i) {
    since += w.steps[i].step_length_m;
    if (static_cast<int>(i) == every5m[k]) {
      EXPECT_GE(since, 5.0);
      EXPECT_LT(since, 5.0 + 1.0);
      since = 0.0;
      ++k;
    }
  }
}

/// Position error of the chained odometry at the end of the walk.
double end_drift_m(const Walk& w, const OdometryTrack& o) {
  const Vec2 d = w.steps.back().T_world_body.position_m() - o.poses.back().position_m();
  return d.norm();
}

TEST(Odometry, ExactIsTheTruth) {
  const Walk w = walk_in("campus", 2);
  OdometryParams p;
  p.model = OdometryModel::kExact;
  const OdometryTrack o = simulate_odometry(w, p);
  ASSERT_EQ(o.steps.size(), w.steps.size());
  for (std::size_t i = 0; i < w.steps.size(); ++i) {
    EXPECT_NEAR(o.poses[i].x_m, w.steps[i].T_world_body.x_m, 1e-9);
    EXPECT_NEAR(o.poses[i].y_m, w.steps[i].T_world_body.y_m, 1e-9);
    EXPECT_NEAR(angle_distance_rad(o.poses[i].yaw_rad, w.steps[i].T_world_body.yaw_rad), 0.0, 1e-9);
  }
}

// VIO: ~0.02 m of drift per second of walking (sensors.md), as a median over seeded walks; the
// per-walk scale error has the configured spread.
TEST(Odometry, VioDriftMatchesItsParameters) {
  std::vector<double> rate;
  for (std::uint64_t seed = 1; seed <= 24; ++seed) {
    const Walk w = walk_in(seed % 2 ? "campus" : "office", seed, 200);
    OdometryParams p;
    p.model = OdometryModel::kVio;
    p.seed = 1000 + seed;
    const OdometryTrack o = simulate_odometry(w, p);
    rate.push_back(end_drift_m(w, o) / w.summary.duration_s);
  }
  const double med = median(rate);
  EXPECT_GT(med, 0.008) << "median drift " << med << " m/s";
  EXPECT_LT(med, 0.04) << "median drift " << med << " m/s";
  // Scale only (no other noise): the chained path length is scale x the true one.
  const Walk w = walk_in("office", 5, 200);
  OdometryParams p;
  p.model = OdometryModel::kVio;
  p.vio = VioNoise{0.05, 0.0, 0.0, 0.0, 0.0, 0.0};
  std::vector<double> scales;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    p.seed = seed;
    const OdometryTrack o = simulate_odometry(w, p);
    double len = 0.0;
    for (std::size_t i = 1; i < o.steps.size(); ++i) len += o.steps[i].T_prev_curr.position_m().norm();
    scales.push_back(len / w.summary.length_m - 1.0);
  }
  double mean = 0.0, var = 0.0;
  for (double s : scales) mean += s / scales.size();
  for (double s : scales) var += (s - mean) * (s - mean) / (scales.size() - 1);
  EXPECT_NEAR(mean, 0.0, 0.012);
  EXPECT_NEAR(std::sqrt(var), 0.05, 0.008);
}

// PDR: the step-length bias scales the walked distance; missed steps are as frequent as asked.
TEST(Odometry, PdrStepsMatchTheirParameters) {
  const Walk w = walk_in("campus", 4, 300);
  OdometryParams p;
  p.model = OdometryModel::kPdr;
  p.pdr = PdrNoise{0.1, 0.0, 0.0, 0.0, 0.0, 0.0};
  int moving = 0, detected = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    p.seed = seed;
    const OdometryTrack o = simulate_odometry(w, p);
    for (std::size_t i = 1; i < w.steps.size(); ++i) {
      if (!w.steps[i].moving) continue;
      ++moving;
      detected += o.steps[i].moving ? 1 : 0;
    }
  }
  EXPECT_NEAR(1.0 - static_cast<double>(detected) / moving, 0.1, 0.02);
  p.pdr = PdrNoise{0.0, 0.0, 0.05, 0.0, 0.0, 0.0};
  std::vector<double> bias;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    p.seed = seed;
    const OdometryTrack o = simulate_odometry(w, p);
    double len = 0.0;
    for (std::size_t i = 1; i < o.steps.size(); ++i) len += o.steps[i].T_prev_curr.position_m().norm();
    bias.push_back(len / w.summary.length_m - 1.0);
  }
  double mean = 0.0, var = 0.0;
  for (double b : bias) mean += b / bias.size();
  for (double b : bias) var += (b - mean) * (b - mean) / (bias.size() - 1);
  EXPECT_NEAR(std::sqrt(var), 0.05, 0.008);
  // Default PDR drifts more than VIO, less than 10% of the distance walked (median).
  std::vector<double> rel;
  for (std::uint64_t seed = 1; seed <= 16; ++seed) {
    const Walk ws = walk_in("office", seed, 200);
    OdometryParams d;
    d.model = OdometryModel::kPdr;
    d.seed = seed;
    rel.push_back(end_drift_m(ws, simulate_odometry(ws, d)) / ws.summary.length_m);
  }
  EXPECT_LT(median(rel), 0.10);
  EXPECT_GT(median(rel), 0.005);
}

// The error a walk states for its odometry (odometry_uncertainty) describes the simulated
// odometry: over seeded walks the end heading error and the path-length error, divided by the
// sigma the stated uncertainty predicts for the whole walk (increment_noise with linear bias
// growth, variances summed), have a spread near 1 (between 0.6 and 1.6: 30 walks, odometry seeds
// independent of the walks'). A mapping that forgot a term or mis-scaled one fails (e.g. the yaw
// bias per second read as per sqrt(s)).
TEST(Odometry, StatedUncertaintyDescribesTheSimulatedOdometry) {
  std::vector<Walk> walks;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) walks.push_back(walk_in("office", seed, 150));
  for (const OdometryModel model : {OdometryModel::kVio, OdometryModel::kPdr}) {
    std::vector<double> z_heading, z_length;
    for (std::uint64_t seed = 1; seed <= walks.size(); ++seed) {
      const Walk& w = walks[seed - 1];
      OdometryParams p;
      p.model = model;
      p.seed = 500 + seed;
      const OdometryTrack o = simulate_odometry(w, p);
      const OdometryUncertainty u = odometry_uncertainty(p);
      OdometryElapsed elapsed;
      double var_heading = 0.0, var_length = 0.0, odo_length = 0.0, true_length = 0.0, heading_error = 0.0;
      for (std::size_t i = 1; i < o.steps.size(); ++i) {
        const IncrementNoise n = increment_noise(u, o.steps[i], o.steps[i].t_s - o.steps[i - 1].t_s, BiasGrowth::kLinear, elapsed);
        var_heading += n.rotation_rad * n.rotation_rad;
        var_length += n.along_m * n.along_m;
        odo_length += o.steps[i].T_prev_curr.position_m().norm();
        true_length += relative_pose(w.steps[i - 1].T_world_body, w.steps[i].T_world_body).position_m().norm();
        heading_error += wrap_angle_rad(o.steps[i].T_prev_curr.yaw_rad -
                                        relative_pose(w.steps[i - 1].T_world_body, w.steps[i].T_world_body).yaw_rad);
      }
      z_heading.push_back(heading_error / std::sqrt(var_heading));
      // PDR's length error is dominated by missed steps (a whole step at once): its stated
      // per-step term is the average variance; the heading is checked for both models.
      if (model == OdometryModel::kVio) z_length.push_back((odo_length - true_length) / std::sqrt(var_length));
    }
    auto rms = [](const std::vector<double>& v) {
      double s = 0.0;
      for (double x : v) s += x * x;
      return std::sqrt(s / static_cast<double>(v.size()));
    };
    const char* name = model == OdometryModel::kVio ? "vio" : "pdr";
    std::printf("%s: rms z heading %.2f, length %.2f\n", name, rms(z_heading), z_length.empty() ? 0.0 : rms(z_length));
    EXPECT_GT(rms(z_heading), 0.6) << name;
    EXPECT_LT(rms(z_heading), 1.6) << name;
    if (!z_length.empty()) {
      EXPECT_GT(rms(z_length), 0.6) << name;
      EXPECT_LT(rms(z_length), 1.6) << name;
    }
  }
  OdometryParams exact;
  exact.model = OdometryModel::kExact;
  EXPECT_EQ(odometry_uncertainty(exact).to_json(), OdometryUncertainty({0, 0, 0, 0, 0, 0, 0}).to_json());
}

TEST(WalkIo, RoundTripAndTum) {
  const std::string dir = (std::filesystem::temp_directory_path() / ("floorcast_walk_io_" + std::to_string(::getpid()))).string();
  std::filesystem::remove_all(dir);
  WalkRecord rec;
  rec.walk = walk_in("apartment", 9, 60);
  rec.odometry_params.model = OdometryModel::kPdr;
  rec.odometry = simulate_odometry(rec.walk, rec.odometry_params);
  rec.odometry_uncertainty = odometry_uncertainty(rec.odometry_params);
  rec.odometry_uncertainty.rotation_rad_per_s = 0.001;  // a stated figure, not the model's: kept
  rec.schedule = {true, 20, 0.0};
  rec.plan_name = "apartment";
  rec.plan_hash = "0123456789abcdef";
  for (int s : schedule_observations(rec.walk, rec.schedule)) {
    rec.observations.push_back({s, "perfect", "observations/step_" + std::to_string(s)});
  }
  save_walk(dir, rec);
  const WalkRecord back = load_walk(dir);
  ASSERT_EQ(back.walk.steps.size(), rec.walk.steps.size());
  for (std::size_t i = 0; i < rec.walk.steps.size(); ++i) {
    EXPECT_EQ(back.walk.steps[i].T_world_body.x_m, rec.walk.steps[i].T_world_body.x_m);
    EXPECT_EQ(back.odometry.steps[i].T_prev_curr.yaw_rad, rec.odometry.steps[i].T_prev_curr.yaw_rad);
    EXPECT_EQ(back.odometry.steps[i].moving, rec.odometry.steps[i].moving);
  }
  EXPECT_EQ(back.observations.size(), rec.observations.size());
  EXPECT_EQ(back.odometry_params.to_json(), rec.odometry_params.to_json());
  EXPECT_EQ(back.odometry_uncertainty.to_json(), rec.odometry_uncertainty.to_json());
  EXPECT_EQ(back.walk.params.to_json(), rec.walk.params.to_json());
  // TUM: 8 numbers per line, unit quaternions about z, the yaw back within round-off.
  const std::vector<StampedPose> truth = load_tum(dir + "/truth.tum");
  ASSERT_EQ(truth.size(), rec.walk.steps.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    EXPECT_NEAR(angle_distance_rad(truth[i].pose.yaw_rad, rec.walk.steps[i].T_world_body.yaw_rad), 0.0, 1e-12);
    EXPECT_EQ(truth[i].pose.x_m, rec.walk.steps[i].T_world_body.x_m);
  }
  EXPECT_THROW(parse_tum("0 1 2 0 0.5 0 0 0.866\n", "x.tum"), InputError);  // not planar
  EXPECT_THROW(parse_tum("0 1 2 0 0 0\n", "x.tum"), InputError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace floorcast
