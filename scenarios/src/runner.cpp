#include "floorcast/scenarios/runner.hpp"
#include "floorcast/scenarios/track_scoring.hpp"

#include "floorcast/core/depth_io.hpp"
#include "floorcast/core/format.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "floorcast/eval/timing.hpp"
#include "floorcast/floorplans/generate.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/scenarios/sampling.hpp"
#include "floorcast/match/external.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/eval/heatmap.hpp"
#include "floorcast/observe/observation_module.hpp"
#include "floorcast/observe/observe_planes.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "floorcast/sim/scan_io.hpp"
#include "floorcast/sim/scan_params.hpp"
#include "floorcast/sim/scan_sim.hpp"
#include "floorcast/sim/odometry.hpp"
#include "floorcast/sim/walk.hpp"
#include "floorcast/track/run.hpp"
#include "floorcast/core/math.hpp"

namespace floorcast {
namespace {

using OJson = nlohmann::ordered_json;
using Json = nlohmann::json;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

PoseEstimate to_estimate(const PoseHypothesis& h, const Pose2& truth) {
  PoseEstimate e;
  e.x_m = h.x_m;
  e.y_m = h.y_m;
  e.yaw_rad = h.yaw_rad;
  e.score = h.score;
  e.position_error_m = std::hypot(h.x_m - truth.x_m, h.y_m - truth.y_m);
  e.yaw_error_deg = angle_distance_rad(h.yaw_rad, truth.yaw_rad) * 180.0 / kPi;
  return e;
}

}  // namespace

struct ScenarioRunner::Impl {
  const Scenario& scenario;
  struct Building {
    FloorPlan plan;
    std::vector<Pose2> poses;
    std::string sampling_used;  // the region sampled ("uniform (fallback: ...)" for transitional_or_uniform)
    SamplingCoverage coverage;
    std::unique_ptr<RayScene> scene;  // only when some cell simulates scans
  };
  std::vector<Building> buildings;
  // Shared per (building, configuration): matchers and perfect observers.
  std::map<std::string, std::unique_ptr<Matcher>> matchers;
  std::map<std::string, std::unique_ptr<PerfectObserver>> observers;

  explicit Impl(const Scenario& s) : scenario(s) {}

  static std::string matcher_key(std::size_t b, const MatcherSpec& m) {
    return std::to_string(b) + "|" + m.config->name() + "|" + m.config->parameters().dump();
  }
  static std::string observer_key(std::size_t b, const ObservationSpec& o) {
    return std::to_string(b) + "|" + o.perfect.to_json().dump();
  }
  /// The sensor parameters of a unit's scan at `step`: scans are seeded by (observation seed,
  /// building, point, step), so every cell sees the same realisation and step 0 is the single-shot
  /// observation.
  static ScanParams unit_scan_params(const CellSpec& cell, const WorkUnit& unit, int step) {
    ScanParams params = cell.observation.scan;
    std::uint64_t key = mix64((static_cast<std::uint64_t>(unit.building) << 32) ^ static_cast<std::uint64_t>(unit.point));
    if (step > 0) key = mix64(key ^ (0x5e9ULL + static_cast<std::uint64_t>(step)));
    params.seed = mix64(cell.observation.seed ^ key);
    return params;
  }
  /// A sequential unit's walk parameters: every random part of the walk is seeded by (its seed,
  /// building, point), the same in every cell.
  static std::pair<WalkParams, OdometryParams> unit_walk_params(const SequentialSpec& q, const WorkUnit& unit) {
    const std::uint64_t key =
        mix64((static_cast<std::uint64_t>(unit.building) << 32) ^ static_cast<std::uint64_t>(unit.point));
    WalkParams wp = q.walk;
    wp.seed = mix64(q.walk.seed ^ key);
    OdometryParams op = q.odometry;
    op.seed = mix64(q.odometry.seed ^ mix64(key ^ 0x0d0ULL));
    return {wp, op};
  }
  /// Depth maps made elsewhere for a unit's scan at `step` (cell.observation.depth_dir) replace
  /// the simulated depth; returns the repairs. Throws InputError naming the folder.
  std::vector<std::string> replace_depth(const CellSpec& cell, const WorkUnit& unit, int step, Scan& scan) const {
    const std::string folder =
        (std::filesystem::path(cell.observation.depth_dir) / unit_scan_folder(scenario, unit, step)).string();
    if (!std::filesystem::is_directory(folder)) {
      throw InputError("observation.depth_dir: no depth maps for unit " + unit.id +
                       (step > 0 ? " at walk step " + std::to_string(step) : std::string()) + " (looked for the folder " +
                       folder + "; `floorcast export` writes the colour views of the scenario's scans in this layout)");
    }
    return load_depth_directory(scan, folder, cell.observation.depth_file).repairs;
  }
};

std::string unit_scan_folder(const Scenario& scenario, const WorkUnit& unit, int step) {
  char point[16], walk_step[24];
  std::snprintf(point, sizeof point, "p%04d", unit.point);
  std::snprintf(walk_step, sizeof walk_step, "step_%04d", step);
  const std::string base = scenario.cells.at(static_cast<std::size_t>(unit.cell)).id + "/" +
                           scenario.buildings.at(static_cast<std::size_t>(unit.building)).label + "/scans/" + point;
  return step > 0 ? base + "/" + walk_step : base;
}

ScenarioRunner::ScenarioRunner(const Scenario& scenario, const std::function<void(const std::string&)>& log)
    : impl_(std::make_unique<Impl>(scenario)) {
  Impl& d = *impl_;
  auto say = [&log](const std::string& s) {
    if (log) log(s);
  };
  const bool any_scan = std::any_of(scenario.cells.begin(), scenario.cells.end(),
                                    [](const CellSpec& c) { return c.observation.source == ObservationSource::kScan; });

  // Buildings and their observation points (the same points for every cell).
  for (std::size_t b = 0; b < scenario.buildings.size(); ++b) {
    const BuildingSpec& spec = scenario.buildings[b];
    Impl::Building building;
    const auto t0 = Clock::now();
    std::vector<Room> rooms;
    if (!spec.file.empty()) {
      building.plan = load_floor_plan(spec.file);
      rooms = spec.rooms_file.empty() ? building.plan.rooms : load_rooms_file(spec.rooms_file);
    } else {
      GeneratedBuilding generated = generate_building(parse_archetype(spec.archetype), spec.seed);
      building.plan = std::move(generated.plan);
      rooms = std::move(generated.rooms);
    }
    std::vector<std::string> kinds;
    const bool or_uniform = spec.sampling_region == "transitional_or_uniform";
    if (spec.sampling_region == "transitional" || or_uniform) kinds = {"transitional"};
    if (spec.sampling_region == "kinds") kinds = scenario.sampling.region_kinds;
    if (!kinds.empty() && rooms.empty()) {
      throw InputError("building \"" + spec.label + "\": sampling by room kind needs room labels (a plan with "
                       "\"rooms\", a generated building, or a rooms file: buildings[].rooms)");
    }
    auto sample = [&](const std::vector<std::string>& k) {
      return sample_observation_points(building.plan, scenario.sampling.count, scenario.sampling.seed, static_cast<int>(b),
                                       scenario.sampling.clearance_m, 0.1, rooms, k);
    };
    SampledPoints sampled;
    building.sampling_used = or_uniform ? "transitional" : spec.sampling_region;
    try {
      sampled = sample(kinds);
    } catch (const SamplingError& e) {
      // sampling.region transitional_or_uniform: a plan whose transitional spaces cannot be
      // sampled (none, outside the free space, too narrow) is sampled uniformly, and says why.
      if (!or_uniform || e.cause() == SamplingRefusal::kNoClearance) throw;
      sampled = sample({});
      building.sampling_used = std::string("uniform (fallback: ") + e.what() + ")";
    }
    building.poses = std::move(sampled.poses);
    building.coverage = std::move(sampled.coverage);
    if (static_cast<int>(building.poses.size()) != scenario.sampling.count) {
      throw InputError("building \"" + spec.label + "\": only " + std::to_string(building.poses.size()) + " of " +
                       std::to_string(scenario.sampling.count) + " observation points fit with clearance " +
                       std::to_string(scenario.sampling.clearance_m) + " m");
    }
    if (!scenario.sampling.random_yaw)
      for (Pose2& p : building.poses) p.yaw_rad = 0.0;
    if (any_scan) building.scene = std::make_unique<RayScene>(extrude_plan(building.plan));
    say("building " + spec.label + ": " + std::to_string(building.plan.walls.size()) + " walls, " +
        std::to_string(building.poses.size()) + " points (" + building.sampling_used + ", " + std::to_string(seconds_since(t0)) +
        " s): " + sampling_coverage_summary(building.coverage));
    for (const std::string& w : building.coverage.warnings) say("building " + spec.label + ": sampling warning: " + w);
    d.buildings.push_back(std::move(building));
  }

  // Matchers and observers for every (building, configuration) any cell uses.
  for (const CellSpec& cell : scenario.cells) {
    for (std::size_t b = 0; b < d.buildings.size(); ++b) {
      for (const MatcherSpec& m : cell.matchers) {
        const std::string key = Impl::matcher_key(b, m);
        if (d.matchers.count(key)) continue;
        const auto t0 = Clock::now();
        d.matchers[key] = m.config->build(d.buildings[b].plan);
        say("matcher " + m.label + " on " + scenario.buildings[b].label + ": precompute " +
            std::to_string(seconds_since(t0)) + " s");
        for (const std::string& note : d.matchers[key]->notes())
          say("matcher " + m.label + " on " + scenario.buildings[b].label + ": note: " + note);
      }
      if (cell.observation.source == ObservationSource::kPerfect) {
        const std::string key = Impl::observer_key(b, cell.observation);
        if (!d.observers.count(key)) {
          d.observers[key] = std::make_unique<PerfectObserver>(d.buildings[b].plan, cell.observation.perfect);
        }
      }
    }
  }
}

ScenarioRunner::~ScenarioRunner() = default;

SimulatedScan ScenarioRunner::unit_scan(const WorkUnit& unit, int step) const {
  const Impl& d = *impl_;
  const CellSpec& cell = d.scenario.cells.at(static_cast<std::size_t>(unit.cell));
  if (cell.observation.source != ObservationSource::kScan) {
    throw InputError("cell " + cell.id + " makes perfect observations: it has no scans");
  }
  // A negative sample is observed in its source building.
  const Impl::Building& building = d.buildings.at(static_cast<std::size_t>(unit.negative() ? unit.source_building : unit.building));
  Pose2 truth = building.poses.at(static_cast<std::size_t>(unit.negative() ? unit.source_point : unit.point));
  if (step > 0) {
    // Along the unit's walk: the true pose at that step (the walk run_sequential makes).
    if (!cell.sequential) {
      throw InputError("cell " + cell.id + " makes single-shot observations: it has no walk step " + std::to_string(step));
    }
    const Walk walk = simulate_walk(building.plan, truth, Impl::unit_walk_params(*cell.sequential, unit).first);
    if (static_cast<std::size_t>(step) >= walk.steps.size()) {
      throw InputError("unit " + unit.id + ": its walk has " + std::to_string(walk.steps.size()) + " steps, no step " +
                       std::to_string(step));
    }
    truth = walk.steps[static_cast<std::size_t>(step)].T_world_body;
  }
  SimulationOptions options;
  options.column_semantics = cell.observation.observe.bev.enabled;
  return simulate_scan(*building.scene, truth, Impl::unit_scan_params(cell, unit, step), options);
}

std::vector<int> ScenarioRunner::unit_observation_steps(const WorkUnit& unit) const {
  const Impl& d = *impl_;
  const CellSpec& cell = d.scenario.cells.at(static_cast<std::size_t>(unit.cell));
  if (!cell.sequential) return {0};
  const Impl::Building& building = d.buildings.at(static_cast<std::size_t>(unit.building));
  try {
    const Walk walk = simulate_walk(building.plan, building.poses.at(static_cast<std::size_t>(unit.point)),
                                    Impl::unit_walk_params(*cell.sequential, unit).first);
    std::vector<int> steps = schedule_observations(walk, cell.sequential->schedule);
    // Step 0 is always observed: the single-shot observation the matchers score.
    if (steps.empty() || steps.front() != 0) steps.insert(steps.begin(), 0);
    return steps;
  } catch (const InputError&) {
    return {0};  // no walk from this point (the run reports it)
  }
}

const FloorPlan& ScenarioRunner::building_plan(int b) const { return impl_->buildings.at(static_cast<std::size_t>(b)).plan; }
const std::vector<Pose2>& ScenarioRunner::building_points(int b) const {
  return impl_->buildings.at(static_cast<std::size_t>(b)).poses;
}
const std::string& ScenarioRunner::building_sampling_region(int b) const {
  return impl_->buildings.at(static_cast<std::size_t>(b)).sampling_used;
}
const SamplingCoverage& ScenarioRunner::building_sampling_coverage(int b) const {
  return impl_->buildings.at(static_cast<std::size_t>(b)).coverage;
}
const Mesh* ScenarioRunner::building_mesh(int b) const {
  const auto& scene = impl_->buildings.at(static_cast<std::size_t>(b)).scene;
  return scene ? &scene->mesh() : nullptr;
}

const OJson& ScenarioRunner::resolved_full() const { return impl_->scenario.resolved; }

UnitResult ScenarioRunner::run_unit(const WorkUnit& unit, UnitSink* images) const {
  const Impl& d = *impl_;
  const Scenario& s = d.scenario;
  const CellSpec& cell = s.cells[static_cast<std::size_t>(unit.cell)];
  const std::size_t b = static_cast<std::size_t>(unit.building);
  const Impl::Building& building = d.buildings[b];
  // Where the observation is made: this building, or for a negative sample another one (its
  // point is then the truth, in that building's frame; the matchers see this building's plan).
  const std::size_t ob = unit.negative() ? static_cast<std::size_t>(unit.source_building) : b;
  const Impl::Building& observed = d.buildings[ob];
  UnitResult r;
  r.unit = unit;
  r.truth = observed.poses[static_cast<std::size_t>(unit.negative() ? unit.source_point : unit.point)];

  // An observation at a pose: perfect, or a simulated scan through the observation module.
  // Scans are seeded by (observation seed, building, point, step): every cell sees the same
  // realisation, and step 0 is the single-shot observation.
  struct Observed {
    Observation2D observation;
    bool ok = true;
    std::string failure;
    bool bev_ok = true;  ///< the observation has a BEV (scans: the observation module made one)
  };
  auto observe_at = [&](const Pose2& pose, int step, OJson* info) {
    Observed o;
    if (cell.observation.source == ObservationSource::kPerfect) {
      const auto t0 = Clock::now();
      o.observation = d.observers.at(Impl::observer_key(ob, cell.observation))->observe(pose);
      r.timings_s["observe"] += seconds_since(t0);
      if (info) (*info)["source"] = "perfect";
    } else {
      const auto t0 = Clock::now();
      // Column semantics (the BEV predictor's truth) only when the observation module makes a BEV.
      SimulationOptions options;
      options.column_semantics = cell.observation.observe.bev.enabled;
      Scan scan = simulate_scan(*observed.scene, pose, Impl::unit_scan_params(cell, unit, step), options).scan;
      r.timings_s["simulate"] += seconds_since(t0);
      if (!cell.observation.depth_dir.empty()) {
        // Depth made elsewhere (a depth network on the colour views `floorcast export` wrote).
        const std::vector<std::string> repairs = d.replace_depth(cell, unit, step, scan);
        if (info && !repairs.empty()) (*info)["depth_repairs"] = repairs;
      }
      const ObservationResult obs = observe_scan(scan, cell.observation.observe);
      r.timings_s["observe"] += obs.total_s;
      o.observation = obs.observation;
      if (info) {
        (*info)["source"] = "scan";
        (*info)["diagnostics"] = to_json(obs.diagnostics);
      }
      if (o.observation.segments_m.empty() && o.observation.planes.empty()) {
        o.ok = false;
        o.failure = obs.diagnostics.warnings.empty() ? "no wall segments observed" : obs.diagnostics.warnings.front();
      }
      // The BEV does not come from the wall segments: a bev matcher can run without them.
      o.bev_ok = !o.observation.bev.empty();
    }
    return o;
  };
  Observed first = observe_at(r.truth, 0, &r.observation);
  if (cell.observation.source == ObservationSource::kPerfect) first.bev_ok = !first.observation.bev.empty();
  const Observation2D& observation = first.observation;
  r.observation_ok = first.ok;
  r.observation_failure = first.failure;
  r.observation["segments"] = observation.segments_m.size();
  r.observation["rays"] = observation.ray_ranges_m.size();
  if (!observation.planes.empty()) r.observation["planes"] = observation.planes.size();

  double match_total = 0.0;
  for (const MatcherSpec& m : cell.matchers) {
    MatcherOutcome o;
    o.label = m.label;
    // A BEV matcher needs the BEV, every other matcher the wall segments.
    const bool uses_bev = m.config->name() == "bev";
    if (uses_bev ? !first.bev_ok : !r.observation_ok) {
      o.ok = false;
      o.failure = uses_bev ? "observation has no BEV (scans: observe_params.bev.enabled; perfect: observation.bev_columns)"
                           : "observation failed: " + r.observation_failure;
      r.outcomes.push_back(o);
      continue;
    }
    const Matcher& matcher = *d.matchers.at(Impl::matcher_key(b, m));
    // A ray matcher whose direction count differs from the observation's rays casts its rays on
    // the observed segments (ray_source "auto"); for perfect observations that is exact.
    const Observation2D& input = observation;
    // Only the estimate and the top-K modes are scored: matchers find them without a posterior
    // (the kernel matcher's exact branch and bound) unless a heatmap is drawn.
    const bool heatmap = images && unit.point < s.output.heatmaps;
    MatchRequest request = MatchRequest::modes(s.scoring.top_k, 1.0, 30.0 * kPi / 180.0);
    if (heatmap) request.output = MatchOutput::kPosterior;
    MatchResult mr;
    const auto tm = Clock::now();
    try {
      mr = matcher.match(input, request);
    } catch (const ExternalMethodError& e) {
      // A misbehaving external method: an error for this unit and method, the run goes on.
      o.ok = false;
      o.error = true;
      o.failure = std::string("error: ") + e.what();
      o.match_s = seconds_since(tm);
      match_total += o.match_s;
      r.outcomes.push_back(o);
      continue;
    }
    o.match_s = mr.match_s;
    match_total += mr.match_s;
    if (!mr.has_pose()) {
      o.ok = false;
      o.failure = "empty posterior";
    } else {
      o.estimate = to_estimate(mr.estimate(), r.truth);
      for (const PoseHypothesis& h : mr.modes) o.top_k.push_back(to_estimate(h, r.truth));
    }
    if (heatmap) {
      const std::optional<PoseHypothesis> best = mr.has_pose() ? std::optional<PoseHypothesis>(mr.estimate()) : std::nullopt;
      const cv::Mat raster = rasterize_occupancy(building.plan, mr.posterior.grid, BlockingOptions{});
      const PoseHypothesis truth{r.truth.x_m, r.truth.y_m, r.truth.yaw_rad, 0.0};
      HeatmapStyle style;
      style.title = unit.id + ", " + m.label + ": " +
                    (o.ok ? "error " + format_fixed(o.estimate.position_error_m, 2) + " m, " +
                                format_fixed(o.estimate.yaw_error_deg, 1) + " deg"
                          : std::string("no pose"));
      const cv::Mat img = render_posterior_heatmap(mr.posterior, raster, truth,
                                                   o.ok ? best : std::nullopt, style);
      std::string stem = unit.id + "_" + m.label;
      for (char& c : stem) if (c == '/') c = '_';
      images->write_image("heatmaps/" + stem + ".png", img);
      // The data behind the picture, for vector figures (python/floorcast/figures.py): the best
      // score over heading per cell (float32, rows from the lowest y) and where it lies.
      images->write_file("heatmaps/" + stem + ".npy", npy_bytes(mr.posterior.max_over_yaw()));
      nlohmann::ordered_json meta;
      meta["unit"] = unit.id;
      meta["building"] = s.buildings[b].label;
      meta["matcher"] = m.label;
      meta["grid"] = {{"origin_m", {mr.posterior.grid.origin_x_m, mr.posterior.grid.origin_y_m}},
                      {"resolution_m", mr.posterior.grid.resolution_m_per_px},
                      {"size_px", {mr.posterior.grid.width_px, mr.posterior.grid.height_px}},
                      {"cell_centre", "array[row, col] is x = origin_m[0] + (col + 0.5) * resolution_m, "
                                      "y = origin_m[1] + (row + 0.5) * resolution_m"}};
      meta["truth"] = {{"x_m", r.truth.x_m}, {"y_m", r.truth.y_m}, {"yaw_rad", r.truth.yaw_rad}};
      if (o.ok) {
        meta["estimate"] = {{"x_m", o.estimate.x_m}, {"y_m", o.estimate.y_m}, {"yaw_rad", o.estimate.yaw_rad}};
        meta["position_error_m"] = o.estimate.position_error_m;
        meta["yaw_error_deg"] = o.estimate.yaw_error_deg;
      } else {
        meta["estimate"] = nullptr;
        meta["position_error_m"] = nullptr;
      }
      images->write_file("heatmaps/" + stem + ".json", meta.dump(2) + "\n");
    }
    r.outcomes.push_back(o);
  }
  r.timings_s["match"] = match_total;
  if (cell.sequential && !unit.negative()) run_sequential(unit, r, [&](const Pose2& pose, int step) {
    const Observed o = observe_at(pose, step, nullptr);
    return o.ok || !o.observation.bev.empty() ? std::optional<Observation2D>(o.observation) : std::nullopt;
  });
  return r;
}

void ScenarioRunner::run_sequential(const WorkUnit& unit, UnitResult& r,
                                    const std::function<std::optional<Observation2D>(const Pose2&, int)>& observe) const {
  const Impl& d = *impl_;
  const CellSpec& cell = d.scenario.cells[static_cast<std::size_t>(unit.cell)];
  const SequentialSpec& q = *cell.sequential;
  const std::size_t b = static_cast<std::size_t>(unit.building);
  const FloorPlan& plan = d.buildings[b].plan;
  const std::uint64_t key = mix64((static_cast<std::uint64_t>(b) << 32) ^ static_cast<std::uint64_t>(unit.point));
  const auto [wp, op] = Impl::unit_walk_params(q, unit);
  const auto t0 = Clock::now();
  Walk walk;
  try {
    walk = simulate_walk(plan, r.truth, wp);
  } catch (const InputError& e) {
    r.walk["failure"] = e.what();
    for (const TrackerSpec& t : q.trackers) {
      TrackOutcome o;
      o.label = t.label;
      o.started = false;
      o.failure = std::string("no walk: ") + e.what();
      o.record.failed = true;
      r.tracks.push_back(o);
    }
    return;
  }
  const OdometryTrack odo = simulate_odometry(walk, op);
  r.timings_s["walk"] = seconds_since(t0);
  const std::vector<int> scheduled = schedule_observations(walk, q.schedule);
  const WalkSummary& sm = walk.summary;
  r.walk = {{"steps", walk.steps.size()},        {"length_m", sm.length_m},
            {"duration_s", sm.duration_s},       {"transitional_share", sm.transitional_share},
            {"longest_straight_m", sm.longest_straight_m}, {"observations", scheduled.size()},
            {"odometry_end_error_m", (walk.steps.back().T_world_body.position_m() - odo.poses.back().position_m()).norm()}};
  {
    // The true path (mm), for trajectory figures.
    nlohmann::ordered_json xy = nlohmann::ordered_json::array();
    for (const WalkStep& s : walk.steps)
      xy.push_back({std::round(s.T_world_body.x_m * 1e3) / 1e3, std::round(s.T_world_body.y_m * 1e3) / 1e3});
    r.walk["truth_xy"] = xy;
  }
  // Observations on the schedule (step 0 again: the single-shot observation, same seed) and the
  // posteriors each tracker's matcher makes of them, computed once per (matcher, step): as point
  // queries (Matcher::query: a tracker asks for the cells it needs; the full posterior is computed
  // here for the first observation, the trackers' initialisation, and otherwise only when a
  // tracker asks for it). A posterior is kept only while a later tracker uses its matcher (a
  // walk's full posteriors are 100+ MB each on an office at 0.1 m: a 100-frame walk kept whole
  // would not fit in memory).
  std::map<int, std::optional<Observation2D>> observations;
  std::map<std::pair<std::string, int>, PosteriorQuery> posteriors;
  std::map<std::pair<std::string, int>, std::string> posterior_errors;  // an external matcher's error
  std::size_t current_tracker = 0;
  auto needed_later = [&](const std::string& matcher_label) {
    for (std::size_t i = current_tracker + 1; i < q.trackers.size(); ++i) {
      if (q.trackers[i].matcher == matcher_label) return true;
    }
    return false;
  };
  auto posterior = [&](const std::string& matcher_label, int step) -> std::optional<PosteriorQuery> {
    if (std::find(scheduled.begin(), scheduled.end(), step) == scheduled.end()) return std::nullopt;
    auto oit = observations.find(step);
    if (oit == observations.end()) {
      oit = observations.emplace(step, observe(walk.steps[static_cast<std::size_t>(step)].T_world_body, step)).first;
    }
    if (!oit->second) return std::nullopt;  // a failed observation is no update
    const MatcherSpec* spec = nullptr;
    for (const MatcherSpec& m : cell.matchers) spec = m.label == matcher_label ? &m : spec;
    // What this matcher needs: the BEV (bev), the wall segments (every other one).
    if (spec->config->name() == "bev" ? oit->second->bev.empty() : oit->second->segments_m.empty()) return std::nullopt;
    const auto k = std::make_pair(matcher_label, step);
    if (posterior_errors.count(k)) return std::nullopt;
    auto pit = posteriors.find(k);
    if (pit != posteriors.end()) return pit->second;
    const auto tm = Clock::now();
    std::optional<PosteriorQuery> p;
    try {
      p = d.matchers.at(Impl::matcher_key(b, *spec))->query(*oit->second);
      if (step == 0) p->full();
    } catch (const ExternalMethodError& e) {
      posterior_errors[k] = "error: matcher " + matcher_label + " at step " + std::to_string(step) + ": " + e.what();
      r.timings_s["track_match"] += seconds_since(tm);
      return std::nullopt;
    }
    r.timings_s["track_match"] += seconds_since(tm);
    if (needed_later(matcher_label)) posteriors.emplace(k, *p);
    return p;
  };
  for (std::size_t ti = 0; ti < q.trackers.size(); ++ti) {
    current_tracker = ti;
    // Posteriors no tracker from here on uses are let go.
    for (auto it = posteriors.begin(); it != posteriors.end();) {
      bool used = false;
      for (std::size_t i = ti; i < q.trackers.size(); ++i) used = used || q.trackers[i].matcher == it->first.first;
      it = used ? std::next(it) : posteriors.erase(it);
    }
    const TrackerSpec& t = q.trackers[ti];
    std::shared_ptr<const TrackerConfig> config = t.config;
    if (const std::optional<std::uint64_t> seed = config->seed()) config = config->with_seed(mix64(*seed ^ mix64(key ^ (0x7a0ULL + ti))));
    const std::unique_ptr<Tracker> tracker = config->build(plan);
    TrackOutcome o;
    o.label = t.label;
    int used = 0;
    const TrackRun run = run_tracker(*tracker, odo.steps, 0, [&](int step) {
      std::optional<PosteriorQuery> p = posterior(t.matcher, step);
      used += p ? 1 : 0;
      return p;
    });
    o.started = run.started;
    o.failure = run.failure;
    o.observations_used = used;
    o.record = track_record(run, walk.steps, 0);
    // An external matcher's error anywhere along the walk makes the track an error (its
    // observations were missing), scored as a failure and run again on resume.
    for (const auto& [k, why] : posterior_errors) {
      if (k.first != t.matcher) continue;
      o.error = true;
      o.started = false;
      o.failure = why;
      o.record.failed = true;
      break;
    }
    double total = 0.0;
    for (std::size_t i = 0; i < run.steps.size(); ++i) {
      const TrackRunStep& s = run.steps[i];
      o.estimate_xy_m.emplace_back(std::round(s.estimate.pose.x_m * 1e3) / 1e3, std::round(s.estimate.pose.y_m * 1e3) / 1e3);
      if (!s.estimate.modes.empty()) {
        // The position error of each of the belief's peaks at this step (steps before the first
        // with peaks: empty lists).
        const WalkStep& truth = walk.steps[static_cast<std::size_t>(s.step)];
        std::vector<double> errors;
        for (const Pose2& m : s.estimate.modes) errors.push_back((m.position_m() - truth.T_world_body.position_m()).norm());
        o.mode_position_error_m.resize(i);
        o.mode_position_error_m.push_back(std::move(errors));
      }
      total += s.time_s;
    }
    r.timings_s["track"] += total;
    r.tracks.push_back(std::move(o));
  }
}

RunOutcome ScenarioRunner::run(UnitSink& sink, const RunOptions& options) const {
  const auto t0 = Clock::now();
  RunOutcome out;
  out.reference_s = reference_workload_s();
  const std::vector<WorkUnit> all = enumerate_units(impl_->scenario);
  out.units_total = all.size();
  const std::vector<WorkUnit> mine = select_shard(all, options.shard);
  out.units_in_shard = mine.size();
  std::vector<WorkUnit> todo;
  for (const WorkUnit& u : mine) {
    if (sink.has_unit(u)) ++out.skipped;
    else todo.push_back(u);
  }
  {
    // Depth made elsewhere: every unit's folder for its first observation is there before any work
    // (those of later walk steps are looked for when the walk reaches them).
    std::size_t missing = 0;
    std::string first;
    for (const WorkUnit& u : todo) {
      const ObservationSpec& o = impl_->scenario.cells[static_cast<std::size_t>(u.cell)].observation;
      if (o.depth_dir.empty()) continue;
      const std::string folder = (std::filesystem::path(o.depth_dir) / unit_scan_folder(impl_->scenario, u, 0)).string();
      if (std::filesystem::is_directory(folder)) continue;
      if (missing++ == 0) first = folder;
    }
    if (missing > 0) {
      throw InputError("observation.depth_dir: no depth maps for " + std::to_string(missing) + " of " +
                       std::to_string(todo.size()) + " units (the first: " + first +
                       "); `floorcast export SCENARIO -o DIR` writes the colour views of the scenario's scans in the "
                       "layout depth_dir mirrors (DIR/<cell>/<building>/scans/pNNNN)");
    }
  }
  std::mutex mutex;
  std::size_t finished = 0;
  auto report = [&] {
    if (options.on_progress) options.on_progress({finished, todo.size(), out.skipped, seconds_since(t0)});
  };
  report();
  const int jobs = options.jobs > 0 ? options.jobs : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  tbb::task_arena arena(jobs);
  // Images are written by the worker that made them (the sink serialises nothing else).
  struct LockedImages : UnitSink {
    UnitSink& inner;
    std::mutex& m;
    LockedImages(UnitSink& i, std::mutex& mm) : inner(i), m(mm) {}
    bool has_unit(const WorkUnit& u) const override { return inner.has_unit(u); }
    void write_unit(const UnitResult& r) override {
      std::lock_guard<std::mutex> lock(m);
      inner.write_unit(r);
    }
    void write_image(const std::string& p, const cv::Mat& img) override {
      std::lock_guard<std::mutex> lock(m);
      inner.write_image(p, img);
    }
    void write_file(const std::string& p, const std::string& bytes) override {
      std::lock_guard<std::mutex> lock(m);
      inner.write_file(p, bytes);
    }
  } locked(sink, mutex);
  // No exception may leave a task: TBB would cancel the task group, and the cancellation reaches
  // every nested parallel algorithm (the matchers', OpenCV's) running in sibling tasks, which then
  // return unfinished results. The first error stops further units and is rethrown after the loop.
  std::exception_ptr first_error;
  std::atomic<bool> stop{false};
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, todo.size(), [&](std::size_t i) {
      if (stop.load()) return;
      try {
        // Isolated: a worker waiting inside a unit's nested parallel loop (the matchers', the
        // filters') runs only that unit's tasks, never a whole other unit, so the unit's stage and
        // match times measure its own work (without isolation a 0.1 s match could absorb a
        // sibling's seconds-long scan and the gate's timing ratios swung 8-70x under load).
        UnitResult result;
        tbb::this_task_arena::isolate([&] { result = run_unit(todo[i], &locked); });
        std::lock_guard<std::mutex> lock(mutex);
        if (stop.load()) return;
        sink.write_unit(result);
        ++finished;
        report();
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!first_error) first_error = std::current_exception();
        stop.store(true);
      }
    }, tbb::simple_partitioner());
  });
  if (first_error) std::rethrow_exception(first_error);
  out.executed = finished;
  out.wall_s = seconds_since(t0);
  return out;
}

}  // namespace floorcast
