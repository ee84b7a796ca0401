// The PALMS particle filter (PALMS sec. III-C; facts in ../shared/reference/palms.md), with the
// initialisations of PALMS Table I and PALMS+ sec. 4.3.
//
// State per particle: position, heading drift (world heading = odometry heading + drift), weight,
// orientation-group label (the posterior slice it was drawn from), cluster membership.
// Motion per step: drift += N(0, sigma_drift); heading ~ N(odometry heading + drift, sigma_heading);
// step length = odometry step + N(0, sigma_step). The sigmas come from the odometry's stated error
// (motion_noise odometry, the default: sigma_step = the increment's along-track error, sigma_heading
// = atan(across-track error / step length), sigma_drift = the increment's rotation error, which
// persists in the particle's heading as the odometry's own does), or are PALMS' constants
// (motion_noise fixed: 0.356 m, 0.05 rad, 0.015 rad per step). Walls (a raster of the map's walls
// and glass, at 0.05 m; doorways pass) are handled per wall_handling; a particle that leaves the
// building gets weight 0. Low-variance resampling after every step; a jitter of N(0, 0.1 m) after
// the resampling of a measurement update, and (motion_noise fixed: PALMS) after every step's.
// Convergence: stage 1 when one orientation group holds > 80% of the particles; then a mean shift
// (1 m flat kernel) on that group every 5 steps; stage 2 (converged) when its largest cluster
// holds >= 50% of the group. Estimate: mean of all particles before stage 1, then the mean of the
// dominant cluster (PALMS).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "floorcast/track/tracker.hpp"

namespace floorcast {

/// How particles are drawn from the initial posterior.
enum class ParticleInit {
  kPalms,         ///< binarise all orientation heatmaps jointly at the percentile, sample uniformly in the marked cells
  kProportional,  ///< sample cells (x slices) proportionally to the posterior (PALMS+ sequential)
  kUniform,       ///< uniform position over the valid area, uniform heading (PALMS Table I baseline)
  kUniformOri,    ///< uniform position, headings from the posterior's orientation candidates (Uniform + Ori)
};

/// What a particle crossing a wall costs.
enum class WallHandling {
  kWeighted,   ///< weight x wall_weight (PALMS default, 0.3)
  kNoPass,     ///< the move is refused: the particle stays where it was
  kScheduled,  ///< weight x scheduled_weight for the first scheduled_updates steps, then 0
  kBounce,     ///< the particle stops just before the wall
};

struct ParticleFilterParams {
  int num_particles = 2000;              ///< PALMS: 2000
  ParticleInit init = ParticleInit::kPalms;
  double init_percentile = 99.0;         ///< PALMS: top 1% of cells over all orientation heatmaps
  MotionNoiseSource motion_noise = MotionNoiseSource::kOdometry;
  /// The odometry's error (motion_noise odometry): a walk states it for its odometry source; the
  /// defaults are for uncharacterised odometry (core/odometry.hpp).
  OdometryUncertainty odometry;
  /// How the odometry's bias terms spread over increments (core/odometry.hpp; measured in
  /// results/sequential.md): per increment (default) or linear growth.
  BiasGrowth bias_growth = BiasGrowth::kPerIncrement;
  double drift_sigma_rad = 0.015;        ///< motion_noise fixed: drift random walk per step (PALMS)
  double heading_sigma_rad = 0.05;       ///< motion_noise fixed: heading noise per step (PALMS)
  double step_sigma_m = 0.356;           ///< motion_noise fixed: step-length noise per step (PALMS)
  WallHandling wall_handling = WallHandling::kWeighted;
  double wall_weight = 0.3;              ///< PALMS: weighted walls x0.3
  double scheduled_weight = 0.9;         ///< PALMS: scheduled walls x0.9 ...
  int scheduled_updates = 40;            ///< ... for 40 updates, then 0
  /// PALMS: resampling jitter (after updates; after every step with motion_noise fixed)
  double jitter_sigma_m = 0.1;
  double stage1_share = 0.8;             ///< PALMS: one orientation group > 80%
  int mean_shift_every = 5;              ///< PALMS: mean shift every 5 steps in stage 2
  double stage2_share = 0.5;             ///< PALMS: largest cluster >= 50% of the group
  double mean_shift_bandwidth_m = 1.0;   ///< flat kernel radius of the mean shift
  /// Measurement updates with later posteriors: weight x (floor + (1 - floor) x value / max), so a
  /// posterior that misses the truth cannot wipe out every particle.
  double measurement_floor = 0.05;
  double wall_raster_resolution_m = 0.05;
  std::uint64_t seed = 1;

  /// The field list (core/fields.hpp): keys, ranges, docs; to_json and apply_overrides use it.
  static const FieldList<ParticleFilterParams>& fields();
  nlohmann::ordered_json to_json() const;
  /// Strict overrides (keys as in to_json); throws ParameterError naming the key.
  void apply_overrides(const nlohmann::json& overrides);
};

/// Names for the enums (also used by the CLI and scenarios).
const std::vector<std::pair<const char*, ParticleInit>>& particle_init_names();
const std::vector<std::pair<const char*, WallHandling>>& wall_handling_names();

/// A snapshot of the particles (for pictures and tests).
struct ParticleSet {
  std::vector<Pose2> poses;   ///< world position and heading
  std::vector<int> groups;    ///< orientation-group labels
};

class ParticleFilter final : public Tracker {
 public:
  ParticleFilter(const FloorPlan& plan, const ParticleFilterParams& params = {});
  ~ParticleFilter() override;

  std::string name() const override { return "pf"; }
  nlohmann::ordered_json parameters() const override { return params_.to_json(); }
  void initialise(const Posterior& posterior, const OdometryStep& first) override;
  void predict(const OdometryStep& step) override;
  using Tracker::update;
  void update(const PosteriorQuery& posterior) override;
  TrackEstimate estimate() const override;
  std::size_t state_bytes() const override;

  ParticleSet particles() const;
  const ParticleFilterParams& params() const { return params_; }
  /// Steps predicted since initialise().
  int steps() const { return step_; }
  /// True when segment a-b crosses the map's walls (the raster the filter uses).
  bool crosses_wall(const Vec2& a_m, const Vec2& b_m) const;
  /// True when p lies in a free cell inside the building.
  bool inside(const Vec2& p_m) const;

 private:
  struct Impl;
  /// Low-variance resampling; jitter_copies: then the jitter of jitter_sigma_m.
  void resample(bool jitter_copies);
  void update_convergence();
  ParticleFilterParams params_;
  std::unique_ptr<Impl> impl_;
  int step_ = 0;
  double last_t_s_ = 0.0;  ///< time of the last odometry sample (increment durations)
  /// Odometry travelled since the start or the last update (the biases' error grows with it).
  OdometryElapsed elapsed_;
};

}  // namespace floorcast
