// `floorcast track PLAN WALK_DIR ...`: sequential localization of a walk folder (`sim walk`, or a
// recording in the same layout): the first observation's posterior starts a tracker (PALMS
// particle filter or F3Loc histogram filter), the odometry moves it, later observations update it
// (scenarios/walk_tracking.hpp; --depth-dir: the scans' depth made elsewhere).
// Writes estimate.tum, errors.csv, metrics.json and track.png.
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/scenarios/run_directory.hpp"
#include "floorcast/scenarios/walk_tracking.hpp"
#include "floorcast/core/format.hpp"
#include "floorcast/core/image_io.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/observation_io.hpp"
#include "floorcast/core/scan_io.hpp"
#include "floorcast/core/trajectory_io.hpp"
#include "floorcast/eval/plot.hpp"
#include "floorcast/eval/sequential.hpp"
#include "floorcast/eval/trajectory_plot.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/sim/walk_io.hpp"
#include "floorcast/track/particle_filter.hpp"
#include "floorcast/track/run.hpp"
#include "observe_cli.hpp"

namespace floorcast::cli {
namespace {

void register_track(CLI::App& root) {
  struct Options {
    std::string plan, walk, filter = "pf", init, matcher, out;
    std::vector<std::string> params, matcher_params;
    std::uint64_t seed = 1;
    double range_m = SharedParams{}.range_m;
    ObserveCliOptions observe;
    bool quiet = false;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = root.add_subcommand("track", "Sequential localization of a walk folder: estimate.tum, errors.csv, metrics.json, track.png");
  cmd->add_option("PLAN", o->plan, "Floor-plan JSON")->required();
  cmd->add_option("WALK_DIR", o->walk, "Walk folder (floorcast sim walk -o DIR)")->required();
  cmd->add_option("--filter", o->filter,
                  "Tracker: pf (PALMS particle filter), hist (F3Loc histogram filter) or hist_mr (histogram filter, "
                  "coarse over the plan and fine in a window)")
      ->capture_default_str()
      ->check(CLI::IsMember(tracker_names()));
  cmd->add_option("--init", o->init, "pf: palms (default), proportional, uniform, uniform-ori; hist, hist_mr: posterior, uniform");
  cmd->add_option("--matcher", o->matcher,
                  "Matcher turning observations into posteriors (default: kernel for pf, ray for hist and hist_mr; a module "
                  "floorcast_matcher_NAME.so is found by name)");
  CLI::Option* tracker_param = cmd->add_option(
      "--tracker-param", o->params, "Tracker parameter override KEY=VALUE (repeatable; keys as in metrics.json's tracker_parameters)");
  add_deprecated_option(*cmd, "--param", tracker_param, o->params);
  cmd->add_option("--matcher-param", o->matcher_params,
                  "Matcher parameter override KEY=VALUE (repeatable; keys as in metrics.json's matcher_parameters)");
  CLI::Option* range_opt = cmd->add_option("--range", o->range_m, "Matching range, metres (the matcher's max_range_m; PALMS+ 4.4: 10)")
                               ->capture_default_str()
                               ->check(in_range(0.5, 60.0));
  cmd->add_option("--seed", o->seed, "Tracker seed")->capture_default_str();
  add_observation_options(*cmd, o->observe);
  cmd->add_flag("--quiet", o->quiet, "No progress output on stderr");
  cmd->add_option("-o,--output", o->out, "Output folder")->required();
  cmd->callback([o, range_opt] {
    refuse_output_inside_inputs(o->out, {o->walk});
    // Every parameter is parsed, typed and checked before any work.
    nlohmann::json tracker_overrides = nlohmann::json::object();
    for (const std::string& p : o->params) add_override(tracker_overrides, p, "--tracker-param");
    if (!o->init.empty()) tracker_overrides["init"] = o->init;
    if (o->filter == "pf" && !tracker_overrides.contains("seed")) tracker_overrides["seed"] = o->seed;
    // The walk's stated odometry error (walk.json odometry_uncertainty), --param odometry={...} keys on top.
    const WalkRecord walk = load_walk(o->walk);
    tracker_overrides = with_odometry(tracker_overrides, walk.odometry_uncertainty);
    nlohmann::json matcher_overrides = nlohmann::json::object();
    for (const std::string& p : o->matcher_params) add_override(matcher_overrides, p, "--matcher-param");
    if (range_opt->count() > 0 && matcher_overrides.contains("max_range_m")) {
      throw InputError("--range and --matcher-param max_range_m both set the matching range: give one");
    }
    SharedParams shared;
    shared.range_m = o->range_m;
    const std::string matcher_name = !o->matcher.empty() ? o->matcher : default_tracker_matcher(o->filter);
    const std::shared_ptr<const MatcherConfig> matcher_config = make_matcher_config(matcher_name, matcher_overrides, shared);
    const std::shared_ptr<const TrackerConfig> tracker_config = make_tracker_config(o->filter, tracker_overrides);
    (void)observation_params_from_cli(o->observe, nullptr);  // the observation module's, checked now
    const FloorPlan plan = load_floor_plan(o->plan);
    if (walk.observations.empty()) throw InputError(o->walk + ": the walk has no observation to start from");
    warn_plan_mismatch(o->walk, walk.plan_hash, o->plan, plan);
    const std::unique_ptr<Matcher> matcher = matcher_config->build(plan);
    const std::unique_ptr<Tracker> tracker = tracker_config->build(plan);

    // Every observation through the observation module (scans, with --depth-dir their depth made
    // elsewhere) and the matcher, the tracker along the odometry (scenarios/walk_tracking.hpp).
    WalkTrackingOptions options;
    options.observation_params = [o](const Scan& scan) { return observation_params_from_cli(o->observe, &scan); };
    options.depth_dir = o->observe.depth_dir;
    options.depth_file.kind = parse_depth_kind(o->observe.depth_kind);
    options.depth_file.integer_unit_m = o->observe.depth_unit_m;
    ProgressMeter progress("observations", o->quiet);
    const auto t_start = std::chrono::steady_clock::now();
    options.progress = [&](std::size_t done, std::size_t total) {
      progress.update(done, total, std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count());
    };
    const WalkTrack track = track_walk_folder(o->walk, walk, *matcher, *tracker, options);
    for (const std::string& n : track.notes) std::cerr << "floorcast: " << n << "\n";
    const TrackRun& run = track.run;
    const int first = track.first_step;
    const int updates = track.observations_used;
    ensure_directory(o->out);
    if (!run.started) {
      std::cout << tracker->name() << ": no track: " << run.failure << "\n";
      write_json(o->out + "/metrics.json", {{"started", false}, {"failure", run.failure}});
      throw CommandExit{kExitNoPose};
    }

    // Errors against the truth, the estimate trajectory, metrics.
    const SequentialRecord& rec = track.record;
    std::vector<StampedPose> estimate;
    std::string csv = "step,t_s,distance_m,est_x_m,est_y_m,est_yaw_deg,truth_x_m,truth_y_m,truth_yaw_deg,position_error_m,"
                      "yaw_error_deg,stage,support,updated,degenerate,time_s\n";
    for (std::size_t i = 0; i < run.steps.size(); ++i) {
      const TrackRunStep& s = run.steps[i];
      const WalkStep& truth = walk.walk.steps[static_cast<std::size_t>(s.step)];
      const Pose2& e = s.estimate.pose;
      estimate.push_back({s.t_s, e});
      char buf[512];
      std::snprintf(buf, sizeof(buf), "%d,%.6f,%.4f,%.4f,%.4f,%.3f,%.4f,%.4f,%.3f,%.4f,%.3f,%d,%.4f,%d,%d,%.6f\n", s.step, s.t_s,
                    rec.distance_m[i], e.x_m, e.y_m, rad_to_deg(e.yaw_rad), truth.T_world_body.x_m, truth.T_world_body.y_m,
                    rad_to_deg(truth.T_world_body.yaw_rad), rec.position_error_m[i], rec.yaw_error_deg[i], s.estimate.stage,
                    s.estimate.support, s.updated ? 1 : 0, s.estimate.degenerate ? 1 : 0, s.time_s);
      csv += buf;
    }
    const SequentialScoring& scoring = options.scoring;
    const SequentialOutcome& out = track.outcome;
    save_tum(o->out + "/estimate.tum", estimate, "floorcast track: " + tracker->name() + " estimate");
    write_text_file_atomic(o->out + "/errors.csv", csv);
    nlohmann::ordered_json m;
    m["started"] = true;
    m["tracker"] = tracker->name();
    m["matcher"] = matcher->name();
    const nlohmann::ordered_json metrics = walk_track_metrics(track, scoring, *tracker);
    for (auto it = metrics.begin(); it != metrics.end(); ++it) m[it.key()] = it.value();
    m["tracker_parameters"] = tracker->parameters();
    m["matcher_parameters"] = matcher->parameters();
    m["walk"] = o->walk;
    m["plan"] = o->plan;
    if (!options.depth_dir.empty()) {
      m["depth_dir"] = options.depth_dir;
      m["depth_kind"] = o->observe.depth_kind;
    }
    if (!track.notes.empty()) m["notes"] = track.notes;
    write_json(o->out + "/metrics.json", m);

    // The picture: truth, odometry, estimate; final particles; where it converged.
    std::vector<Vec2> truth_path, odom_path, est_path, conv;
    for (std::size_t k = static_cast<std::size_t>(first); k < walk.walk.steps.size(); ++k) {
      truth_path.push_back(walk.walk.steps[k].T_world_body.position_m());
      odom_path.push_back(walk.odometry.poses[k].position_m());
    }
    for (const StampedPose& s : estimate) est_path.push_back(s.pose.position_m());
    for (std::size_t i = 0; i < run.steps.size(); ++i) {
      if (run.steps[i].estimate.stage >= 2) {
        conv.push_back(est_path[i]);
        break;
      }
    }
    std::vector<MarkerLayer> markers;
    if (const auto* pf = dynamic_cast<const ParticleFilter*>(tracker.get())) {
      std::vector<Vec2> pts;
      const ParticleSet set = pf->particles();
      for (std::size_t i = 0; i < set.poses.size(); i += std::max<std::size_t>(1, set.poses.size() / 500)) {
        pts.push_back(set.poses[i].position_m());
      }
      markers.push_back({"particles (end)", pts, cv::Scalar(160, 160, 160), 2, true});
    }
    markers.push_back({"start", {truth_path.front()}, cv::Scalar(0, 160, 0), 7, true});
    markers.push_back({"true end", {truth_path.back()}, cv::Scalar(0, 0, 0), 6, true});
    if (!est_path.empty()) markers.push_back({"estimated end", {est_path.back()}, series_colour(0), 6, true});
    if (!conv.empty()) markers.push_back({"converged", conv, cv::Scalar(0, 0, 220), 8, false});
    // The estimate as pieces between jumps (an argmax that moves across the plan between steps is
    // a jump, not a walk through the walls): more than 1.5 m between consecutive steps.
    std::vector<TrajectoryLayer> lines = {{"true path", truth_path, series_colour(2), 3},
                                          {"odometry", odom_path, series_colour(1), 1}};
    int jumps = 0;
    for (std::size_t i = 0; i < est_path.size(); ++i) {
      if (i == 0 || (est_path[i] - est_path[i - 1]).norm() > 1.5) {
        if (i > 0) ++jumps;
        lines.push_back({lines.size() == 2 ? "estimate" : "", {}, series_colour(0), 2});
      }
      lines.back().points_m.push_back(est_path[i]);
    }
    std::ostringstream title;
    title << std::fixed << std::setprecision(2) << plan.name << ": " << tracker->name() << " (" << matcher->name()
          << "), RMSE " << out.rmse_m << " m, last-10 " << out.rmse_last_m << " m, "
          << (out.converged ? "converged" : "not converged") << (jumps ? ", " + std::to_string(jumps) + " jumps (gaps)" : "");
    const cv::Mat img = draw_plan_with_trajectories(plan, lines, markers, title.str());
    write_png(o->out + "/track.png", img);

    std::cout << std::fixed << std::setprecision(2) << tracker->name() << " (" << matcher->name() << "): "
              << run.steps.size() << " steps, " << updates << " observations; RMSE " << out.rmse_m << " m, last-10 RMSE "
              << out.rmse_last_m << " m, end error " << out.end_error_m << " m; success@1m "
              << (out.success[0] ? "yes" : "no") << "; "
              << (out.converged ? "converged after " + format_fixed(out.convergence_time_s - rec.t_s.front(), 1) + " s / " +
                                      format_fixed(out.convergence_distance_m, 1) + " m"
                                : std::string("not converged"))
              << " (" << describe_convergence(o->filter, tracker->parameters()) << ")"
              << "; " << std::setprecision(1) << 1e3 * rec.time_per_step_s << " ms/step -> " << o->out << "\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_track);
}  // namespace floorcast::cli
