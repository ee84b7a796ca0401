#include "floorcast/sim/walk_io.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "floorcast/core/fields.hpp"
#include "floorcast/core/file_io.hpp"
#include "floorcast/core/json_reader.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/trajectory_io.hpp"

namespace floorcast {

const FieldList<WalkSummary>& walk_summary_fields() {
  using S = WalkSummary;
  static const FieldList<S> f =
      FieldList<S>("walk summary")
          .number("length_m", &S::length_m, 0.0, 1e9, "length walked, m")
          .number("duration_s", &S::duration_s, 0.0, 1e9, "duration, s")
          .number("speed_mps", &S::speed_mps, 0.0, 100.0, "walking speed, m/s")
          .number("cadence_hz", &S::cadence_hz, 0.0, 100.0, "step frequency, Hz")
          .integer("pauses", &S::pauses, 0, 100000000, "pauses")
          .number("total_turn_deg", &S::total_turn_deg, 0.0, 1e12, "sum of absolute heading changes, deg")
          .number("transitional_share", &S::transitional_share, 0.0, 1.0, "share of samples in transitional space")
          .integer("goals", &S::goals, 0, 100000000, "goals walked to")
          .number("longest_straight_m", &S::longest_straight_m, 0.0, 1e9, "longest stretch without turning 20 deg, m");
  return f;
}

namespace {

using OJson = nlohmann::ordered_json;
constexpr int kWalkFormatVersion = 1;
const char* const kCsvHeader =
    "step,t_s,moving,x_m,y_m,yaw_rad,step_length_m,odom_moving,odom_dx_m,odom_dy_m,odom_dyaw_rad,odom_x_m,odom_y_m,"
    "odom_yaw_rad,observation";


const FieldList<WalkObservation>& observation_fields() {
  using O = WalkObservation;
  static const FieldList<O> f =
      FieldList<O>("walk observation")
          .integer("step", &O::step, 0, 100000000, "the step the observation is made at")
          .text("kind", &O::kind, "perfect (observation.json) or scan (a scan folder)")
          .text("path", &O::path, "relative to the walk folder")
          .check([](const O& o, const ParamReader& r) {
            if (o.kind != "perfect" && o.kind != "scan") r.fail("kind", "expected perfect or scan");
            if (o.path.empty() || o.path.front() == '/' || o.path.find("..") != std::string::npos) {
              r.fail("path", "must be a relative path inside the walk folder");
            }
          });
  return f;
}

/// walk.json (the steps themselves are in steps.csv, the trajectories in the .tum files).
const FieldList<WalkRecord>& walk_json_fields() {
  using R = WalkRecord;
  static const FieldList<R> plan = FieldList<R>("plan")
                                       .text("name", &R::plan_name, "the plan's name")
                                       .text("hash", &R::plan_hash, "hex FNV-1a of the plan's canonical JSON");
  auto params = [](const char* key, auto get) {
    return std::make_pair(
        [key, get](OJson& j, const R& r) { j[key] = get(r).to_json(); },
        [key, get](ParamReader& reader, R& r) {
          nlohmann::json overrides;
          reader.read(key, overrides);
          try {
            get(r).apply_overrides(overrides);
          } catch (const ParameterError& e) {
            reader.fail(std::string(key) + "." + e.key(), e.what());
          }
        });
  };
  const auto walk_params = params("walk_params", [](auto& r) -> auto& { return r.walk.params; });
  const auto odometry_params = params("odometry_params", [](auto& r) -> auto& { return r.odometry_params; });
  static const FieldList<R> f =
      FieldList<R>("walk")
          .custom(
              "format", [](OJson& j, const R&) { j["format"] = "floorcast-walk"; },
              [](ParamReader& r, R&) {
                std::string format;
                r.read("format", format);
                if (format != "floorcast-walk") r.fail("format", "expected \"floorcast-walk\"");
              },
              "text", "\"floorcast-walk\"")
          .custom(
              "format_version", [](OJson& j, const R&) { j["format_version"] = kWalkFormatVersion; },
              [](ParamReader& r, R&) {
                int version = 0;
                r.read("format_version", version, 0, 1000000);
                if (version != kWalkFormatVersion) r.fail("format_version", "unsupported");
              },
              "integer", "format version (1)")
          .custom(
              "frames",
              [](OJson& j, const R&) {
                j["frames"] = "world: plan metres, yaw CCW from +x; increments T_prev_curr in the previous body frame";
              },
              [](ParamReader& r, R&) {
                std::string frames;
                r.read("frames", frames);
              },
              "text", "the frames, in words")
          .section("plan", [](auto& r) -> auto& { return r; }, plan)
          .custom("walk_params", walk_params.first, walk_params.second, "object", "the walk's parameters")
          .custom("odometry_params", odometry_params.first, odometry_params.second, "object", "the odometry's parameters")
          .custom(
              "odometry_uncertainty",
              [](OJson& j, const R& r) { j["odometry_uncertainty"] = r.odometry_uncertainty.to_json(); },
              [](ParamReader& reader, R& r) {
                r.odometry_uncertainty = odometry_uncertainty(r.odometry_params);
                if (!reader.optional("odometry_uncertainty")) return;  // older walks: derived from the model
                nlohmann::json overrides;
                reader.read("odometry_uncertainty", overrides);
                try {
                  r.odometry_uncertainty.apply_overrides(overrides);
                } catch (const ParameterError& e) {
                  reader.fail("odometry_uncertainty." + e.key(), e.what());
                }
              },
              "object", "the odometry's error as trackers should assume it (absent: derived from odometry_params)")
          .section("schedule", &R::schedule, schedule_fields())
          .json("observation_settings", &R::observation_settings, "sensor preset, perfect-observer parameters, ...")
          .section("summary", [](auto& r) -> auto& { return r.walk.summary; }, walk_summary_fields())
          .list("observations", &R::observations, observation_fields())
          .custom(
              "route_m",
              [](OJson& j, const R& r) {
                OJson route = OJson::array();
                for (const Vec2& p : r.walk.route_m) route.push_back({p.x(), p.y()});
                j["route_m"] = route;
              },
              [](ParamReader& reader, R& r) {
                nlohmann::json route;
                reader.read("route_m", route);
                if (!route.is_array()) reader.fail("route_m", "expected an array of [x, y]");
                for (std::size_t i = 0; i < route.size(); ++i) {
                  if (!route[i].is_array() || route[i].size() != 2 || !route[i][0].is_number() || !route[i][1].is_number()) {
                    reader.fail("route_m[" + std::to_string(i) + "]", "expected [x, y]");
                  }
                  r.walk.route_m.emplace_back(route[i][0].get<double>(), route[i][1].get<double>());
                }
              },
              "[[x, y], ...]", "the planned path the walker followed, m");
  return f;
}

}  // namespace

void save_walk(const std::string& dir, const WalkRecord& rec) {
  create_directories_or_throw(dir);
  const Walk& w = rec.walk;
  if (rec.odometry.steps.size() != w.steps.size()) throw InputError(dir + ": odometry and walk have different lengths");
  write_text_file_atomic(dir + "/walk.json", walk_json_fields().write(rec).dump(2) + "\n");

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

namespace {

/// The name of column k of steps.csv.
std::string csv_column_name(int k) {
  std::stringstream header(kCsvHeader);
  std::string name;
  for (int i = 0; i <= k && std::getline(header, name, ','); ++i) {
  }
  return name;
}

}  // namespace

WalkRecord load_walk(const std::string& dir) {
  const std::string json_path = dir + "/walk.json";
  if (!std::filesystem::is_directory(dir)) throw InputError(dir + ": not a walk folder (no such directory)");
  // Missing: not a walk folder; a FIFO, device or folder there is named by read_text_file.
  if (std::error_code ec; !std::filesystem::exists(json_path, ec)) throw InputError(json_path + ": missing (not a walk folder?)");
  const nlohmann::json j = read_json_file(json_path);
  WalkRecord rec;
  walk_json_fields().read_record(rec, j, json_path);

  // steps.csv: truth and odometry, one row per sample.
  const std::string csv_path = dir + "/steps.csv";
  std::string csv_text = read_text_file(csv_path);
  strip_utf8_bom(csv_text);  // a spreadsheet's byte-order mark
  std::istringstream csv(csv_text);
  std::string line;
  // Windows line ends (a file edited in a spreadsheet) are line ends.
  auto next_line = [&csv, &line] {
    if (!std::getline(csv, line)) return false;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  };
  if (!next_line() || line != kCsvHeader) {
    throw InputError(csv_path + ":1: unexpected header \"" + printable_text(line, 80) + "\" (expected: " + kCsvHeader + ")");
  }
  int number = 1;
  while (next_line()) {
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
    // Finite is not enough: an odometry step of 1e308 m overflows the integrated track to inf and
    // every error to NaN. Positions and steps stay within the coordinate range of plans.
    static const int kLengthColumns[] = {3, 4, 6, 8, 9, 11, 12};
    for (const int k : kLengthColumns) {
      if (std::abs(v[static_cast<std::size_t>(k)]) > kMaxAbsCoordinateM) {
        std::ostringstream os;
        os << csv_path << ":" << number << ": column " << (k + 1) << " (" << csv_column_name(k) << ") = " << v[static_cast<std::size_t>(k)]
           << " m is beyond +-" << kMaxAbsCoordinateM << " m";
        throw InputError(os.str());
      }
    }
    static const int kAngleColumns[] = {5, 10, 13};
    for (const int k : kAngleColumns) {
      if (std::abs(v[static_cast<std::size_t>(k)]) > 1.0e6) {
        std::ostringstream os;
        os << csv_path << ":" << number << ": column " << (k + 1) << " (" << csv_column_name(k) << ") = " << v[static_cast<std::size_t>(k)]
           << " rad is beyond +-1e6 rad";
        throw InputError(os.str());
      }
    }
    if (v[1] < 0.0 || v[1] > 1.0e12) {
      std::ostringstream os;
      os << csv_path << ":" << number << ": t_s = " << v[1] << " s is outside [0, 1e12]";
      throw InputError(os.str());
    }
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

  for (std::size_t i = 0; i < rec.observations.size(); ++i) {
    if (static_cast<std::size_t>(rec.observations[i].step) >= rec.walk.steps.size()) {
      throw ParameterError(json_path + ": observations[" + std::to_string(i) + "].step: value " +
                               std::to_string(rec.observations[i].step) + " outside [0, " +
                               std::to_string(rec.walk.steps.size() - 1) + "]",
                           "observations[" + std::to_string(i) + "].step");
    }
  }
  return rec;
}

}  // namespace floorcast
