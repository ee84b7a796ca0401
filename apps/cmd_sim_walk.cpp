// `floorcast sim walk PLAN ...`: a simulated walk with odometry and scheduled observations, written
// as a walk folder (sim/walk_io.hpp) that `floorcast track` reads, plus a picture of it.
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/core/image_io.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/random.hpp"
#include "floorcast/eval/plot.hpp"
#include "floorcast/eval/trajectory_plot.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/scan_sim.hpp"
#include "floorcast/sim/walk_io.hpp"
#include "floorcast/sim/walk_sim.hpp"

namespace floorcast::cli {
namespace {

void register_sim_walk(CLI::App& root) {
  struct Options {
    std::string plan, start = "random", odometry = "vio", sensor = "perfect", setting = "full", out;
    int steps = WalkParams{}.steps;
    int scan_every = 0;
    double scan_every_m = 0.0;
    bool no_initial = false;
    int rays = PerfectObservationParams{}.num_rays;
    double range_m = 0.0;  ///< 0: not given
    bool doors_open = false;
    bool rgb = false;
    std::uint64_t seed = 1;
    std::string walk_params, odometry_params;
  };
  auto o = std::make_shared<Options>();
  CLI::App& sim = group(root, "sim", "Simulator: rotating scans, perfect observations, 3D buildings");
  auto* cmd = sim.add_subcommand("walk", "Simulate a walk (truth, odometry, observations along it) into a walk folder");
  cmd->add_option("PLAN", o->plan, "Floor-plan JSON")->required();
  CLI::Option* pose_opt =
      cmd->add_option("--pose", o->start, "Start pose X,Y,YAW_DEG, or 'random' (seeded by --seed, in the largest free region)")
          ->capture_default_str();
  add_deprecated_option(*cmd, "--start", pose_opt, o->start);
  cmd->add_option("--steps", o->steps, "Samples of the walk (steps and pauses)")->capture_default_str()->check(in_range(2, 1000000));
  cmd->add_option("--odometry", o->odometry, "Odometry model: exact, vio (ARKit-like), pdr (step counting)")
      ->capture_default_str()
      ->check(CLI::IsMember({"exact", "vio", "pdr"}));
  cmd->add_option("--scan-every", o->scan_every, "Also observe every N samples (0 = only the initial scan)")
      ->capture_default_str()
      ->check(in_range(0, 1000000));
  cmd->add_option("--scan-every-m", o->scan_every_m, "Also observe every M metres walked (0 = off)")
      ->capture_default_str()
      ->check(in_range(0, 1e6));
  cmd->add_flag("--no-initial-scan", o->no_initial, "No observation at the start (default: scan, then walk)");
  std::vector<std::string> sensors = scan_preset_names();
  cmd->add_option("--sensor", o->sensor, "Observations: a sensor preset (simulated scans) or 'perfect' (exact walls)")
      ->capture_default_str()
      ->check(CLI::IsMember(sensors));
  cmd->add_option("--setting", o->setting, "Scans: full rotation, partial (3 views) or single (one forward view, F3Loc)")
      ->capture_default_str()
      ->check(CLI::IsMember({"full", "partial", "single"}));
  cmd->add_option("--rays", o->rays, "Perfect observations: equiangular rays")->capture_default_str()->check(in_range(0, 3600));
  cmd->add_option("--range", o->range_m,
                  "Observation range, metres (perfect observations: default 10; scans: default the preset's maximum range)")
      ->check(in_range(0.01, 1e4));
  cmd->add_flag("--doors-open", o->doors_open, "Perfect observations: open doors stay open (default: all closed)");
  cmd->add_flag("--rgb", o->rgb,
                "Scans: also render every view of every observation in colour (OpenGL through OSMesa, headless) from "
                "its true camera pose: view_NNN_rgb.png, for a depth network (then `track --depth-dir`); with "
                "--setting single, F3Loc's one forward view per observation");
  cmd->add_option("--walk-params", o->walk_params, "JSON object of walk parameter overrides (keys of walk.json walk_params)");
  cmd->add_option("--odometry-params", o->odometry_params, "JSON object of odometry parameter overrides");
  cmd->add_option("--seed", o->seed, "Random seed (walk, odometry, sensor noise)")->capture_default_str();
  cmd->add_option("-o,--output", o->out, "Output walk folder")->required();
  cmd->callback([o] {
    const FloorPlan plan = load_floor_plan(o->plan);
    WalkParams wp;
    wp.steps = o->steps;
    wp.seed = o->seed;
    if (!o->walk_params.empty()) {
      const nlohmann::json j = parse_json_text(o->walk_params, "--walk-params");
      wp.apply_overrides(j);
    }
    OdometryParams op;
    op.seed = mix64(o->seed ^ 0x0d0e7e11ULL);
    if (!o->odometry_params.empty()) {
      const nlohmann::json j = parse_json_text(o->odometry_params, "--odometry-params");
      op.apply_overrides(j);
    }
    op.apply_overrides({{"model", o->odometry}});
    if (o->rgb && o->sensor == "perfect") {
      throw InputError("--rgb renders the views of simulated scans: give a sensor preset (--sensor mono, phone, lidar, ...)");
    }
    WalkSimulationOptions so;
    so.walk = wp;
    so.odometry = op;
    so.schedule = {!o->no_initial, o->scan_every, o->scan_every_m};
    if (!is_random_pose(o->start)) so.start = parse_pose(o->start, "--pose");
    so.perfect = o->sensor == "perfect";
    so.perfect_params.num_rays = o->rays;
    if (o->range_m > 0.0) so.perfect_params.max_range_m = o->range_m;
    so.perfect_params.blocking.open_doors_block = !o->doors_open;
    if (!so.perfect) {
      so.scan = scan_preset(o->sensor);
      parse_scan_setting(o->setting, so.scan.setting);
      if (o->range_m > 0.0) so.scan.sensor.max_range_m = o->range_m;
    }
    so.scan_seed = o->seed;
    so.rgb = o->rgb;
    const SimulatedWalkFolder written = write_simulated_walk(plan, so, o->out);
    const WalkRecord& rec = written.record;
    const std::vector<int>& steps = written.observation_steps;
    const Pose2 start = rec.walk.steps.front().T_world_body;

    // The picture: true path, odometry, start, observations.
    std::vector<Vec2> truth, odom, observed;
    for (const WalkStep& w : rec.walk.steps) truth.push_back(w.T_world_body.position_m());
    for (const Pose2& p : rec.odometry.poses) odom.push_back(p.position_m());
    for (int s : steps) observed.push_back(rec.walk.steps[static_cast<std::size_t>(s)].T_world_body.position_m());
    const WalkSummary& sm = rec.walk.summary;
    std::ostringstream title;
    title << std::fixed << std::setprecision(1) << plan.name << ": walk of " << rec.walk.steps.size() << " steps, "
          << sm.length_m << " m in " << sm.duration_s << " s; odometry " << o->odometry;
    const cv::Mat img = draw_plan_with_trajectories(
        plan, {{"true path", truth, series_colour(2), 3}, {"odometry (" + o->odometry + ")", odom, series_colour(1), 2}},
        {{"start", {truth.front()}, cv::Scalar(0, 160, 0), 7, true},
         {"end", {truth.back()}, cv::Scalar(0, 0, 0), 6, true},
         {"observation", observed, series_colour(0), 5, false}},
        title.str());
    write_png(o->out + "/walk.png", img);

    const double drift = (rec.walk.steps.back().T_world_body.position_m() - rec.odometry.poses.back().position_m()).norm();
    std::cout << std::fixed << std::setprecision(2) << "walk: " << rec.walk.steps.size() << " samples, " << sm.length_m
              << " m in " << sm.duration_s << " s (" << sm.speed_mps << " m/s, " << sm.cadence_hz << " steps/s, "
              << sm.pauses << " pauses, " << std::setprecision(0) << 100.0 * sm.transitional_share
              << "% in transitional space, longest straight " << std::setprecision(1) << sm.longest_straight_m
              << " m) from " << format_pose(start) << "; odometry " << o->odometry << " ends " << std::setprecision(2)
              << drift << " m off; " << steps.size() << " observations (" << o->sensor << (o->rgb ? ", colour views" : "")
              << ") -> " << o->out << "\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_sim_walk);
}  // namespace floorcast::cli
