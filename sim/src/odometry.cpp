#include "floorcast/sim/odometry.hpp"

#include <cmath>

#include "floorcast/core/math.hpp"
#include "floorcast/core/fields.hpp"
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

namespace {

const FieldList<VioNoise>& vio_fields() {
  using P = VioNoise;
  static const FieldList<P> f =
      FieldList<P>("odometry vio")
          .number("scale_sigma", &P::scale_sigma, 0.0, 1.0, "scale error drawn per walk (relative sigma)")
          .number("scale_random_walk_per_sqrt_s", &P::scale_random_walk_per_sqrt_s, 0.0, 1.0, "scale random walk, 1/sqrt(s)")
          .number("yaw_bias_sigma_dps", &P::yaw_bias_sigma_dps, 0.0, 90.0, "yaw drift rate drawn per walk, deg/s")
          .number("yaw_random_walk_deg_per_sqrt_s", &P::yaw_random_walk_deg_per_sqrt_s, 0.0, 90.0, "yaw random walk, deg/sqrt(s)")
          .number("rotation_scale_sigma", &P::rotation_scale_sigma, 0.0, 1.0, "rotation scale error (relative sigma)")
          .number("translation_noise_mps", &P::translation_noise_mps, 0.0, 10.0, "translation noise, m/s");
  return f;
}

const FieldList<PdrNoise>& pdr_fields() {
  using P = PdrNoise;
  static const FieldList<P> f =
      FieldList<P>("odometry pdr")
          .number("miss_probability", &P::miss_probability, 0.0, 1.0, "probability that a step is missed")
          .number("false_step_probability", &P::false_step_probability, 0.0, 1.0, "probability of a false step")
          .number("step_length_bias_sigma", &P::step_length_bias_sigma, 0.0, 1.0, "step length bias drawn per walk (relative)")
          .number("step_length_sigma_m", &P::step_length_sigma_m, 0.0, 2.0, "step length noise per step, m")
          .number("heading_bias_sigma_deg", &P::heading_bias_sigma_deg, 0.0, 180.0, "heading bias drawn per walk, deg")
          .number("heading_random_walk_deg_per_sqrt_step", &P::heading_random_walk_deg_per_sqrt_step, 0.0, 90.0,
                  "heading random walk, deg/sqrt(step)");
  return f;
}

}  // namespace

const FieldList<OdometryParams>& OdometryParams::fields() {
  using P = OdometryParams;
  static const FieldList<P> f = FieldList<P>("odometry")
                                    .choice("model", &P::model, odometry_model_names(), "odometry model: exact, vio or pdr")
                                    .section("vio", &P::vio, vio_fields())
                                    .section("pdr", &P::pdr, pdr_fields())
                                    .unsigned_integer("seed", &P::seed, "random seed");
  return f;
}

nlohmann::ordered_json OdometryParams::to_json() const { return fields().write(*this); }

void OdometryParams::apply_overrides(const nlohmann::json& overrides) { fields().read(*this, overrides); }

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
