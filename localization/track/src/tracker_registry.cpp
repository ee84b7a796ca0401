// The built-in tracker table (explicit, like the matcher registry: static self-registration is
// dropped by the linker from static libraries). A new tracker is one entry here: its parameter
// struct P has a field list (P::fields(), core/fields.hpp) and, when it draws random numbers, a
// `seed` member.
#include <algorithm>
#include <sstream>
#include <type_traits>

#include "floorcast/track/histogram_filter.hpp"
#include "floorcast/track/multires_histogram_filter.hpp"
#include "floorcast/track/particle_filter.hpp"
#include "floorcast/track/tracker.hpp"

namespace floorcast {
namespace {

template <class P, class = void>
struct HasSeed : std::false_type {};
template <class P>
struct HasSeed<P, std::void_t<decltype(std::declval<P&>().seed)>> : std::true_type {};

/// A tracker configuration of parameter type P building tracker type T.
template <class P, class T>
class Config final : public TrackerConfig {
 public:
  Config(const char* name, P params) : name_(name), params_(std::move(params)) {}
  std::string name() const override { return name_; }
  nlohmann::ordered_json parameters() const override { return P::fields().write(params_); }
  std::shared_ptr<const TrackerConfig> with_seed(std::uint64_t seed) const override {
    P p = params_;
    if constexpr (HasSeed<P>::value) p.seed = seed;
    (void)seed;
    return std::make_shared<Config>(name_, std::move(p));
  }
  std::optional<std::uint64_t> seed() const override {
    if constexpr (HasSeed<P>::value) return params_.seed;
    return std::nullopt;
  }
  std::unique_ptr<Tracker> build(const FloorPlan& plan) const override { return std::make_unique<T>(plan, params_); }

 private:
  const char* name_;
  P params_;
};

template <class P, class T>
std::shared_ptr<const TrackerConfig> parse(const char* name, const nlohmann::json& overrides) {
  P p;
  P::fields().read(p, overrides);
  return std::make_shared<Config<P, T>>(name, std::move(p));
}

template <class P>
std::vector<FieldInfo> describe() {
  return P::fields().describe(P{});
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
  std::shared_ptr<const TrackerConfig> (*parse)(const char*, const nlohmann::json&);
  std::vector<FieldInfo> (*describe)();
  std::string (*convergence)(const nlohmann::ordered_json&);
  const char* matcher;  ///< the matcher its paper pairs it with (the default where none is named)
};

constexpr Entry kTrackers[] = {
    {"hist", &parse<HistogramFilterParams, HistogramFilter>, &describe<HistogramFilterParams>, &hist_convergence, "ray"},
    {"hist_mr", &parse<MultiResolutionHistogramFilterParams, MultiResolutionHistogramFilter>,
     &describe<MultiResolutionHistogramFilterParams>, &hist_convergence, "ray"},
    {"pf", &parse<ParticleFilterParams, ParticleFilter>, &describe<ParticleFilterParams>, &pf_convergence, "kernel"},
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

std::shared_ptr<const TrackerConfig> make_tracker_config(const std::string& name, const nlohmann::json& overrides) {
  const Entry& e = find(name);
  return e.parse(e.name, overrides);
}

std::unique_ptr<Tracker> make_tracker(const std::string& name, const FloorPlan& plan, const nlohmann::json& overrides) {
  return make_tracker_config(name, overrides)->build(plan);
}

std::vector<FieldInfo> tracker_parameter_fields(const std::string& name) { return find(name).describe(); }

std::vector<std::string> tracker_names() {
  std::vector<std::string> names;
  for (const Entry& e : kTrackers) names.emplace_back(e.name);
  std::sort(names.begin(), names.end());
  return names;
}

std::string default_tracker_matcher(const std::string& name) { return find(name).matcher; }

std::string describe_convergence(const std::string& name, const nlohmann::json& overrides) {
  const Entry& e = find(name);
  return e.convergence(e.parse(e.name, overrides)->parameters());
}

}  // namespace floorcast
