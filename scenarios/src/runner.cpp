#include "floorcast/scenarios/runner.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "floorcast/eval/timing.hpp"
#include "floorcast/floorplans/generate.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/scenarios/sampling.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/observe/observation_module.hpp"
#include "floorcast/observe/observe_planes.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "floorcast/sim/scan_io.hpp"
#include "floorcast/sim/scan_params.hpp"
#include "floorcast/sim/scan_sim.hpp"
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
};

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
    const std::vector<std::string>& kinds = scenario.sampling.region_kinds;
    std::vector<std::vector<Vec2>> regions;
    if (!spec.file.empty()) {
      building.plan = load_floor_plan(spec.file);
      if (!kinds.empty()) {
        if (spec.rooms_file.empty()) {
          throw InputError("building \"" + spec.label + "\": sampling.region_kinds needs room labels (a rooms file: "
                           "buildings[].rooms)");
        }
        regions = load_room_polygons(spec.rooms_file, kinds);
      }
    } else {
      GeneratedBuilding generated = generate_building(parse_archetype(spec.archetype), spec.seed);
      building.plan = std::move(generated.plan);
      for (const GeneratedRoom& room : generated.rooms) {
        if (std::find(kinds.begin(), kinds.end(), room.kind) != kinds.end()) regions.push_back(room.polygon_m);
      }
    }
    if (!kinds.empty() && regions.empty()) {
      throw InputError("building \"" + spec.label + "\": no room of the sampling.region_kinds");
    }
    building.poses = sample_observation_poses(building.plan, scenario.sampling.count, scenario.sampling.seed,
                                              static_cast<int>(b), scenario.sampling.clearance_m, 0.1, regions);
    if (static_cast<int>(building.poses.size()) != scenario.sampling.count) {
      throw InputError("building \"" + spec.label + "\": only " + std::to_string(building.poses.size()) + " of " +
                       std::to_string(scenario.sampling.count) + " observation points fit with clearance " +
                       std::to_string(scenario.sampling.clearance_m) + " m");
    }
    if (!scenario.sampling.random_yaw)
      for (Pose2& p : building.poses) p.yaw_rad = 0.0;
    if (any_scan) building.scene = std::make_unique<RayScene>(extrude_plan(building.plan));
    say("building " + spec.label + ": " + std::to_string(building.plan.walls.size()) + " walls, " +
        std::to_string(building.poses.size()) + " points (" + std::to_string(seconds_since(t0)) + " s)");
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

const OJson& ScenarioRunner::resolved_full() const { return impl_->scenario.resolved; }

UnitResult ScenarioRunner::run_unit(const WorkUnit& unit, UnitSink* images) const {
  const Impl& d = *impl_;
  const Scenario& s = d.scenario;
  const CellSpec& cell = s.cells[static_cast<std::size_t>(unit.cell)];
  const std::size_t b = static_cast<std::size_t>(unit.building);
  const Impl::Building& building = d.buildings[b];
  UnitResult r;
  r.unit = unit;
  r.truth = building.poses[static_cast<std::size_t>(unit.point)];

  Observation2D observation;
  if (cell.observation.source == ObservationSource::kPerfect) {
    const auto t0 = Clock::now();
    observation = d.observers.at(Impl::observer_key(b, cell.observation))->observe(r.truth);
    r.timings_s["observe"] = seconds_since(t0);
    r.observation["source"] = "perfect";
  } else {
    ScanParams params = cell.observation.scan;
    // Seeded by (observation seed, building, point): every cell sees the same realisation.
    params.seed = mix64(cell.observation.seed ^ mix64((static_cast<std::uint64_t>(b) << 32) ^
                                                      static_cast<std::uint64_t>(unit.point)));
    const auto t0 = Clock::now();
    const Scan scan = simulate_scan(*building.scene, r.truth, params).scan;
    r.timings_s["simulate"] = seconds_since(t0);
    const ObservationResult obs = observe_scan(scan, cell.observation.observe);
    r.timings_s["observe"] = obs.total_s;
    observation = obs.observation;
    r.observation["source"] = "scan";
    r.observation["diagnostics"] = to_json(obs.diagnostics);
    if (observation.segments_m.empty()) {
      r.observation_ok = false;
      r.observation_failure = obs.diagnostics.warnings.empty() ? "no wall segments observed"
                                                                : obs.diagnostics.warnings.front();
    }
  }
  r.observation["segments"] = observation.segments_m.size();
  r.observation["rays"] = observation.ray_ranges_m.size();

  double match_total = 0.0;
  for (const MatcherSpec& m : cell.matchers) {
    MatcherOutcome o;
    o.label = m.label;
    if (!r.observation_ok) {
      o.ok = false;
      o.failure = "observation failed: " + r.observation_failure;
      r.outcomes.push_back(o);
      continue;
    }
    const Matcher& matcher = *d.matchers.at(Impl::matcher_key(b, m));
    // A ray matcher whose direction count differs from the observation's rays casts its rays on
    // the observed segments (ray_source "auto"); for perfect observations that is exact.
    const Observation2D& input = observation;
    const MatchResult mr = matcher.match(input);
    o.match_s = mr.match_s;
    match_total += mr.match_s;
    const PoseHypothesis best = mr.posterior.argmax();
    if (!(best.score > 0.0)) {
      o.ok = false;
      o.failure = "empty posterior";
    } else {
      o.estimate = to_estimate(best, r.truth);
      for (const PoseHypothesis& h : mr.posterior.top_k(s.scoring.top_k, 1.0, 30.0 * kPi / 180.0))
        o.top_k.push_back(to_estimate(h, r.truth));
    }
    if (images && unit.point < s.output.heatmaps) {
      const cv::Mat raster = rasterize_occupancy(building.plan, mr.posterior.grid, BlockingOptions{});
      const PoseHypothesis truth{r.truth.x_m, r.truth.y_m, r.truth.yaw_rad, 0.0};
      const cv::Mat img = render_posterior_heatmap(mr.posterior, raster, truth,
                                                   o.ok ? std::optional<PoseHypothesis>(best) : std::nullopt);
      std::string name = unit.id + "_" + m.label + ".png";
      for (char& c : name) if (c == '/') c = '_';
      images->write_image("heatmaps/" + name, img);
    }
    r.outcomes.push_back(o);
  }
  r.timings_s["match"] = match_total;
  return r;
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
        const UnitResult result = run_unit(todo[i], &locked);
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
