#include "floorcast/scenarios/units.hpp"

#include <cmath>
#include <cstdio>

#include "floorcast/core/json_text.hpp"

namespace floorcast {

std::vector<WorkUnit> enumerate_units(const Scenario& scenario) {
  std::vector<WorkUnit> units;
  for (const CellSpec& cell : scenario.cells) {
    for (std::size_t b = 0; b < scenario.buildings.size(); ++b) {
      for (int p = 0; p < scenario.sampling.count; ++p) {
        WorkUnit u;
        u.cell = cell.index;
        u.building = static_cast<int>(b);
        u.point = p;
        char point[16];
        std::snprintf(point, sizeof point, "%04d", p);
        u.id = cell.id + "/" + scenario.buildings[b].label + "/" + point;
        units.push_back(std::move(u));
      }
    }
  }
  return units;
}

ShardSpec parse_shard(const std::string& text) {
  // I/N with I, N of at most 9 digits each (std::regex would recurse per character).
  const auto slash = text.find('/');
  auto number = [&](const std::string& digits, int& out) {
    if (digits.empty() || digits.size() > 9) return false;
    for (const char c : digits) {
      if (c < '0' || c > '9') return false;
    }
    out = std::stoi(digits);
    return true;
  };
  ShardSpec s;
  if (slash == std::string::npos || !number(text.substr(0, slash), s.index) || !number(text.substr(slash + 1), s.count)) {
    throw InputError("--shard: expected I/N with 0 <= I < N (e.g. 0/4), got \"" + printable_text(text, 40) + "\"");
  }
  if (s.count < 1 || s.index >= s.count)
    throw InputError("--shard: need 0 <= I < N, got \"" + text + "\"");
  return s;
}

std::vector<WorkUnit> select_shard(const std::vector<WorkUnit>& units, const ShardSpec& shard) {
  std::vector<WorkUnit> out;
  for (std::size_t k = 0; k < units.size(); ++k)
    if (static_cast<int>(k % static_cast<std::size_t>(shard.count)) == shard.index) out.push_back(units[k]);
  return out;
}

namespace {

using OJson = nlohmann::ordered_json;
using Json = nlohmann::json;

OJson pose_to_json(const PoseEstimate& p) {
  OJson j;
  j["x_m"] = p.x_m;
  j["y_m"] = p.y_m;
  j["yaw_rad"] = p.yaw_rad;
  j["score"] = p.score;
  j["position_error_m"] = p.position_error_m;
  j["yaw_error_deg"] = p.yaw_error_deg;
  return j;
}

double number(const Json& j, const char* key, const std::string& source) {
  if (!j.contains(key) || !j.at(key).is_number()) throw InputError(source + ": missing or non-numeric \"" + key + "\"");
  return j.at(key).get<double>();
}

PoseEstimate pose_from_json(const Json& j, const std::string& source) {
  PoseEstimate p;
  p.x_m = number(j, "x_m", source);
  p.y_m = number(j, "y_m", source);
  p.yaw_rad = number(j, "yaw_rad", source);
  p.score = number(j, "score", source);
  p.position_error_m = number(j, "position_error_m", source);
  p.yaw_error_deg = number(j, "yaw_error_deg", source);
  return p;
}

}  // namespace

OJson unit_to_json(const UnitResult& r) {
  OJson j;
  j["id"] = r.unit.id;
  j["cell"] = r.unit.cell;
  j["building"] = r.unit.building;
  j["point"] = r.unit.point;
  j["truth"] = {{"x_m", r.truth.x_m}, {"y_m", r.truth.y_m}, {"yaw_rad", r.truth.yaw_rad}};
  j["observation_ok"] = r.observation_ok;
  if (!r.observation_ok) j["observation_failure"] = r.observation_failure;
  j["observation"] = r.observation;
  OJson outcomes = OJson::array();
  for (const MatcherOutcome& o : r.outcomes) {
    OJson m;
    m["label"] = o.label;
    m["ok"] = o.ok;
    if (!o.ok) {
      m["failure"] = o.failure;
    } else {
      m["estimate"] = pose_to_json(o.estimate);
      OJson top = OJson::array();
      for (const PoseEstimate& p : o.top_k) top.push_back(pose_to_json(p));
      m["top_k"] = top;
    }
    outcomes.push_back(m);
  }
  j["outcomes"] = outcomes;
  if (!r.tracks.empty() || !r.walk.empty()) {
    j["walk"] = r.walk;
    OJson tracks = OJson::array();
    for (const TrackOutcome& t : r.tracks) {
      OJson tj;
      tj["label"] = t.label;
      tj["started"] = t.started;
      if (!t.started) tj["failure"] = t.failure;
      tj["observations_used"] = t.observations_used;
      tj["t_s"] = t.record.t_s;
      tj["distance_m"] = t.record.distance_m;
      tj["position_error_m"] = t.record.position_error_m;
      tj["yaw_error_deg"] = t.record.yaw_error_deg;
      tj["stage"] = t.record.stage;
      if (!t.estimate_xy_m.empty()) {
        OJson xy = OJson::array();
        for (const Vec2& p : t.estimate_xy_m) xy.push_back({p.x(), p.y()});
        tj["estimate_xy"] = xy;
      }
      tracks.push_back(tj);
    }
    j["tracks"] = tracks;
  }
  OJson timings = OJson::object();
  for (const auto& [k, v] : r.timings_s) timings[k] = v;
  OJson per_matcher = OJson::object();
  for (const MatcherOutcome& o : r.outcomes) per_matcher[o.label] = o.match_s;
  timings["match_by_matcher"] = per_matcher;
  if (!r.tracks.empty()) {
    OJson per_tracker = OJson::object();
    for (const TrackOutcome& t : r.tracks) per_tracker[t.label] = t.record.time_per_step_s;
    timings["step_by_tracker"] = per_tracker;
  }
  j["timings"] = timings;
  return j;
}

UnitResult unit_from_json(const Json& j, const std::string& source) {
  UnitResult r;
  try {
    r.unit.id = j.at("id").get<std::string>();
    r.unit.cell = j.at("cell").get<int>();
    r.unit.building = j.at("building").get<int>();
    r.unit.point = j.at("point").get<int>();
    r.truth.x_m = number(j.at("truth"), "x_m", source);
    r.truth.y_m = number(j.at("truth"), "y_m", source);
    r.truth.yaw_rad = number(j.at("truth"), "yaw_rad", source);
    r.observation_ok = j.at("observation_ok").get<bool>();
    if (!r.observation_ok) r.observation_failure = j.at("observation_failure").get<std::string>();
    r.observation = j.at("observation");
    const Json& timings = j.at("timings");
    for (auto it = timings.begin(); it != timings.end(); ++it)
      if (it.value().is_number()) r.timings_s[it.key()] = it.value().get<double>();
    for (const Json& m : j.at("outcomes")) {
      MatcherOutcome o;
      o.label = m.at("label").get<std::string>();
      o.ok = m.at("ok").get<bool>();
      if (!o.ok) {
        o.failure = m.at("failure").get<std::string>();
      } else {
        o.estimate = pose_from_json(m.at("estimate"), source);
        for (const Json& p : m.at("top_k")) o.top_k.push_back(pose_from_json(p, source));
      }
      const Json& per = timings.at("match_by_matcher");
      if (per.contains(o.label)) o.match_s = per.at(o.label).get<double>();
      r.outcomes.push_back(std::move(o));
    }
    if (j.contains("walk")) r.walk = j.at("walk");
    if (j.contains("tracks")) {
      for (const Json& t : j.at("tracks")) {
        TrackOutcome o;
        o.label = t.at("label").get<std::string>();
        o.started = t.at("started").get<bool>();
        if (!o.started) o.failure = t.at("failure").get<std::string>();
        o.observations_used = t.at("observations_used").get<int>();
        o.record.t_s = t.at("t_s").get<std::vector<double>>();
        o.record.distance_m = t.at("distance_m").get<std::vector<double>>();
        o.record.position_error_m = t.at("position_error_m").get<std::vector<double>>();
        o.record.yaw_error_deg = t.at("yaw_error_deg").get<std::vector<double>>();
        o.record.stage = t.at("stage").get<std::vector<int>>();
        o.record.failed = !o.started;
        if (t.contains("estimate_xy"))
          for (const Json& p : t.at("estimate_xy")) o.estimate_xy_m.emplace_back(p.at(0).get<double>(), p.at(1).get<double>());
        if (timings.contains("step_by_tracker") && timings.at("step_by_tracker").contains(o.label)) {
          o.record.time_per_step_s = timings.at("step_by_tracker").at(o.label).get<double>();
        }
        r.tracks.push_back(std::move(o));
      }
    }
  } catch (const Json::exception& e) {
    throw InputError(source + ": not a valid unit result: " + e.what());
  }
  return r;
}

OJson strip_timings(OJson unit_json) {
  unit_json.erase("timings");
  if (unit_json.contains("observation") && unit_json["observation"].is_object())
    unit_json["observation"].erase("timings");
  return unit_json;
}

}  // namespace floorcast
