#include "floorcast/bench/match_bench.hpp"

#include <fftw3.h>
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

#include "floorcast/bench/modes_equivalence.hpp"
#include "floorcast/core/fields.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/timing.hpp"
#include "floorcast/match/kernel_matcher.hpp"
#include "floorcast/match/plan_raster.hpp"
#include "floorcast/match/bev_matcher.hpp"
#include "floorcast/match/ray_matcher.hpp"
#include "floorcast/observe/bev_predictor.hpp"
#include "floorcast/scenarios/sampling.hpp"
#include "floorcast/sim/perfect_observation.hpp"

namespace floorcast {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kAnyValue = 1e300;
constexpr int kManyItems = 1 << 30;

/// CPU (process, all threads) and wall seconds of one call.
struct Cost {
  double cpu_s = 0.0;
  double wall_s = 0.0;
};

template <class F>
Cost measure(F&& f) {
  const double c0 = process_cpu_s();
  const auto t0 = Clock::now();
  f();
  return {process_cpu_s() - c0, std::chrono::duration<double>(Clock::now() - t0).count()};
}

struct Series {
  std::vector<double> cpu, wall;
  void add(const Cost& c) {
    cpu.push_back(c.cpu_s);
    wall.push_back(c.wall_s);
  }
  MatchBenchCost cost() const { return {cpu.empty() ? 0.0 : median(cpu), wall.empty() ? 0.0 : median(wall)}; }
};

/// Median of the per-observation ratios a / b.
double median_ratio(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> r;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    if (b[i] > 0.0) r.push_back(a[i] / b[i]);
  return r.empty() ? 0.0 : median(r);
}

std::map<std::string, double> median_of(const std::vector<std::map<std::string, double>>& all) {
  std::map<std::string, std::vector<double>> v;
  for (const auto& m : all)
    for (const auto& [k, x] : m) v[k].push_back(x);
  std::map<std::string, double> out;
  for (auto& [k, x] : v) out[k] = median(x);
  return out;
}

/// The bounded search's scored share from its (median) counters. Both bounded searches report
/// it; a missing counter is a broken matcher, not a value to invent.
double scored_share(const std::map<std::string, double>& counters, const char* matcher) {
  const auto it = counters.find("cells_scored_share");
  if (it == counters.end())
    throw std::logic_error(std::string("bench match: the ") + matcher + " matcher's search reported no cells_scored_share");
  return it->second;
}

nlohmann::ordered_json to_json(const std::map<std::string, double>& m) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [k, v] : m) j[k] = v;
  return j;
}

/// One full-size FFTW r2c + c2r pair on rows x cols (FFTW_ESTIMATE, as the correlator plans),
/// median CPU seconds over repeats: the least one correlation of an exhaustive FFT posterior costs.
double fft_pair_cpu_s(int rows, int cols, int repeats) {
  const int half = cols / 2 + 1;
  float* real = fftwf_alloc_real(static_cast<std::size_t>(rows) * cols);
  fftwf_complex* spec = fftwf_alloc_complex(static_cast<std::size_t>(rows) * half);
  fftwf_plan fwd = fftwf_plan_dft_r2c_2d(rows, cols, real, spec, FFTW_ESTIMATE);
  fftwf_plan inv = fftwf_plan_dft_c2r_2d(rows, cols, spec, real, FFTW_ESTIMATE);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (std::size_t i = 0; i < static_cast<std::size_t>(rows) * cols; ++i) real[i] = u(rng);
  std::vector<double> t;
  for (int k = 0; k < repeats; ++k) {
    const double a = thread_cpu_s();
    fftwf_execute(fwd);
    fftwf_execute(inv);
    t.push_back(thread_cpu_s() - a);
  }
  fftwf_destroy_plan(fwd);
  fftwf_destroy_plan(inv);
  fftwf_free(real);
  fftwf_free(spec);
  return median(t);
}

/// Largest |FFT heatmap - direct correlation| over sampled cells of one (yaw, scale = 1) heatmap:
/// the single-precision round-off actually seen on this plan.
double fft_error_probe(const FloorPlan& plan, const Observation2D& obs, double yaw, int cells, std::uint64_t seed) {
  KernelMatcherParams p;
  p.scales = {1.0};
  p.zero_below = 0.0;
  p.modes_search = ModesSearch::kPosterior;
  const KernelMatcher m(plan, p);
  const MatchResult r = m.match_yaws(obs, {yaw});
  std::vector<std::pair<int, int>> valid;
  for (int row = 0; row < m.grid().height_px; ++row)
    for (int col = 0; col < m.grid().width_px; ++col)
      if (m.valid_mask().at<std::uint8_t>(row, col)) valid.emplace_back(row, col);
  std::mt19937_64 rng(seed);
  double worst = 0.0;
  for (int i = 0; i < cells && !valid.empty(); ++i) {
    const auto [row, col] = valid[std::uniform_int_distribution<std::size_t>(0, valid.size() - 1)(rng)];
    const double s = m.cell_score(obs, yaw, 1.0, row, col);
    worst = std::max(worst, std::abs(std::max(s, 0.0) - r.posterior.scores[0].at<float>(row, col)));
  }
  return worst;
}

/// The observers' poses of params.region: uniform over `valid`, or transitional (the scenarios'
/// sampling: rooms of the transitional kinds, 0.5 m clearance, on `grid`'s resolution).
std::vector<Pose2> bench_poses(const FloorPlan& plan, const cv::Mat& valid, const GridSpec& grid,
                               const MatchBenchParams& params) {
  if (params.region == "transitional") {
    return sample_observation_poses(plan, params.observations, params.seed, 0, 0.5, grid.resolution_m_per_px, plan.rooms,
                                    {"transitional"});
  }
  if (params.region != "uniform") throw InputError("bench match: region must be uniform or transitional");
  return sample_valid_poses(valid, grid, params.observations, params.seed);
}

}  // namespace

std::vector<double> pad_yaws(std::vector<double> yaws, std::size_t n) {
  for (int k = 0; k < 36 && yaws.size() < n; ++k) {
    const double y = 2.0 * kPi * (k + 0.5) / 36.0;
    bool near = false;
    for (double e : yaws) near = near || angle_distance_rad(e, y) < 5.0 * kPi / 180.0;
    if (!near) yaws.push_back(y);
  }
  return yaws;
}

MatchBenchResult bench_match(const FloorPlan& plan, const MatchBenchParams& params) {
  MatchBenchResult out;
  out.plan = plan.name;
  out.threads = tbb::info::default_concurrency();
  out.observations = params.observations;
  out.region = params.region;
  out.top_k = params.top_k;

  if (params.kernel) {
    const auto t0 = Clock::now();
    const KernelMatcher kernel(plan);
    const double precompute_wall = std::chrono::duration<double>(Clock::now() - t0).count();
    const GridSpec& g = kernel.grid();
    out.kernel_measured = true;
    out.grid_width_px = g.width_px;
    out.grid_height_px = g.height_px;
    out.valid_cells = cv::countNonZero(kernel.valid_mask());
    PerfectObservationParams pp;
    pp.num_rays = 0;
    pp.max_range_m = kernel.params().max_range_m;
    pp.blocking = kernel.blocking();
    const PerfectObserver observer(plan, pp);
    std::vector<Observation2D> observations;
    for (const Pose2& p : bench_poses(plan, kernel.valid_mask(), kernel.grid(), params)) observations.push_back(observer.observe(p));

    const int S = static_cast<int>(kernel.params().scales.size());
    MatchRequest full;
    full.top_k = params.top_k;
    (void)kernel.match(observations.front(), MatchRequest::modes(params.top_k));  // warm-up: thread pool
    Series modes, argmax, posterior, own_modes;
    std::vector<double> slices, own_slices;
    std::vector<std::map<std::string, double>> counters, modes_stages, posterior_stages;
    ModesEquivalenceResult eq;
    ModesEquivalenceParams ep;
    ep.top_k = params.top_k;
    for (std::size_t i = 0; i < observations.size(); ++i) {
      const Observation2D& obs = observations[i];
      const std::vector<double> own = kernel.yaw_candidates(obs);
      own_slices.push_back(static_cast<double>(own.size()));
      own_modes.add(measure([&] { (void)kernel.match(obs, MatchRequest::modes(params.top_k)); }));
      const std::vector<double> yaws =
          params.kernel_orientations > 0 ? pad_yaws(own, static_cast<std::size_t>(params.kernel_orientations)) : own;
      slices.push_back(static_cast<double>(yaws.size()));
      MatchResult bb, fft;
      modes.add(measure([&] { bb = kernel.match_yaws(obs, yaws, MatchRequest::modes(params.top_k)); }));
      argmax.add(measure([&] { (void)kernel.match_yaws(obs, yaws, MatchRequest::modes(1)); }));
      counters.push_back(bb.counters);
      modes_stages.push_back(bb.stage_s);
      if (params.posteriors) {
        posterior.add(measure([&] { fft = kernel.match_yaws(obs, yaws, full); }));
        posterior_stages.push_back(fft.stage_s);
        compare_modes(kernel, obs, bb, fft, ep, "observation " + std::to_string(i), eq);
      }
    }
    const double pair = fft_pair_cpu_s(kernel.fft_rows(), kernel.fft_cols(), 5);
    const double O = median(slices);
    KernelMatchBench& k = out.kernel;
    k.orientations = O;
    k.scales = S;
    k.modes = modes.cost();
    k.argmax = argmax.cost();
    k.own_candidates = median(own_slices);
    k.modes_own_candidates = own_modes.cost();
    k.precompute_wall_s = precompute_wall;
    k.precompute_mb = kernel.precompute_bytes() / 1e6;
    k.search_maps_mb = kernel.search_bytes() / 1e6;
    k.fft_cols = kernel.fft_cols();
    k.fft_rows = kernel.fft_rows();
    k.fft_pair_cpu_s = pair;
    k.fft_floor_cpu_s = pair * O * S;
    k.search_counters = to_json(median_of(counters));
    k.modes_stages_cpu_s = to_json(median_of(modes_stages));
    if (params.posteriors) {
      k.posteriors = true;
      k.posterior = posterior.cost();
      k.posterior_over_modes = median_ratio(posterior.cpu, modes.cpu);
      k.posterior_over_floor = median(posterior.cpu) / (pair * O * S);
      k.posterior_stages_cpu_s = to_json(median_of(posterior_stages));
      k.posterior_mb = O * g.width_px * g.height_px * 4.0 / 1e6;
      k.equivalence = eq;
      k.fft_max_abs_error =
          fft_error_probe(plan, observations.front(), kernel.yaw_candidates(observations.front()).front(), 300, params.seed);
    }
  }

  for (int D : params.ray_directions) {
    RayMatcherParams rp;
    rp.num_directions = D;
    rp.volume_bits = params.ray_volume_bits;
    std::vector<double> pre;
    std::unique_ptr<RayMatcher> ray;
    for (int i = 0; i < std::max(1, params.ray_precompute_repeats); ++i) {
      ray.reset();
      ray = std::make_unique<RayMatcher>(plan, rp);
      pre.push_back(ray->precompute_s());
    }
    PerfectObservationParams pp;
    pp.num_rays = D;
    pp.max_range_m = rp.max_range_m;
    pp.blocking = ray->blocking();
    const PerfectObserver observer(plan, pp);
    // The same poses as the kernel's (same grid, same blocking, same valid area).
    std::vector<Observation2D> observations;
    const cv::Mat valid = matcher_valid_mask(plan, ray->grid(), ray->blocking());
    for (const Pose2& p : bench_poses(plan, valid, ray->grid(), params))
      observations.push_back(observer.observe(p));
    (void)ray->match(observations.front(), MatchRequest::modes(params.top_k));
    // The exhaustive search on the same volume, side by side with the bounded one.
    RayMatcherParams ep = rp;
    ep.search = RaySearch::kExhaustive;
    const RayMatcher exhaustive(*ray, ep);  // shares the volume
    Series modes, modes_exhaustive, yaw_map, posterior;
    std::vector<std::map<std::string, double>> stages, counters;
    int same_estimate = 0, same_modes = 0;
    for (const Observation2D& obs : observations) {
      MatchResult a, b, e;
      modes.add(measure([&] { a = ray->match(obs, MatchRequest::modes(params.top_k)); }));
      stages.push_back(a.stage_s);
      counters.push_back(a.counters);
      modes_exhaustive.add(measure([&] { e = exhaustive.match(obs, MatchRequest::modes(params.top_k)); }));
      bool same = a.modes.size() == e.modes.size();
      for (std::size_t i = 0; same && i < a.modes.size(); ++i) {
        same = a.modes[i].slice == e.modes[i].slice && a.modes[i].row == e.modes[i].row &&
               a.modes[i].col == e.modes[i].col && a.modes[i].score == e.modes[i].score;
      }
      same_modes += same;
      MatchRequest ym = MatchRequest::modes(params.top_k);
      ym.output = MatchOutput::kMaxOverYaw;
      yaw_map.add(measure([&] { (void)ray->match(obs, ym); }));
      if (params.posteriors) {
        MatchRequest full;
        full.top_k = params.top_k;
        posterior.add(measure([&] { b = ray->match(obs, full); }));
        same_estimate += a.modes.size() == b.modes.size() &&
                         (a.modes.empty() || (a.modes[0].slice == b.modes[0].slice && a.modes[0].row == b.modes[0].row &&
                                              a.modes[0].col == b.modes[0].col));
      }
    }
    RayMatchBench r;
    r.directions = D;
    r.precompute_s = median(pre);
    r.volume_mb = ray->precompute_bytes() / 1e6;
    r.valid_cells = static_cast<int>(ray->volume().num_cells());
    r.modes = modes.cost();
    r.modes_exhaustive = modes_exhaustive.cost();
    r.exhaustive_over_bounded = median_ratio(modes_exhaustive.cpu, modes.cpu);
    r.bounded_modes_identical = same_modes;
    r.max_over_yaw = yaw_map.cost();
    const std::map<std::string, double> c = median_of(counters);
    r.cells_scored_share = scored_share(c, "ray");
    r.stages_cpu_s = to_json(median_of(stages));
    r.search_counters = to_json(c);
    if (params.posteriors) {
      r.posteriors = true;
      r.posterior = posterior.cost();
      r.posterior_mb = static_cast<double>(D) * ray->grid().width_px * ray->grid().height_px * 4.0 / 1e6;
      r.same_estimate_as_posterior = same_estimate;
    }
    out.ray.push_back(std::move(r));
  }

  // The BEV matcher, with and without semantics.
  for (const bool semantics : {true, false}) {
    if (params.bev_fov_deg.empty()) break;
    BevMatcherParams bp;
    bp.semantics = semantics;
    bp.resolution_m = params.bev_resolution_m;
    const auto t0 = Clock::now();
    const BevMatcher bounded(plan, bp);
    const double precompute_wall = std::chrono::duration<double>(Clock::now() - t0).count();
    BevMatcherParams ep = bp;
    ep.search = BevSearch::kExhaustive;
    const BevMatcher exhaustive(bounded, ep);  // shares the volume
    const BevClasses classes = semantics ? BevClasses::kSemantic : BevClasses::kOccupancy;
    const SemanticPlanLines lines = semantic_plan_lines(plan, classes, bp.blocking.cut_height_m);
    const cv::Mat valid = matcher_valid_mask(plan, bounded.grid(), bp.blocking);
    const std::vector<Pose2> poses = sample_valid_poses(valid, bounded.grid(), params.observations, params.seed);
    // The truth along every 5 deg column, shaped by the predictor's structured3d_good spreads.
    BevErrorModel shape = bev_error_preset("structured3d_good");
    BevMatchBench b;
    b.semantics = semantics;
    b.precompute_wall_s = precompute_wall;
    b.precompute_mb = bounded.precompute_bytes() / 1e6;
    b.valid_cells = static_cast<int>(bounded.volume().num_cells());
    b.directions = bp.num_directions;
    b.orientations = bp.num_orientations;
    for (const double fov : params.bev_fov_deg) {
      std::vector<Observation2D> observations;
      for (const Pose2& pose : poses) {
        BevPrediction pred;
        pred.classes = classes;
        pred.bins = bp.bins();
        for (int w = 0; w < 72; ++w) {
          const double az = wrap_angle_rad(2.0 * kPi * w / 72);
          if (fov < 360.0 && std::abs(az) > 0.5 * fov * kPi / 180.0 + 1e-9) continue;
          std::vector<BevColumnElement> els;
          for (const SemanticHit& h : semantic_ray_hits(lines, pose.position_m(), pose.yaw_rad + az, bp.max_range_m)) {
            BevColumnElement e;
            e.truth = h.label;
            e.range_m = h.range_m;
            els.push_back(e);
          }
          const std::vector<float> col = predict_bev_column(els, classes, pred.bins, shape);
          pred.column_azimuth_rad.push_back(az);
          pred.probabilities.insert(pred.probabilities.end(), col.begin(), col.end());
        }
        Observation2D o;
        o.bev.push_back(std::move(pred));
        observations.push_back(std::move(o));
      }
      (void)bounded.match(observations.front(), MatchRequest::modes(params.top_k));
      Series modes, modes_exhaustive, posterior;
      std::vector<std::map<std::string, double>> stages, counters;
      int same = 0;
      for (const Observation2D& obs : observations) {
        MatchResult a, e;
        modes.add(measure([&] { a = bounded.match(obs, MatchRequest::modes(params.top_k)); }));
        stages.push_back(a.stage_s);
        counters.push_back(a.counters);
        modes_exhaustive.add(measure([&] { e = exhaustive.match(obs, MatchRequest::modes(params.top_k)); }));
        bool identical = a.modes.size() == e.modes.size();
        for (std::size_t i = 0; identical && i < a.modes.size(); ++i) {
          identical = a.modes[i].slice == e.modes[i].slice && a.modes[i].row == e.modes[i].row &&
                      a.modes[i].col == e.modes[i].col && a.modes[i].score == e.modes[i].score;
        }
        same += identical;
        if (params.posteriors) {
          MatchRequest full;
          full.top_k = params.top_k;
          posterior.add(measure([&] { (void)bounded.match(obs, full); }));
        }
      }
      BevViewBench f;
      f.fov_deg = fov;
      f.columns = observations.front().bev.front().num_columns();
      f.modes = modes.cost();
      f.modes_exhaustive = modes_exhaustive.cost();
      f.exhaustive_over_bounded = median_ratio(modes_exhaustive.cpu, modes.cpu);
      f.bounded_modes_identical = same;
      const std::map<std::string, double> c = median_of(counters);
      f.cells_scored_share = scored_share(c, "bev");
      f.stages_cpu_s = to_json(median_of(stages));
      f.search_counters = to_json(c);
      if (params.posteriors) {
        f.posteriors = true;
        f.posterior = posterior.cost();
        f.posterior_mb = static_cast<double>(bp.num_orientations) * bounded.grid().width_px * bounded.grid().height_px * 4.0 / 1e6;
      }
      b.views.push_back(std::move(f));
    }
    out.bev.push_back(std::move(b));
  }
  return out;
}

namespace {

const FieldList<MatchBenchCost>& cost_fields() {
  using C = MatchBenchCost;
  static const FieldList<C> f = FieldList<C>("cost")
                                    .number("cpu_s", &C::cpu_s, 0.0, kAnyValue, "CPU s (process, all threads), median")
                                    .number("wall_s", &C::wall_s, 0.0, kAnyValue, "wall s, median");
  return f;
}

const FieldList<KernelMatchBench>& kernel_fields() {
  using K = KernelMatchBench;
  auto posteriors = [](const K& k) { return k.posteriors; };
  static const FieldList<K> f =
      FieldList<K>("kernel")
          .number("orientations", &K::orientations, 0.0, kAnyValue, "median orientation candidates after padding (O)")
          .integer("scales", &K::scales, 0, kManyItems, "scales (S)")
          .section("modes", &K::modes, cost_fields())
          .section("argmax", &K::argmax, cost_fields())
          .number("own_candidates", &K::own_candidates, 0.0, kAnyValue, "median of the matcher's own PALMS+ candidates")
          .section("modes_own_candidates", &K::modes_own_candidates, cost_fields())
          .number("precompute_wall_s", &K::precompute_wall_s, 0.0, kAnyValue, "plan precompute, wall s")
          .number("precompute_mb", &K::precompute_mb, 0.0, kAnyValue, "plan precompute, MB")
          .number("search_maps_mb", &K::search_maps_mb, 0.0, kAnyValue, "branch-and-bound search maps, MB")
          .integer("fft_cols", &K::fft_cols, 0, kManyItems, "correlator transform width")
          .integer("fft_rows", &K::fft_rows, 0, kManyItems, "correlator transform height")
          .number("fft_pair_cpu_s", &K::fft_pair_cpu_s, 0.0, kAnyValue, "one full-size r2c + c2r pair, CPU s")
          .number("fft_floor_cpu_s", &K::fft_floor_cpu_s, 0.0, kAnyValue, "O x S pairs, CPU s")
          .json("search_counters", &K::search_counters, "search counters, medians")
          .json("modes_stages_cpu_s", &K::modes_stages_cpu_s, "search stages, CPU s, medians")
          .flag("posteriors", &K::posteriors, "the full posterior was measured (the fields below)")
          .section("posterior", &K::posterior, cost_fields())
          .optional(posteriors)
          .number("posterior_over_modes", &K::posterior_over_modes, 0.0, kAnyValue, "median ratio posterior / search")
          .optional(posteriors)
          .number("posterior_over_floor", &K::posterior_over_floor, 0.0, kAnyValue, "posterior / FFT floor")
          .optional(posteriors)
          .json("posterior_stages_cpu_s", &K::posterior_stages_cpu_s, "posterior stages, CPU s, medians")
          .optional(posteriors)
          .number("posterior_mb", &K::posterior_mb, 0.0, kAnyValue, "posterior, MB")
          .optional(posteriors)
          .section("equivalence", &K::equivalence, modes_equivalence_fields())
          .optional(posteriors)
          .number("fft_max_abs_error", &K::fft_max_abs_error, 0.0, kAnyValue, "largest |FFT - direct correlation| probed")
          .optional(posteriors);
  return f;
}

const FieldList<RayMatchBench>& ray_fields() {
  using R = RayMatchBench;
  auto posteriors = [](const R& r) { return r.posteriors; };
  static const FieldList<R> f =
      FieldList<R>("ray")
          .integer("directions", &R::directions, 0, kManyItems, "rays per observation")
          .number("precompute_s", &R::precompute_s, 0.0, kAnyValue, "distance volume precompute, s (median)")
          .number("volume_mb", &R::volume_mb, 0.0, kAnyValue, "distance volume, MB")
          .integer("valid_cells", &R::valid_cells, 0, kManyItems, "cells of the volume")
          .section("modes", &R::modes, cost_fields())
          .section("modes_exhaustive", &R::modes_exhaustive, cost_fields())
          .number("exhaustive_over_bounded", &R::exhaustive_over_bounded, 0.0, kAnyValue, "median ratio exhaustive / bounded")
          .integer("bounded_modes_identical", &R::bounded_modes_identical, 0, kManyItems, "observations with identical top-K lists")
          .number("cells_scored_share", &R::cells_scored_share, 0.0, 1.0, "median share of cells the bounded search scored")
          .section("max_over_yaw", &R::max_over_yaw, cost_fields())
          .json("stages_cpu_s", &R::stages_cpu_s, "search stages, CPU s, medians")
          .json("search_counters", &R::search_counters, "search counters, medians")
          .flag("posteriors", &R::posteriors, "the full posterior was measured (the fields below)")
          .section("posterior", &R::posterior, cost_fields())
          .optional(posteriors)
          .number("posterior_mb", &R::posterior_mb, 0.0, kAnyValue, "posterior, MB")
          .optional(posteriors)
          .integer("same_estimate_as_posterior", &R::same_estimate_as_posterior, 0, kManyItems,
                   "observations whose search estimate is the posterior's")
          .optional(posteriors);
  return f;
}

const FieldList<BevViewBench>& bev_view_fields() {
  using V = BevViewBench;
  auto posteriors = [](const V& v) { return v.posteriors; };
  static const FieldList<V> f =
      FieldList<V>("view")
          .number("fov_deg", &V::fov_deg, 0.0, 360.0, "field of view, deg (360: the full circle)")
          .integer("columns", &V::columns, 0, kManyItems, "BEV columns of a view")
          .section("modes", &V::modes, cost_fields())
          .section("modes_exhaustive", &V::modes_exhaustive, cost_fields())
          .number("exhaustive_over_bounded", &V::exhaustive_over_bounded, 0.0, kAnyValue, "median ratio exhaustive / bounded")
          .integer("bounded_modes_identical", &V::bounded_modes_identical, 0, kManyItems, "observations with identical top-K lists")
          .number("cells_scored_share", &V::cells_scored_share, 0.0, 1.0,
                  "median share of cell-orientation pairs the bounded search scored")
          .json("stages_cpu_s", &V::stages_cpu_s, "search stages, CPU s, medians")
          .json("search_counters", &V::search_counters, "search counters, medians")
          .flag("posteriors", &V::posteriors, "the full posterior was measured (the fields below)")
          .section("posterior", &V::posterior, cost_fields())
          .optional(posteriors)
          .number("posterior_mb", &V::posterior_mb, 0.0, kAnyValue, "posterior, MB")
          .optional(posteriors);
  return f;
}

const FieldList<BevMatchBench>& bev_fields() {
  using B = BevMatchBench;
  static const FieldList<B> f =
      FieldList<B>("bev")
          .flag("semantics", &B::semantics, "walls, windows and doors (false: occupancy only)")
          .number("precompute_wall_s", &B::precompute_wall_s, 0.0, kAnyValue, "semantic ray volume precompute, wall s")
          .number("precompute_mb", &B::precompute_mb, 0.0, kAnyValue, "precompute, MB")
          .integer("valid_cells", &B::valid_cells, 0, kManyItems, "cells of the volume")
          .integer("directions", &B::directions, 0, kManyItems, "ray directions of the volume")
          .integer("orientations", &B::orientations, 0, kManyItems, "orientations searched")
          .list("views", &B::views, bev_view_fields());
  return f;
}

const FieldList<MatchBenchResult>& match_bench_fields() {
  using M = MatchBenchResult;
  auto kernel = [](const M& m) { return m.kernel_measured; };
  static const FieldList<M> f =
      FieldList<M>("bench match")
          .text("plan", &M::plan, "the plan's name")
          .integer("threads", &M::threads, 0, kManyItems, "TBB threads")
          .integer("observations", &M::observations, 0, kManyItems, "perfect observations (medians over them)")
          .text("region", &M::region, "where the kernel and ray observers stand: uniform or transitional")
          .integer("top_k", &M::top_k, 0, kManyItems, "modes asked for")
          .flag("kernel_measured", &M::kernel_measured, "the kernel matcher was measured (grid, kernel)")
          .integer("grid_width_px", &M::grid_width_px, 0, kManyItems, "kernel grid width, cells")
          .optional(kernel)
          .integer("grid_height_px", &M::grid_height_px, 0, kManyItems, "kernel grid height, cells")
          .optional(kernel)
          .integer("valid_cells", &M::valid_cells, 0, kManyItems, "kernel grid cells in the valid area")
          .optional(kernel)
          .section("kernel", &M::kernel, kernel_fields())
          .optional(kernel)
          .list("ray", &M::ray, ray_fields())
          .list("bev", &M::bev, bev_fields());
  return f;
}

}  // namespace

nlohmann::ordered_json to_json(const MatchBenchResult& result) { return match_bench_fields().write(result); }

MatchBenchResult read_match_bench(const nlohmann::json& j, const std::string& source) {
  MatchBenchResult r;
  match_bench_fields().read_record(r, j, source);
  return r;
}

}  // namespace floorcast
