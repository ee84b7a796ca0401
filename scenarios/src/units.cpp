#include "floorcast/scenarios/units.hpp"

#include <cmath>
#include <cstdio>

#include "floorcast/core/fields.hpp"
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
      // Negatives: the points of the other buildings in turn (b+1, b+2, ... wrapping around),
      // each building's points in order.
      const int others = static_cast<int>(scenario.buildings.size()) - 1;
      for (int k = 0; k < scenario.sampling.negatives && others > 0; ++k) {
        WorkUnit u;
        u.cell = cell.index;
        u.building = static_cast<int>(b);
        u.point = scenario.sampling.count + k;
        u.source_building = static_cast<int>((b + 1 + static_cast<std::size_t>(k % others)) % scenario.buildings.size());
        u.source_point = (k / others) % scenario.sampling.count;
        char point[16];
        std::snprintf(point, sizeof point, "n%04d", k);
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

constexpr double kAny = 1e300;  // numbers in unit files: any finite value

const FieldList<PoseEstimate>& pose_estimate_fields() {
  using P = PoseEstimate;
  static const FieldList<P> f = FieldList<P>("pose estimate")
                                    .number("x_m", &P::x_m, -kAny, kAny, "world x, m")
                                    .number("y_m", &P::y_m, -kAny, kAny, "world y, m")
                                    .number("yaw_rad", &P::yaw_rad, -kAny, kAny, "world heading, rad")
                                    .number("score", &P::score, -kAny, kAny, "the matcher's score")
                                    .number("position_error_m", &P::position_error_m, -kAny, kAny, "distance to the truth, m")
                                    .number("yaw_error_deg", &P::yaw_error_deg, -kAny, kAny, "heading error, deg");
  return f;
}

const FieldList<Pose2>& truth_fields() {
  static const FieldList<Pose2> f = FieldList<Pose2>("truth")
                                        .number("x_m", &Pose2::x_m, -kAny, kAny, "world x, m")
                                        .number("y_m", &Pose2::y_m, -kAny, kAny, "world y, m")
                                        .number("yaw_rad", &Pose2::yaw_rad, -kAny, kAny, "world heading, rad");
  return f;
}

/// Where a negative sample's observation was made.
const FieldList<WorkUnit>& negative_source_fields() {
  static const FieldList<WorkUnit> f =
      FieldList<WorkUnit>("negative sample")
          .integer("source_building", &WorkUnit::source_building, 0, 1 << 30, "the building the observation was made in")
          .integer("source_point", &WorkUnit::source_point, 0, 1 << 30, "its observation point there");
  return f;
}

const FieldList<WorkUnit>& work_unit_fields() {
  static const FieldList<WorkUnit> f =
      FieldList<WorkUnit>("work unit")
          .text("id", &WorkUnit::id, "<cell id>/<building label>/<point, 4 digits> (negatives n<k, 4 digits>)")
          .integer("cell", &WorkUnit::cell, 0, 1 << 30, "sweep cell index")
          .integer("building", &WorkUnit::building, 0, 1 << 30, "building index (the plan matched against)")
          .integer("point", &WorkUnit::point, 0, 1 << 30, "observation point index (negatives after the positives)")
          .section("negative", [](auto& u) -> auto& { return u; }, negative_source_fields())
          .optional([](const WorkUnit& u) { return u.negative(); });
  return f;
}

const FieldList<MatcherOutcome>& matcher_outcome_fields() {
  using M = MatcherOutcome;
  static const FieldList<M> f =
      FieldList<M>("matcher outcome")
          .text("label", &M::label, "the matcher's label in the scenario")
          .flag("ok", &M::ok, "false: no estimate (reason in failure)")
          .text("failure", &M::failure, "why there is no estimate")
          .optional([](const M& m) { return !m.ok; })
          .flag("error", &M::error, "true: the method itself misbehaved (an external method; run again on resume)")
          .optional([](const M& m) { return m.error; })
          .section("estimate", &M::estimate, pose_estimate_fields())
          .optional([](const M& m) { return m.ok; })
          .list("top_k", &M::top_k, pose_estimate_fields())
          .optional([](const M& m) { return m.ok; });
  return f;
}

const FieldList<TrackOutcome>& track_outcome_fields() {
  using T = TrackOutcome;
  static const FieldList<T> f =
      FieldList<T>("track outcome")
          .text("label", &T::label, "the tracker's label in the scenario")
          .flag("started", &T::started, "false: no track (reason in failure)")
          .text("failure", &T::failure, "why there is no track")
          .optional([](const T& t) { return !t.started || t.error; })
          .flag("error", &T::error, "true: the tracker or its matcher misbehaved (an external method; run again on resume)")
          .optional([](const T& t) { return t.error; })
          .integer("observations_used", &T::observations_used, 0, 1 << 30, "observations whose posteriors were applied")
          .series("t_s", [](auto& t) -> auto& { return t.record.t_s; }, "time per step, s")
          .series("distance_m", [](auto& t) -> auto& { return t.record.distance_m; }, "distance walked since the start, m")
          .series("position_error_m", [](auto& t) -> auto& { return t.record.position_error_m; }, "position error per step, m")
          .series("yaw_error_deg", [](auto& t) -> auto& { return t.record.yaw_error_deg; }, "heading error per step, deg")
          .integers("stage", [](auto& t) -> auto& { return t.record.stage; }, "convergence stage per step")
          .custom(
              "estimate_xy",
              [](OJson& j, const T& t) {
                if (t.estimate_xy_m.empty()) return;
                OJson xy = OJson::array();
                for (const Vec2& p : t.estimate_xy_m) xy.push_back({p.x(), p.y()});
                j["estimate_xy"] = xy;
              },
              [](ParamReader& r, T& t) {
                if (!r.optional("estimate_xy")) return;
                Json xy;
                r.read("estimate_xy", xy);
                if (!xy.is_array()) r.fail("estimate_xy", "expected an array of [x, y]");
                for (std::size_t i = 0; i < xy.size(); ++i) {
                  const Json& p = xy[i];
                  if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) {
                    r.fail("estimate_xy[" + std::to_string(i) + "]", "expected [x, y]");
                  }
                  t.estimate_xy_m.emplace_back(p[0].get<double>(), p[1].get<double>());
                }
              },
              "[[x, y], ...]", "estimated position per step, m (rounded to 1 mm; absent in older runs)")
          .custom(
              "mode_position_error_m",
              [](OJson& j, const T& t) {
                if (!t.mode_position_error_m.empty()) j["mode_position_error_m"] = t.mode_position_error_m;
              },
              [](ParamReader& r, T& t) {
                if (!r.optional("mode_position_error_m")) return;
                Json modes;
                r.read("mode_position_error_m", modes);
                if (!modes.is_array()) r.fail("mode_position_error_m", "expected an array of arrays of numbers");
                for (std::size_t i = 0; i < modes.size(); ++i) {
                  const std::string key = "mode_position_error_m[" + std::to_string(i) + "]";
                  if (!modes[i].is_array()) r.fail(key, "expected an array of numbers");
                  std::vector<double> step;
                  for (const Json& v : modes[i]) {
                    if (!v.is_number()) r.fail(key, "expected numbers");
                    step.push_back(v.get<double>());
                  }
                  t.mode_position_error_m.push_back(std::move(step));
                }
              },
              "[[error, ...], ...]",
              "per step, the position error of each of the belief's peaks, best first, m (trackers reporting modes only)");
  return f;
}

/// Timings live under "timings" only (strip_timings removes them): the unit's stage times, each
/// matcher's match time and each tracker's time per step.
void write_timings(OJson& j, const UnitResult& r) {
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
}

void read_timings(ParamReader& r, UnitResult& u) {
  Json timings;
  r.read("timings", timings);
  if (!timings.is_object()) r.fail("timings", "expected an object");
  for (auto it = timings.begin(); it != timings.end(); ++it)
    if (it.value().is_number()) u.timings_s[it.key()] = it.value().get<double>();
  const Json per = timings.value("match_by_matcher", Json::object());
  for (MatcherOutcome& o : u.outcomes)
    if (per.contains(o.label) && per.at(o.label).is_number()) o.match_s = per.at(o.label).get<double>();
  const Json steps = timings.value("step_by_tracker", Json::object());
  for (TrackOutcome& t : u.tracks)
    if (steps.contains(t.label) && steps.at(t.label).is_number()) t.record.time_per_step_s = steps.at(t.label).get<double>();
}

bool sequential(const UnitResult& r) { return !r.tracks.empty() || !r.walk.empty(); }

const FieldList<UnitResult>& unit_fields() {
  using U = UnitResult;
  static const FieldList<U> f =
      FieldList<U>("unit result")
          .flatten(&U::unit, work_unit_fields())
          .section("truth", &U::truth, truth_fields())
          .flag("observation_ok", &U::observation_ok, "false: the observation failed (reason in observation_failure)")
          .text("observation_failure", &U::observation_failure, "why the observation failed")
          .optional([](const U& u) { return !u.observation_ok; })
          .json("observation", &U::observation, "observation summary and the observation module's diagnostics")
          .list("outcomes", &U::outcomes, matcher_outcome_fields())
          .json("walk", &U::walk, "sequential scenarios: the walk's summary")
          .optional(sequential)
          .list("tracks", &U::tracks, track_outcome_fields())
          .optional(sequential)
          .custom("timings", write_timings, read_timings, "object",
                  "seconds per stage, match_by_matcher, step_by_tracker (excluded from comparisons)");
  return f;
}

}  // namespace

OJson unit_to_json(const UnitResult& r) { return unit_fields().write(r); }

UnitResult unit_from_json(const Json& j, const std::string& source) {
  UnitResult r;
  unit_fields().read_record(r, j, source);
  for (TrackOutcome& t : r.tracks) t.record.failed = !t.started;
  return r;
}

bool unit_has_errors(const UnitResult& r) {
  for (const MatcherOutcome& o : r.outcomes)
    if (o.error) return true;
  for (const TrackOutcome& t : r.tracks)
    if (t.error) return true;
  return false;
}

OJson strip_timings(OJson unit_json) {
  unit_json.erase("timings");
  if (unit_json.contains("observation") && unit_json["observation"].is_object())
    unit_json["observation"].erase("timings");
  return unit_json;
}

}  // namespace floorcast
