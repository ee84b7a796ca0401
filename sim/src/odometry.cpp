#include "floorcast/sim/odometry.hpp"

#include <cmath>

#include "floorcast/core/math.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/core/random.hpp"

namespace floorcast {
namespace {

enum OdometryStream : std::uint64_t {
  kStreamWalkConstants = 201,
  kStreamIncrement = 202,
};

OdometryTrack finish(const Walk& walk, std::vector<OdometryStep> steps) {
  OdometryTrack t;
  t.steps = std::move(steps);
  t.poses = integrate_odometry(walk.steps.front().T_world_body, t.steps);
  return t;
}

OdometryTrack exact(const Walk& walk) {
  std::vector<OdometryStep> steps;
  for (std::size_t i = 0; i < walk.steps.size(); ++i) {
    OdometryStep s;
    s.t_s = walk.steps[i].t_s;
    s.moving = walk.steps[i].moving;
    if (i > 0) s.T_prev_curr = relative_pose(walk.steps[i - 1].T_world_body, walk.steps[i].T_world_body);
    steps.push_back(s);
  }
  return finish(walk, std::move(steps));
}

OdometryTrack vio(const Walk& walk, const OdometryParams& p) {
  const VioNoise& n = p.vio;
  const CounterRng walk_rng(p.seed, kStreamWalkConstants);
  double scale = 1.0 + n.scale_sigma * walk_rng.normal(0);
  const double yaw_bias = deg_to_rad(n.yaw_bias_sigma_dps) * walk_rng.normal(1);
  const double rotation_scale = 1.0 + n.rotation_scale_sigma * walk_rng.normal(2);
  std::vector<OdometryStep> steps;
  for (std::size_t i = 0; i < walk.steps.size(); ++i) {
    OdometryStep s;
    s.t_s = walk.steps[i].t_s;
    s.moving = true;  // VIO reports a pose every frame, standing or not
    if (i > 0) {
      const CounterRng rng(p.seed, kStreamIncrement, i);
      const double dt = walk.steps[i].t_s - walk.steps[i - 1].t_s;
      const Pose2 truth = relative_pose(walk.steps[i - 1].T_world_body, walk.steps[i].T_world_body);
      scale += n.scale_random_walk_per_sqrt_s * std::sqrt(dt) * rng.normal(0);
      const double noise = n.translation_noise_mps * dt;
      s.T_prev_curr.x_m = scale * truth.x_m + noise * rng.normal(1);
      s.T_prev_curr.y_m = scale * truth.y_m + noise * rng.normal(2);
      s.T_prev_curr.yaw_rad = wrap_angle_rad(rotation_scale * truth.yaw_rad + yaw_bias * dt +
                                             deg_to_rad(n.yaw_random_walk_deg_per_sqrt_s) * std::sqrt(dt) * rng.normal(3));
    }
    steps.push_back(s);
  }
  return finish(walk, std::move(steps));
}

OdometryTrack pdr(const Walk& walk, const OdometryParams& p) {
  const PdrNoise& n = p.pdr;
  const CounterRng walk_rng(p.seed, kStreamWalkConstants);
  const double length_bias = n.step_length_bias_sigma * walk_rng.normal(0);
  const double heading_bias = deg_to_rad(n.heading_bias_sigma_deg) * walk_rng.normal(1);
  // Mean true step length (a false step is taken at the detector's typical length).
  double walked = 0.0;
  int moving = 0;
  for (const WalkStep& w : walk.steps) {
    walked += w.step_length_m;
    moving += w.moving ? 1 : 0;
  }
  const double typical = moving > 0 ? walked / moving : 0.65;
  std::vector<OdometryStep> steps;
  double heading_error = heading_bias;
  double last_heading = walk.steps.front().T_world_body.yaw_rad + heading_error;
  for (std::size_t i = 0; i < walk.steps.size(); ++i) {
    OdometryStep s;
    s.t_s = walk.steps[i].t_s;
    s.moving = false;
    if (i > 0) {
      const CounterRng rng(p.seed, kStreamIncrement, i);
      const WalkStep& w = walk.steps[i];
      heading_error += deg_to_rad(n.heading_random_walk_deg_per_sqrt_step) * rng.normal(0);
      const double heading = w.T_world_body.yaw_rad + heading_error;
      const bool detected = w.moving ? rng.uniform(1) >= n.miss_probability : rng.uniform(1) < n.false_step_probability;
      const double dyaw = wrap_angle_rad(heading - last_heading);
      last_heading = heading;
      s.T_prev_curr.yaw_rad = dyaw;
      if (detected) {
        const double true_len = w.moving ? w.step_length_m : typical;
        const double len = std::max(0.0, true_len * (1.0 + length_bias) + n.step_length_sigma_m * rng.normal(2));
        s.T_prev_curr.x_m = len * std::cos(dyaw);
        s.T_prev_curr.y_m = len * std::sin(dyaw);
        s.moving = true;
      }
    }
    steps.push_back(s);
  }
  return finish(walk, std::move(steps));
}

}  // namespace

const std::vector<std::pair<const char*, OdometryModel>>& odometry_model_names() {
  static const std::vector<std::pair<const char*, OdometryModel>> names = {
      {"exact", OdometryModel::kExact}, {"vio", OdometryModel::kVio}, {"pdr", OdometryModel::kPdr}};
  return names;
}

nlohmann::ordered_json OdometryParams::to_json() const {
  nlohmann::ordered_json j;
  j["model"] = enum_name(model, odometry_model_names());
  j["vio"] = {{"scale_sigma", vio.scale_sigma},
              {"scale_random_walk_per_sqrt_s", vio.scale_random_walk_per_sqrt_s},
              {"yaw_bias_sigma_dps", vio.yaw_bias_sigma_dps},
              {"yaw_random_walk_deg_per_sqrt_s", vio.yaw_random_walk_deg_per_sqrt_s},
              {"rotation_scale_sigma", vio.rotation_scale_sigma},
              {"translation_noise_mps", vio.translation_noise_mps}};
  j["pdr"] = {{"miss_probability", pdr.miss_probability},
              {"false_step_probability", pdr.false_step_probability},
              {"step_length_bias_sigma", pdr.step_length_bias_sigma},
              {"step_length_sigma_m", pdr.step_length_sigma_m},
              {"heading_bias_sigma_deg", pdr.heading_bias_sigma_deg},
              {"heading_random_walk_deg_per_sqrt_step", pdr.heading_random_walk_deg_per_sqrt_step}};
  j["seed"] = seed;
  return j;
}

void OdometryParams::apply_overrides(const nlohmann::json& overrides) {
  ParamReader r(overrides, "odometry");
  r.read_enum("model", model, odometry_model_names());
  r.section("vio", [&](ParamReader& v) {
    v.read("scale_sigma", vio.scale_sigma, 0.0, 1.0);
    v.read("scale_random_walk_per_sqrt_s", vio.scale_random_walk_per_sqrt_s, 0.0, 1.0);
    v.read("yaw_bias_sigma_dps", vio.yaw_bias_sigma_dps, 0.0, 90.0);
    v.read("yaw_random_walk_deg_per_sqrt_s", vio.yaw_random_walk_deg_per_sqrt_s, 0.0, 90.0);
    v.read("rotation_scale_sigma", vio.rotation_scale_sigma, 0.0, 1.0);
    v.read("translation_noise_mps", vio.translation_noise_mps, 0.0, 10.0);
  });
  r.section("pdr", [&](ParamReader& d) {
    d.read("miss_probability", pdr.miss_probability, 0.0, 1.0);
    d.read("false_step_probability", pdr.false_step_probability, 0.0, 1.0);
    d.read("step_length_bias_sigma", pdr.step_length_bias_sigma, 0.0, 1.0);
    d.read("step_length_sigma_m", pdr.step_length_sigma_m, 0.0, 2.0);
    d.read("heading_bias_sigma_deg", pdr.heading_bias_sigma_deg, 0.0, 180.0);
    d.read("heading_random_walk_deg_per_sqrt_step", pdr.heading_random_walk_deg_per_sqrt_step, 0.0, 90.0);
  });
  r.read("seed", seed);
  r.finish();
}

OdometryUncertainty odometry_uncertainty(const OdometryParams& p) {
  OdometryUncertainty u;
  u.translation_per_m = u.translation_m_per_s = u.translation_m_per_step = 0.0;
  u.rotation_per_rad = u.rotation_rad_per_s = u.rotation_rad_per_sqrt_s = u.rotation_rad_per_step = 0.0;
  switch (p.model) {
    case OdometryModel::kExact: break;
    case OdometryModel::kVio:
      u.translation_per_m = p.vio.scale_sigma;
      u.translation_m_per_s = p.vio.translation_noise_mps;
      u.rotation_per_rad = p.vio.rotation_scale_sigma;
      u.rotation_rad_per_s = deg_to_rad(p.vio.yaw_bias_sigma_dps);
      u.rotation_rad_per_sqrt_s = deg_to_rad(p.vio.yaw_random_walk_deg_per_sqrt_s);
      break;
    case OdometryModel::kPdr: {
      constexpr double kTypicalStepM = 0.7;
      u.translation_per_m = p.pdr.step_length_bias_sigma;
      u.translation_m_per_step = std::sqrt(p.pdr.step_length_sigma_m * p.pdr.step_length_sigma_m +
                                           p.pdr.miss_probability * kTypicalStepM * kTypicalStepM);
      u.rotation_rad_per_step = deg_to_rad(p.pdr.heading_random_walk_deg_per_sqrt_step);
      break;
    }
  }
  return u;
}

OdometryTrack simulate_odometry(const Walk& walk, const OdometryParams& params) {
  if (walk.steps.empty()) return {};
  switch (params.model) {
    case OdometryModel::kExact: return exact(walk);
    case OdometryModel::kVio: return vio(walk, params);
    case OdometryModel::kPdr: return pdr(walk, params);
  }
  return exact(walk);
}

}  // namespace floorcast
