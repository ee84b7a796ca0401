#include "floorcast/sim/walk_io.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/json_reader.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/trajectory_io.hpp"

namespace floorcast {
namespace {

using OJson = nlohmann::ordered_json;
constexpr int kWalkFormatVersion = 1;
const char* const kCsvHeader =
    "step,t_s,moving,x_m,y_m,yaw_rad,step_length_m,odom_moving,odom_dx_m,odom_dy_m,odom_dyaw_rad,odom_x_m,odom_y_m,"
    "odom_yaw_rad,observation";

OJson summary_json(const WalkSummary& s) {
  OJson j;
  j["length_m"] = s.length_m;
  j["duration_s"] = s.duration_s;
  j["speed_mps"] = s.speed_mps;
  j["cadence_hz"] = s.cadence_hz;
  j["pauses"] = s.pauses;
  j["total_turn_deg"] = s.total_turn_deg;
  j["transitional_share"] = s.transitional_share;
  j["goals"] = s.goals;
  j["longest_straight_m"] = s.longest_straight_m;
  return j;
}

WalkSummary summary_from(const JsonReader& r) {
  r.only({"length_m", "duration_s", "speed_mps", "cadence_hz", "pauses", "total_turn_deg", "transitional_share",
          "goals", "longest_straight_m"});
  WalkSummary s;
  s.length_m = r.number("length_m", 0.0, 1e9);
  s.duration_s = r.number("duration_s", 0.0, 1e9);
  s.speed_mps = r.number("speed_mps", 0.0, 100.0);
  s.cadence_hz = r.number("cadence_hz", 0.0, 100.0);
  s.pauses = static_cast<int>(r.integer("pauses", 0, 100000000));
  s.total_turn_deg = r.number("total_turn_deg", 0.0, 1e12);
  s.transitional_share = r.number("transitional_share", 0.0, 1.0);
  s.goals = static_cast<int>(r.integer("goals", 0, 100000000));
  s.longest_straight_m = r.number("longest_straight_m", 0.0, 1e9);
  return s;
}

}  // namespace

void save_walk(const std::string& dir, const WalkRecord& rec) {
  create_directories_or_throw(dir);
  const Walk& w = rec.walk;
  if (rec.odometry.steps.size() != w.steps.size()) throw InputError(dir + ": odometry and walk have different lengths");
  OJson j;
  j["format"] = "floorcast-walk";
  j["format_version"] = kWalkFormatVersion;
  j["frames"] = "world: plan metres, yaw CCW from +x; increments T_prev_curr in the previous body frame";
  j["plan"] = {{"name", rec.plan_name}, {"hash", rec.plan_hash}};
  j["walk_params"] = w.params.to_json();
  j["odometry_params"] = rec.odometry_params.to_json();
  j["odometry_uncertainty"] = rec.odometry_uncertainty.to_json();
  j["schedule"] = {{"initial", rec.schedule.initial}, {"every_steps", rec.schedule.every_steps}, {"every_m", rec.schedule.every_m}};
  j["observation_settings"] = rec.observation_settings;
  j["summary"] = summary_json(w.summary);
  OJson obs = OJson::array();
  for (const WalkObservation& o : rec.observations) obs.push_back({{"step", o.step}, {"kind", o.kind}, {"path", o.path}});
  j["observations"] = obs;
  OJson route = OJson::array();
  for (const Vec2& p : w.route_m) route.push_back({p.x(), p.y()});
  j["route_m"] = route;
  write_text_file_atomic(dir + "/walk.json", j.dump(2) + "\n");

  // truth.tum in the world (plan) frame; odometry.tum in the odometry's own frame, which starts
  // at the identity (T_odom_body = T_world_start^-1 T_world_odometry): what a real odometry
  // source (VIO, PDR) reports and what evo expects of an odometry file.
  std::vector<StampedPose> truth, odom;
  const Pose2 start = rec.odometry.poses.empty() ? Pose2{} : rec.odometry.poses.front();
  for (std::size_t i = 0; i < w.steps.size(); ++i) {
    truth.push_back({w.steps[i].t_s, w.steps[i].T_world_body});
    const Pose2& p = rec.odometry.poses[i];
    const Vec2 xy = start.inverse_transform(p.position_m());
    odom.push_back({rec.odometry.steps[i].t_s, Pose2{xy.x(), xy.y(), wrap_angle_rad(p.yaw_rad - start.yaw_rad)}});
  }
  save_tum(dir + "/truth.tum", truth, "floorcast walk: ground truth, world (plan) frame");
  save_tum(dir + "/odometry.tum", odom,
           "floorcast walk: odometry (" + rec.odometry_params.to_json()["model"].get<std::string>() +
               "), odometry frame: the first pose is the identity");

  std::vector<bool> observed(w.steps.size(), false);
  for (const WalkObservation& o : rec.observations) {
    if (o.step >= 0 && static_cast<std::size_t>(o.step) < observed.size()) observed[static_cast<std::size_t>(o.step)] = true;
  }
  std::string csv = std::string(kCsvHeader) + "\n";
  char buf[640];
  for (std::size_t i = 0; i < w.steps.size(); ++i) {
    const WalkStep& s = w.steps[i];
    const OdometryStep& o = rec.odometry.steps[i];
    const Pose2& op = rec.odometry.poses[i];
    std::snprintf(buf, sizeof(buf), "%zu,%.17g,%d,%.17g,%.17g,%.17g,%.17g,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d\n", i,
                  s.t_s, s.moving ? 1 : 0, s.T_world_body.x_m, s.T_world_body.y_m, s.T_world_body.yaw_rad, s.step_length_m,
                  o.moving ? 1 : 0, o.T_prev_curr.x_m, o.T_prev_curr.y_m, o.T_prev_curr.yaw_rad, op.x_m, op.y_m, op.yaw_rad,
                  observed[i] ? 1 : 0);
    csv += buf;
  }
  write_text_file_atomic(dir + "/steps.csv", csv);
}

WalkRecord load_walk(const std::string& dir) {
  const std::string json_path = dir + "/walk.json";
  if (!std::filesystem::is_directory(dir)) throw InputError(dir + ": not a walk folder (no such directory)");
  if (!std::filesystem::is_regular_file(json_path)) throw InputError(json_path + ": missing (not a walk folder?)");
  const nlohmann::json j = read_json_file(json_path);
  const JsonReader r(j, json_path, "");
  r.only({"format", "format_version", "frames", "plan", "walk_params", "odometry_params", "odometry_uncertainty",
          "schedule", "observation_settings", "summary", "observations", "route_m"});
  if (r.string("format") != "floorcast-walk") r.fail_key("format", "expected \"floorcast-walk\"");
  if (r.integer("format_version", 0, 1000000) != kWalkFormatVersion) r.fail_key("format_version", "unsupported");
  WalkRecord rec;
  {
    const JsonReader p = r.object("plan");
    p.only({"name", "hash"});
    rec.plan_name = p.string("name");
    rec.plan_hash = p.string("hash");
  }
  try {
    rec.walk.params.apply_overrides(r.raw("walk_params"));
    rec.odometry_params.apply_overrides(r.raw("odometry_params"));
    rec.odometry_uncertainty = odometry_uncertainty(rec.odometry_params);
    if (j.contains("odometry_uncertainty")) rec.odometry_uncertainty.apply_overrides(r.raw("odometry_uncertainty"));
  } catch (const InputError& e) {
    throw InputError(json_path + ": " + e.what());
  }
  {
    const JsonReader s = r.object("schedule");
    s.only({"initial", "every_steps", "every_m"});
    rec.schedule.initial = s.boolean("initial");
    rec.schedule.every_steps = static_cast<int>(s.integer("every_steps", 0, 100000000));
    rec.schedule.every_m = s.number("every_m", 0.0, 1e9);
  }
  rec.observation_settings = r.raw("observation_settings");
  rec.walk.summary = summary_from(r.object("summary"));
  const nlohmann::json& route = r.raw("route_m");
  if (!route.is_array()) r.fail_key("route_m", "expected an array of [x, y]");
  for (std::size_t i = 0; i < route.size(); ++i) {
    if (!route[i].is_array() || route[i].size() != 2 || !route[i][0].is_number() || !route[i][1].is_number()) {
      r.fail_key("route_m[" + std::to_string(i) + "]", "expected [x, y]");
    }
    rec.walk.route_m.emplace_back(route[i][0].get<double>(), route[i][1].get<double>());
  }

  // steps.csv: truth and odometry, one row per sample.
  const std::string csv_path = dir + "/steps.csv";
  std::istringstream csv(read_text_file(csv_path));
  std::string line;
  if (!std::getline(csv, line) || line != kCsvHeader) throw InputError(csv_path + ":1: unexpected header (expected: " + kCsvHeader + ")");
  int number = 1;
  while (std::getline(csv, line)) {
    ++number;
    if (line.empty()) continue;
    std::vector<double> v;
    std::stringstream fields(line);
    std::string f;
    while (std::getline(fields, f, ',')) {
      char* end = nullptr;
      const double x = std::strtod(f.c_str(), &end);
      if (f.empty() || end != f.c_str() + f.size() || !std::isfinite(x)) {
        throw InputError(csv_path + ":" + std::to_string(number) + ": \"" + f + "\" is not a finite number");
      }
      v.push_back(x);
    }
    if (v.size() != 15) throw InputError(csv_path + ":" + std::to_string(number) + ": expected 15 columns");
    if (static_cast<std::size_t>(v[0]) != rec.walk.steps.size()) {
      throw InputError(csv_path + ":" + std::to_string(number) + ": step numbers must count up from 0");
    }
    WalkStep s;
    s.t_s = v[1];
    s.moving = v[2] != 0.0;
    s.T_world_body = {v[3], v[4], v[5]};
    s.step_length_m = v[6];
    rec.walk.steps.push_back(s);
    OdometryStep o;
    o.t_s = v[1];
    o.moving = v[7] != 0.0;
    o.T_prev_curr = {v[8], v[9], v[10]};
    rec.odometry.steps.push_back(o);
    rec.odometry.poses.push_back({v[11], v[12], v[13]});
  }
  if (rec.walk.steps.empty()) throw InputError(csv_path + ": no steps");

  const nlohmann::json& obs = r.raw("observations");
  if (!obs.is_array()) r.fail_key("observations", "expected an array");
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const JsonReader o(obs[i], json_path, "observations[" + std::to_string(i) + "]");
    o.only({"step", "kind", "path"});
    WalkObservation w;
    w.step = static_cast<int>(o.integer("step", 0, static_cast<long long>(rec.walk.steps.size()) - 1));
    w.kind = o.string("kind");
    if (w.kind != "perfect" && w.kind != "scan") o.fail_key("kind", "expected perfect or scan");
    w.path = o.string("path");
    if (w.path.empty() || w.path.front() == '/' || w.path.find("..") != std::string::npos) {
      o.fail_key("path", "must be a relative path inside the walk folder");
    }
    rec.observations.push_back(w);
  }
  return rec;
}

}  // namespace floorcast
