#include "floorcast/sim/walk_sim.hpp"

#include <chrono>
#include <iomanip>
#include <memory>
#include <sstream>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/hash.hpp"
#include "floorcast/core/observation_io.hpp"
#include "floorcast/core/random.hpp"
#include "floorcast/sim/gl_renderer.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "floorcast/sim/scan_io.hpp"
#include "floorcast/sim/scan_sim.hpp"

namespace floorcast {

std::string walk_observation_folder(int step) {
  std::ostringstream s;
  s << "observations/step_" << std::setw(4) << std::setfill('0') << step;
  return s.str();
}

SimulatedWalkFolder write_simulated_walk(const FloorPlan& plan, const WalkSimulationOptions& o, const std::string& dir) {
  using Clock = std::chrono::steady_clock;
  if (o.rgb && o.perfect) {
    throw InputError("colour views need simulated scans (a sensor preset), not perfect observations");
  }
  if (o.rgb) {
    std::string why;
    if (!gl_renderer_available(&why)) throw InputError("colour views: " + why);
  }
  if (!o.perfect) validate_scan_params(o.scan);
  SimulatedWalkFolder out;
  WalkRecord& rec = out.record;
  const Pose2 start = o.start ? *o.start : random_start_pose(plan, o.walk);
  rec.walk = simulate_walk(plan, start, o.walk);
  rec.odometry_params = o.odometry;
  rec.odometry = simulate_odometry(rec.walk, o.odometry);
  rec.schedule = o.schedule;
  rec.plan_name = plan.name;
  rec.plan_hash = hex64(plan_hash(plan));
  create_directories_or_throw(dir);

  out.observation_steps = schedule_observations(rec.walk, rec.schedule);
  if (o.perfect) {
    rec.observation_settings = {{"source", "perfect"}, {"perfect_observer", o.perfect_params.to_json()}};
    const PerfectObserver observer(plan, o.perfect_params);
    for (int s : out.observation_steps) {
      const Pose2& truth = rec.walk.steps[static_cast<std::size_t>(s)].T_world_body;
      ObservationRecord obs;
      obs.observation = observer.observe(truth);
      obs.source = "perfect";
      obs.T_world_observer = truth;
      obs.metadata["step"] = std::to_string(s);
      const std::string rel = walk_observation_folder(s);
      create_directories_or_throw(dir + "/" + rel);
      save_observation(dir + "/" + rel + "/observation.json", obs);
      rec.observations.push_back({s, "perfect", rel});
    }
  } else {
    rec.observation_settings = {{"source", "scan"}, {"sensor", scan_params_to_json(o.scan)}};
    if (o.rgb) rec.observation_settings["rgb"] = true;
    const RayScene scene(extrude_plan(plan));
    std::unique_ptr<GlRenderer> gl;
    if (o.rgb) gl = std::make_unique<GlRenderer>(scene.mesh(), o.scan.geometry.width_px, o.scan.geometry.height_px);
    const std::string plan_hex = hex64(plan_hash(plan));
    for (int s : out.observation_steps) {
      const Pose2& truth = rec.walk.steps[static_cast<std::size_t>(s)].T_world_body;
      ScanParams p = o.scan;
      p.seed = mix64(o.scan_seed ^ mix64(0x5ca9ULL + static_cast<std::uint64_t>(s)));
      const auto t0 = Clock::now();
      SimulatedScan sim = simulate_scan(scene, truth, p);
      sim.truth.plan_hash = plan_hex;
      out.render_s += std::chrono::duration<double>(Clock::now() - t0).count();
      if (gl) out.rgb_s += render_scan_colour(*gl, sim);
      const std::string rel = walk_observation_folder(s);
      save_simulated_scan(dir + "/" + rel, sim);
      rec.observations.push_back({s, "scan", rel});
    }
  }
  save_walk(dir, rec);
  return out;
}

}  // namespace floorcast
