// The built-in tracker table (explicit, like the matcher registry: static self-registration is
// dropped by the linker from static libraries).
#include <algorithm>

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

struct Entry {
  const char* name;
  std::unique_ptr<Tracker> (*make)(const FloorPlan&, const nlohmann::json&);
  nlohmann::ordered_json (*resolve)(const nlohmann::json&);
};

constexpr Entry kTrackers[] = {
    {"hist", &build<HistogramFilterParams, HistogramFilter>, &resolve<HistogramFilterParams>},
    {"pf", &build<ParticleFilterParams, ParticleFilter>, &resolve<ParticleFilterParams>},
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

}  // namespace floorcast
