#include "floorcast/track/particle_filter.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "floorcast/core/math.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/core/random.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "wall_raster.hpp"

namespace floorcast {
namespace {

enum PfStream : std::uint64_t {
  kStreamInit = 301,
  kStreamMotion = 302,
  kStreamResample = 303,
  kStreamJitter = 304,
};

}  // namespace

const std::vector<std::pair<const char*, ParticleInit>>& particle_init_names() {
  static const std::vector<std::pair<const char*, ParticleInit>> n = {{"palms", ParticleInit::kPalms},
                                                                      {"proportional", ParticleInit::kProportional},
                                                                      {"uniform", ParticleInit::kUniform},
                                                                      {"uniform-ori", ParticleInit::kUniformOri}};
  return n;
}

const std::vector<std::pair<const char*, WallHandling>>& wall_handling_names() {
  static const std::vector<std::pair<const char*, WallHandling>> n = {{"weighted", WallHandling::kWeighted},
                                                                      {"no-pass", WallHandling::kNoPass},
                                                                      {"scheduled", WallHandling::kScheduled},
                                                                      {"bounce", WallHandling::kBounce}};
  return n;
}

const FieldList<ParticleFilterParams>& ParticleFilterParams::fields() {
  using P = ParticleFilterParams;
  static const FieldList<P> f =
      FieldList<P>("tracker pf")
          .integer("num_particles", &P::num_particles, 1, 10000000, "particles (PALMS: 2000)")
          .choice("init", &P::init, particle_init_names(),
                  "initialisation (PALMS Table I, PALMS+ sec. 4.3): top-percentile cells, proportional to the "
                  "posterior, uniform, uniform position with the posterior's orientations")
          .number("init_percentile", &P::init_percentile, 0.0, 100.0, "palms init: percentile of the heatmaps (PALMS: 99)")
          .choice("motion_noise", &P::motion_noise, motion_noise_names(),
                  "motion noise from the odometry's stated error (odometry) or PALMS' constants per step (fixed)")
          .section("odometry", &P::odometry, OdometryUncertainty::fields())
          .choice("bias_growth", &P::bias_growth, bias_growth_names(),
                  "how the odometry's bias terms spread over increments: per increment or linear growth")
          .number("drift_sigma_rad", &P::drift_sigma_rad, 0.0, 10.0, "motion_noise fixed: heading drift random walk per step, rad (PALMS: 0.015)")
          .number("heading_sigma_rad", &P::heading_sigma_rad, 0.0, 10.0, "motion_noise fixed: heading noise per step, rad (PALMS: 0.05)")
          .number("step_sigma_m", &P::step_sigma_m, 0.0, 10.0, "motion_noise fixed: step-length noise per step, m (PALMS: 0.356)")
          .choice("wall_handling", &P::wall_handling, wall_handling_names(), "what a particle crossing a wall costs")
          .number("wall_weight", &P::wall_weight, 0.0, 1.0, "weighted walls: weight factor (PALMS: 0.3)")
          .number("scheduled_weight", &P::scheduled_weight, 0.0, 1.0, "scheduled walls: weight factor at first (PALMS: 0.9)")
          .integer("scheduled_updates", &P::scheduled_updates, 0, 100000000,
                   "scheduled walls: steps with scheduled_weight, then 0 (PALMS: 40)")
          .number("jitter_sigma_m", &P::jitter_sigma_m, 0.0, 10.0, "resampling jitter, m (PALMS: 0.1)")
          .number("stage1_share", &P::stage1_share, 0.0, 1.0, "stage 1: one orientation group holds more than this (PALMS: 0.8)")
          .integer("mean_shift_every", &P::mean_shift_every, 1, 100000, "mean shift every N steps in stage 1 (PALMS: 5)")
          .number("stage2_share", &P::stage2_share, 0.0, 1.0, "stage 2: largest cluster share of the group (PALMS: 0.5)")
          .number("mean_shift_bandwidth_m", &P::mean_shift_bandwidth_m, 0.01, 100.0, "flat kernel radius of the mean shift, m")
          .number("measurement_floor", &P::measurement_floor, 0.0, 1.0,
                  "measurement update: weight x (floor + (1 - floor) x value / max)")
          .number("wall_raster_resolution_m", &P::wall_raster_resolution_m, 0.005, 1.0, "wall raster resolution, m")
          .unsigned_integer("seed", &P::seed, "random seed");
  return f;
}

nlohmann::ordered_json ParticleFilterParams::to_json() const { return fields().write(*this); }

void ParticleFilterParams::apply_overrides(const nlohmann::json& overrides) { fields().read(*this, overrides); }

struct ParticleFilter::Impl {
  WallRaster walls;
  // Particles (structure of arrays) and the resampling buffers (allocated once).
  std::vector<double> x, y, drift, w;
  std::vector<int> group, cluster;
  std::vector<double> x2, y2, drift2;
  std::vector<int> group2, cluster2;
  std::vector<double> cumulative;
  double odo_heading = 0.0;  ///< integrated odometry heading since initialise()
  int stage = 0;
  int dominant_group = -1;
  double dominant_share = 0.0;
  double cluster_share = 0.0;
  bool degenerate = false;
  int num_groups = 1;
};

ParticleFilter::ParticleFilter(const FloorPlan& plan, const ParticleFilterParams& params)
    : params_(params), impl_(std::make_unique<Impl>()) {
  impl_->walls = make_wall_raster(plan, params_.wall_raster_resolution_m);
  const std::size_t n = static_cast<std::size_t>(params_.num_particles);
  for (auto* v : {&impl_->x, &impl_->y, &impl_->drift, &impl_->w, &impl_->x2, &impl_->y2, &impl_->drift2, &impl_->cumulative}) {
    v->assign(n, 0.0);
  }
  for (auto* v : {&impl_->group, &impl_->cluster, &impl_->group2, &impl_->cluster2}) v->assign(n, 0);
}

ParticleFilter::~ParticleFilter() = default;

bool ParticleFilter::crosses_wall(const Vec2& a, const Vec2& b) const { return impl_->walls.crosses(a, b, nullptr); }
bool ParticleFilter::inside(const Vec2& p) const { return impl_->walls.inside(p); }

std::size_t ParticleFilter::state_bytes() const {
  return impl_->walls.bytes() + impl_->x.size() * (8 * sizeof(double) + 4 * sizeof(int));
}

void ParticleFilter::initialise(const Posterior& post, const OdometryStep& first) {
  Impl& d = *impl_;
  last_t_s_ = first.t_s;
  elapsed_ = {};
  const std::size_t n = d.x.size();
  const GridSpec& g = post.grid;
  const int S = post.num_slices();
  if (S == 0) throw InputError("particle filter: the initial posterior has no orientation slices");
  d.odo_heading = 0.0;
  d.stage = 0;
  d.dominant_group = -1;
  d.degenerate = false;
  step_ = 0;
  const CounterRng rng(params_.seed, kStreamInit);
  // Cells (slice, row, col) the particles are drawn from, with their weights.
  std::vector<std::int64_t> cells;
  std::vector<double> weights;
  const bool uniform = params_.init == ParticleInit::kUniform || params_.init == ParticleInit::kUniformOri;
  if (!uniform) {
    std::vector<float> values;
    for (int s = 0; s < S; ++s) {
      const cv::Mat& m = post.scores[static_cast<std::size_t>(s)];
      for (int r = 0; r < m.rows; ++r) {
        const float* row = m.ptr<float>(r);
        for (int c = 0; c < m.cols; ++c)
          if (row[c] > 0.0f) values.push_back(row[c]);
      }
    }
    if (values.empty()) {
      // An empty posterior: nothing to start from. Report it instead of inventing a start.
      throw InputError("particle filter: the initial posterior is empty (every cell scored 0): no pose to start from");
    }
    float threshold = 0.0f;
    if (params_.init == ParticleInit::kPalms) {
      // Binarise all orientation heatmaps jointly at the percentile of the scored cells.
      const std::size_t k = std::min(values.size() - 1, static_cast<std::size_t>(params_.init_percentile / 100.0 * values.size()));
      std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
      threshold = values[k];
    }
    for (int s = 0; s < S; ++s) {
      const cv::Mat& m = post.scores[static_cast<std::size_t>(s)];
      for (int r = 0; r < m.rows; ++r) {
        const float* row = m.ptr<float>(r);
        for (int c = 0; c < m.cols; ++c) {
          if (!(row[c] > 0.0f) || row[c] < threshold) continue;
          cells.push_back((static_cast<std::int64_t>(s) * g.height_px + r) * g.width_px + c);
          weights.push_back(params_.init == ParticleInit::kPalms ? 1.0 : row[c]);
        }
      }
    }
  } else {
    // Uniform over the valid area of the filter's wall raster (sampled on the posterior's grid).
    for (int r = 0; r < g.height_px; ++r)
      for (int c = 0; c < g.width_px; ++c) {
        if (!d.walls.inside(g.cell_center_m(r, c))) continue;
        cells.push_back(static_cast<std::int64_t>(r) * g.width_px + c);
        weights.push_back(1.0);
      }
    if (cells.empty()) throw InputError("particle filter: the plan has no free cell to start in");
  }
  std::vector<double> cdf(weights.size());
  std::partial_sum(weights.begin(), weights.end(), cdf.begin());
  const double total = cdf.back();
  d.num_groups = uniform && params_.init == ParticleInit::kUniform ? 36 : S;
  for (std::size_t i = 0; i < n; ++i) {
    const CounterRng pr = rng.child(i);
    const double u = pr.uniform(0) * total;
    const std::size_t k = std::min(cdf.size() - 1, static_cast<std::size_t>(std::lower_bound(cdf.begin(), cdf.end(), u) - cdf.begin()));
    const std::int64_t cell = cells[k];
    const int c = static_cast<int>(cell % g.width_px);
    const int r = static_cast<int>((cell / g.width_px) % g.height_px);
    const int s = static_cast<int>(cell / (static_cast<std::int64_t>(g.width_px) * g.height_px));
    const Vec2 centre = g.cell_center_m(r, c);
    d.x[i] = centre.x() + (pr.uniform(1) - 0.5) * g.resolution_m_per_px;
    d.y[i] = centre.y() + (pr.uniform(2) - 0.5) * g.resolution_m_per_px;
    if (params_.init == ParticleInit::kUniform) {
      d.drift[i] = wrap_angle_rad(kTwoPi * pr.uniform(3));
      d.group[i] = std::min(35, static_cast<int>((d.drift[i] + kPi) / kTwoPi * 36.0));
    } else if (params_.init == ParticleInit::kUniformOri) {
      const int slice = std::min(S - 1, static_cast<int>(pr.uniform(3) * S));
      d.drift[i] = post.yaw_rad[static_cast<std::size_t>(slice)];
      d.group[i] = slice;
    } else {
      d.drift[i] = post.yaw_rad[static_cast<std::size_t>(s)];
      d.group[i] = s;
    }
    d.w[i] = 1.0 / static_cast<double>(n);
    d.cluster[i] = 0;
  }
  update_convergence();
}

void ParticleFilter::predict(const OdometryStep& step) {
  Impl& d = *impl_;
  ++step_;
  const double heading_before = d.odo_heading;
  d.odo_heading = wrap_angle_rad(d.odo_heading + step.T_prev_curr.yaw_rad);
  const double len = step.T_prev_curr.position_m().norm();
  const bool moves = step.moving && len > 0.0;
  const double direction = heading_before + std::atan2(step.T_prev_curr.y_m, step.T_prev_curr.x_m);
  const double dt = step.t_s - last_t_s_;
  last_t_s_ = step.t_s;
  const ParticleFilterParams& p = params_;
  // This increment's noise: from the odometry's stated error, or PALMS' constants. A standing
  // increment still drifts in heading by the odometry's time terms (odometry mode).
  double step_sigma = p.step_sigma_m, heading_sigma = p.heading_sigma_rad, drift_sigma = p.drift_sigma_rad;
  bool drift_standing = false;
  if (p.motion_noise == MotionNoiseSource::kOdometry) {
    const IncrementNoise e = increment_noise(p.odometry, step, dt, params_.bias_growth, elapsed_);
    step_sigma = e.along_m;
    heading_sigma = len > 0.0 ? std::atan2(e.across_m, len) : 0.0;
    drift_sigma = e.rotation_rad;
    drift_standing = true;
  }
  const CounterRng rng(params_.seed, kStreamMotion, static_cast<std::uint64_t>(step_));
  const std::size_t n = d.x.size();
  const bool scheduled_zero = p.wall_handling == WallHandling::kScheduled && step_ > p.scheduled_updates;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      if (!moves && !drift_standing) continue;
      const CounterRng pr = rng.child(i);
      d.drift[i] = wrap_angle_rad(d.drift[i] + drift_sigma * pr.normal(0));
      if (!moves) continue;
      const double h = direction + d.drift[i] + heading_sigma * pr.normal(1);
      const double dist = len + step_sigma * pr.normal(2);
      const Vec2 from(d.x[i], d.y[i]);
      Vec2 to = from + dist * Vec2(std::cos(h), std::sin(h));
      Vec2 stop = from;
      if (d.walls.crosses(from, to, &stop)) {
        switch (p.wall_handling) {
          case WallHandling::kWeighted: d.w[i] *= p.wall_weight; break;
          case WallHandling::kNoPass: to = from; break;
          case WallHandling::kScheduled: d.w[i] *= scheduled_zero ? 0.0 : p.scheduled_weight; break;
          case WallHandling::kBounce: to = stop; break;
        }
      }
      if (!d.walls.inside(to)) d.w[i] = 0.0;  // left the building
      d.x[i] = to.x();
      d.y[i] = to.y();
    }
  });
  // PALMS jitters after every step's resampling; with the odometry's own noise the jitter is left
  // to the resampling after a measurement (its purpose: spreading the copies a likelihood made),
  // since a per-step jitter is a fixed motion noise of its own (0.1 m per step: a 1.1 m random
  // walk over 120 steps, whatever the odometry says).
  resample(p.motion_noise == MotionNoiseSource::kFixed);
  update_convergence();
}

void ParticleFilter::update(const PosteriorQuery& post) {
  Impl& d = *impl_;
  const double best = post.max_score();
  if (!(best > 0.0) || post.num_slices() == 0) {
    d.degenerate = true;  // an empty posterior carries no information: the weights stay
    return;
  }
  // The posterior's cell of every particle (its grid cell, the slice nearest its heading), each
  // distinct cell asked once: converged particles share a few cells.
  const std::size_t n = d.x.size();
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;  // (cell key, particle)
  keyed.reserve(n);
  const GridSpec& g = post.grid();
  for (std::size_t i = 0; i < n; ++i) {
    int r = 0, c = 0;
    if (!g.world_to_cell({d.x[i], d.y[i]}, r, c)) continue;
    const int slice = post.nearest_slice(d.odo_heading + d.drift[i]);
    const std::uint64_t key = (static_cast<std::uint64_t>(slice) * static_cast<std::uint64_t>(g.height_px) + static_cast<std::uint64_t>(r)) *
                                  static_cast<std::uint64_t>(g.width_px) + static_cast<std::uint64_t>(c);
    keyed.emplace_back(key, static_cast<std::uint32_t>(i));
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<PosteriorCell> cells;
  std::vector<std::uint32_t> cell_of(keyed.size());
  for (std::size_t k = 0; k < keyed.size(); ++k) {
    if (k == 0 || keyed[k].first != keyed[k - 1].first) {
      const std::uint64_t key = keyed[k].first;
      const std::uint64_t W = static_cast<std::uint64_t>(g.width_px), H = static_cast<std::uint64_t>(g.height_px);
      cells.push_back({static_cast<int>(key / (W * H)), static_cast<int>((key / W) % H), static_cast<int>(key % W)});
    }
    cell_of[k] = static_cast<std::uint32_t>(cells.size() - 1);
  }
  std::vector<float> scores;
  post.scores(cells, scores);
  // Particles outside the grid weigh the floor alone.
  std::vector<double> value(n, 0.0);
  for (std::size_t k = 0; k < keyed.size(); ++k) value[keyed[k].second] = scores[cell_of[k]] / best;
  for (std::size_t i = 0; i < n; ++i) d.w[i] *= params_.measurement_floor + (1.0 - params_.measurement_floor) * value[i];
  elapsed_ = {};  // the biases' error restarts from the pose this update told
  resample(true);
  update_convergence();
}

void ParticleFilter::resample(bool jitter_copies) {
  Impl& d = *impl_;
  const std::size_t n = d.x.size();
  double total = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    total += d.w[i];
    d.cumulative[i] = total;
  }
  d.degenerate = !(total > 0.0);
  if (d.degenerate) {
    // Every particle died (all left the map or hit walls under scheduled/zero weights): keep
    // them, with equal weights, and report it.
    std::fill(d.w.begin(), d.w.end(), 1.0 / static_cast<double>(n));
    return;
  }
  // Low-variance (systematic) resampling: one uniform offset, n equally spaced pointers.
  const CounterRng rng(params_.seed, kStreamResample, static_cast<std::uint64_t>(step_));
  const double stride = total / static_cast<double>(n);
  double u = rng.uniform(0) * stride;
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i, u += stride) {
    while (k + 1 < n && d.cumulative[k] < u) ++k;
    d.x2[i] = d.x[k];
    d.y2[i] = d.y[k];
    d.drift2[i] = d.drift[k];
    d.group2[i] = d.group[k];
    d.cluster2[i] = d.cluster[k];
  }
  std::swap(d.x, d.x2);
  std::swap(d.y, d.y2);
  std::swap(d.drift, d.drift2);
  std::swap(d.group, d.group2);
  std::swap(d.cluster, d.cluster2);
  std::fill(d.w.begin(), d.w.end(), 1.0 / static_cast<double>(n));
  // Jitter; a jitter into or through a wall is not taken.
  const CounterRng jitter(params_.seed, kStreamJitter, static_cast<std::uint64_t>(step_));
  const double sigma = jitter_copies ? params_.jitter_sigma_m : 0.0;
  if (sigma > 0.0) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const CounterRng pr = jitter.child(i);
        const Vec2 from(d.x[i], d.y[i]);
        const Vec2 to = from + sigma * Vec2(pr.normal(0), pr.normal(1));
        if (d.walls.inside(to) && !d.walls.crosses(from, to, nullptr)) {
          d.x[i] = to.x();
          d.y[i] = to.y();
        }
      }
    });
  }
}

namespace {

/// Flat-kernel mean shift of 2D points with binned seeding (seeds at the centres of occupied
/// bandwidth-sized bins), neighbours from a hash grid. Returns, per point, the index of its mode
/// (modes closer than half a bandwidth are merged), and the modes.
std::vector<int> mean_shift(const std::vector<Vec2>& pts, double bandwidth, std::vector<Vec2>& modes) {
  const double cell = bandwidth;
  auto key = [cell](const Vec2& p) {
    const std::int64_t cx = static_cast<std::int64_t>(std::floor(p.x() / cell));
    const std::int64_t cy = static_cast<std::int64_t>(std::floor(p.y() / cell));
    return (cx << 32) ^ (cy & 0xffffffff);
  };
  std::unordered_map<std::int64_t, std::vector<int>> grid;
  for (std::size_t i = 0; i < pts.size(); ++i) grid[key(pts[i])].push_back(static_cast<int>(i));
  // The points of every bin stored contiguously (x and y apart, in the bins' index order), so the
  // neighbour sums of the mean-shift iterations (the particle filter's largest cost, profiled)
  // stream through memory without branches; the sums run in the same order as over the indices.
  struct Bin {
    std::vector<double> x, y;
  };
  std::unordered_map<std::int64_t, Bin> bins;
  for (const auto& kv : grid) {
    Bin& b = bins[kv.first];
    for (int i : kv.second) {
      b.x.push_back(pts[static_cast<std::size_t>(i)].x());
      b.y.push_back(pts[static_cast<std::size_t>(i)].y());
    }
  }
  const double bw2 = bandwidth * bandwidth;
  auto mean_near = [&](const Vec2& c, int& count) {
    double sx = 0.0, sy = 0.0;
    count = 0;
    const std::int64_t cx = static_cast<std::int64_t>(std::floor(c.x() / cell));
    const std::int64_t cy = static_cast<std::int64_t>(std::floor(c.y() / cell));
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        auto it = bins.find(((cx + dx) << 32) ^ ((cy + dy) & 0xffffffff));
        if (it == bins.end()) continue;
        const Bin& b = it->second;
        const std::size_t m = b.x.size();
        for (std::size_t k = 0; k < m; ++k) {
          const double ex = b.x[k] - c.x(), ey = b.y[k] - c.y();
          const bool in = ex * ex + ey * ey <= bw2;
          sx += in ? b.x[k] : 0.0;
          sy += in ? b.y[k] : 0.0;
          count += in ? 1 : 0;
        }
      }
    return count > 0 ? Vec2(Vec2(sx, sy) / count) : c;
  };
  // Seeds: bin centroids, in a fixed order (sorted keys) for determinism.
  std::vector<std::int64_t> keys;
  for (const auto& kv : grid) keys.push_back(kv.first);
  std::sort(keys.begin(), keys.end());
  // Each seed climbs on its own (in parallel); the modes are merged in seed order: the same
  // modes at any thread count.
  std::vector<Vec2> climbed(keys.size());
  tbb::parallel_for(std::size_t{0}, keys.size(), [&](std::size_t s) {
    const std::vector<int>& members = grid.at(keys[s]);
    Vec2 c = Vec2::Zero();
    for (int i : members) c += pts[static_cast<std::size_t>(i)];
    c /= static_cast<double>(members.size());
    for (int it = 0; it < 30; ++it) {
      int count = 0;
      const Vec2 next = mean_near(c, count);
      const bool done = (next - c).norm() < 1e-3 * bandwidth;
      c = next;
      if (done) break;
    }
    climbed[s] = c;
  });
  modes.clear();
  for (const Vec2& c : climbed) {
    bool merged = false;
    for (const Vec2& m : modes) merged = merged || (m - c).norm() < 0.5 * bandwidth;
    if (!merged) modes.push_back(c);
  }
  std::vector<int> label(pts.size(), -1);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    double best = bandwidth * bandwidth;
    for (std::size_t m = 0; m < modes.size(); ++m) {
      const double d2 = (pts[i] - modes[m]).squaredNorm();
      if (d2 <= best) {
        best = d2;
        label[i] = static_cast<int>(m);
      }
    }
  }
  return label;
}

}  // namespace

void ParticleFilter::update_convergence() {
  Impl& d = *impl_;
  const std::size_t n = d.x.size();
  std::vector<int> counts(static_cast<std::size_t>(std::max(d.num_groups, 1)), 0);
  for (int g : d.group) {
    if (g >= 0 && g < static_cast<int>(counts.size())) ++counts[static_cast<std::size_t>(g)];
  }
  const auto top = std::max_element(counts.begin(), counts.end());
  d.dominant_group = static_cast<int>(top - counts.begin());
  d.dominant_share = static_cast<double>(*top) / static_cast<double>(n);
  if (d.stage == 0 && d.dominant_share > params_.stage1_share) d.stage = 1;
  if (d.stage >= 1 && step_ % params_.mean_shift_every == 0) {
    std::vector<Vec2> pts;
    std::vector<std::size_t> index;
    for (std::size_t i = 0; i < n; ++i) {
      if (d.group[i] != d.dominant_group) continue;
      pts.emplace_back(d.x[i], d.y[i]);
      index.push_back(i);
    }
    std::vector<Vec2> modes;
    const std::vector<int> label = mean_shift(pts, params_.mean_shift_bandwidth_m, modes);
    std::vector<int> size(modes.size(), 0);
    for (int l : label)
      if (l >= 0) ++size[static_cast<std::size_t>(l)];
    const int best = modes.empty() ? -1 : static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
    std::fill(d.cluster.begin(), d.cluster.end(), 0);
    for (std::size_t k = 0; k < pts.size(); ++k) {
      if (label[k] == best && best >= 0) d.cluster[index[k]] = 1;
    }
    d.cluster_share = pts.empty() || best < 0 ? 0.0 : static_cast<double>(size[static_cast<std::size_t>(best)]) / pts.size();
    if (d.cluster_share >= params_.stage2_share) d.stage = 2;
  }
}

TrackEstimate ParticleFilter::estimate() const {
  const Impl& d = *impl_;
  TrackEstimate e;
  e.stage = d.stage;
  e.degenerate = d.degenerate;
  // Before stage 1: the mean of all particles; then the mean of the dominant cluster (PALMS).
  Vec2 sum = Vec2::Zero();
  double sx = 0.0, sy = 0.0;
  std::size_t count = 0;
  const bool use_cluster = d.stage >= 1 && std::count(d.cluster.begin(), d.cluster.end(), 1) > 0;
  for (std::size_t i = 0; i < d.x.size(); ++i) {
    if (use_cluster && d.cluster[i] != 1) continue;
    sum += Vec2(d.x[i], d.y[i]);
    const double h = d.odo_heading + d.drift[i];
    sx += std::cos(h);
    sy += std::sin(h);
    ++count;
  }
  if (count == 0) return e;
  e.pose = {sum.x() / count, sum.y() / count, std::atan2(sy, sx)};
  e.support = use_cluster ? static_cast<double>(count) / d.x.size() : d.dominant_share;
  return e;
}

ParticleSet ParticleFilter::particles() const {
  ParticleSet s;
  for (std::size_t i = 0; i < impl_->x.size(); ++i) {
    s.poses.push_back({impl_->x[i], impl_->y[i], wrap_angle_rad(impl_->odo_heading + impl_->drift[i])});
    s.groups.push_back(impl_->group[i]);
  }
  return s;
}

}  // namespace floorcast
