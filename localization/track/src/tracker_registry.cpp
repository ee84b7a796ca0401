// The built-in tracker table (explicit, like the matcher registry: static self-registration is
// dropped by the linker from static libraries).
#include <algorithm>
#include <sstream>

#include "floorcast/track/histogram_filter.hpp"
#include "floorcast/track/particle_filter.hpp"
#include "floorcast/track/tracker.hpp"

namespace floorcast {
namespace {

template <class P, class T>
std::unique_ptr<Tracker> build(const FloorPlan& plan, const nlohmann::json& overrides) {
  P p;
  p.apply_overrides(overrides);
  return std::make_unique<T>(plan, p);
}

template <class P>
nlohmann::ordered_json resolve(const nlohmann::json& overrides) {
  P p;
  p.apply_overrides(overrides);
  return p.to_json();
}

std::string number(const nlohmann::ordered_json& p, const char* key) {
  std::ostringstream s;
  s << p.at(key).get<double>();
  return s.str();
}

std::string pf_convergence(const nlohmann::ordered_json& p) {
  return "PALMS two-stage: one orientation group holds > " + number(p, "stage1_share") +
         " of the particles, then the largest mean-shift cluster (" + number(p, "mean_shift_bandwidth_m") +
         " m) of that group holds >= " + number(p, "stage2_share") + " of it";
}

std::string hist_convergence(const nlohmann::ordered_json& p) {
  return "belief mass within " + number(p, "support_radius_m") + " m and " + number(p, "support_yaw_deg") +
         " deg of the estimate >= " + number(p, "converged_mass");
}

struct Entry {
  const char* name;
  std::unique_ptr<Tracker> (*make)(const FloorPlan&, const nlohmann::json&);
  nlohmann::ordered_json (*resolve)(const nlohmann::json&);
  std::string (*convergence)(const nlohmann::ordered_json&);
};

constexpr Entry kTrackers[] = {
    {"hist", &build<HistogramFilterParams, HistogramFilter>, &resolve<HistogramFilterParams>, &hist_convergence},
    {"pf", &build<ParticleFilterParams, ParticleFilter>, &resolve<ParticleFilterParams>, &pf_convergence},
};

const Entry& find(const std::string& name) {
  for (const Entry& e : kTrackers) {
    if (name == e.name) return e;
  }
  std::string known;
  for (const std::string& n : tracker_names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown tracker \"" + name + "\" (known: " + known + ")");
}

}  // namespace

const std::vector<std::pair<const char*, MotionNoiseSource>>& motion_noise_names() {
  static const std::vector<std::pair<const char*, MotionNoiseSource>> n = {{"odometry", MotionNoiseSource::kOdometry},
                                                                           {"fixed", MotionNoiseSource::kFixed}};
  return n;
}

nlohmann::json with_odometry(const nlohmann::json& overrides, const OdometryUncertainty& odometry) {
  nlohmann::json out = overrides.is_object() ? overrides : nlohmann::json::object();
  nlohmann::json section = odometry.to_json();
  if (out.contains("odometry")) {
    if (!out.at("odometry").is_object()) return out;
    section.merge_patch(out.at("odometry"));
  }
  out["odometry"] = section;
  return out;
}

std::unique_ptr<Tracker> make_tracker(const std::string& name, const FloorPlan& plan, const nlohmann::json& overrides) {
  return find(name).make(plan, overrides);
}

nlohmann::ordered_json resolve_tracker_parameters(const std::string& name, const nlohmann::json& overrides) {
  return find(name).resolve(overrides);
}

std::vector<std::string> tracker_names() {
  std::vector<std::string> names;
  for (const Entry& e : kTrackers) names.emplace_back(e.name);
  std::sort(names.begin(), names.end());
  return names;
}

std::string describe_convergence(const std::string& name, const nlohmann::json& overrides) {
  const Entry& e = find(name);
  return e.convergence(e.resolve(overrides));
}

}  // namespace floorcast
