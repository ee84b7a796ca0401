// `floorcast bench walls`: accuracy of the observation module's wall segments against the perfect
// observation of the same pose (visible walls within the sensor's range, doors as in the plan): recovered
// fraction of the visible wall length, precision, spurious segments, angle and offset errors, per
// configuration of the module, on simulated scans at sampled poses of one or more plans.
#include <algorithm>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/scenarios/sampling.hpp"
#include "floorcast/eval/observation_accuracy.hpp"
#include "floorcast/observe/observation_module.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "floorcast/sim/scan_sim.hpp"

namespace floorcast::cli {
namespace {

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(pos);
  const std::size_t hi = std::min(v.size() - 1, lo + 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

struct Config {
  std::string label;
  ObservationParams params;
  nlohmann::json overrides;
  SegmentAccuracy total;
  SegmentAccuracy opaque;  ///< against the truth without glass (which the LiDAR barely returns)
  std::vector<double> recall_per_scan, segments_per_scan, time_s;
};

/// The 2D points the LiDAR path's cloud has in the slice band at camera height: what any wall
/// extractor could see there.
std::vector<Eigen::Vector2d> lidar_slice(const Scan& scan, const ObservationParams& p, double half_m) {
  const BackProjectionResult bp = back_project_scan(scan, p.lidar.back_projection);
  PointCloud3f cloud;
  for (const ViewCloud& v : bp.views) {
    const PointCloud3f pts = view_points_scan(v, 1.0);
    cloud.insert(cloud.end(), pts.begin(), pts.end());
  }
  return slice_points(voxel_downsample(cloud, p.lidar.voxel_m), half_m, p.lidar.max_range_m);
}

void register_bench_walls(CLI::App& root) {
  CLI::App& bench = group(root, "bench", "Benchmarks (medians over repeats, same-run ratios)");
  struct Options {
    std::vector<std::string> plans;
    int points = 12;
    std::uint64_t seed = 21;
    double clearance_m = 0.5;
    std::string sensor = "lidar";
    double range_m = 0.0;
    std::vector<std::string> configs;
    bool json = false;
    bool per_scan = false;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = bench.add_subcommand(
      "walls", "Observed wall segments vs the perfect observation (recovered wall length, precision, errors)");
  cmd->add_option("--plan", o->plans, "Floor plans (default: the shipped apartment and office)");
  cmd->add_option("--points", o->points, "Poses per plan (sampled like `floorcast run`)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--seed", o->seed, "Pose sampling seed (scan noise seed = seed + pose index)")->capture_default_str();
  cmd->add_option("--clearance", o->clearance_m, "Minimum distance of a pose to walls, metres")->capture_default_str();
  cmd->add_option("--sensor", o->sensor, "Scan preset")->capture_default_str()->check(
      CLI::IsMember({"lidar", "mono", "phone", "perfect"}));
  cmd->add_option("--range", o->range_m, "Truth range, metres (default: the preset's maximum range)");
  cmd->add_option("--config", o->configs,
                  "LABEL=JSON observation-parameter overrides (keys as `observe`'s params); repeatable. "
                  "Default for lidar: pcl and voxelplane extractors with the default parameters");
  cmd->add_flag("--per-scan", o->per_scan, "Also print one line per scan and configuration");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->callback([o] {
    if (o->plans.empty()) {
      o->plans = {source_dir() + "/floorplans/buildings/apartment.json",
                  source_dir() + "/floorplans/buildings/office.json"};
    }
    const ScanParams preset = scan_preset(o->sensor);
    const double range_m = o->range_m > 0.0 ? o->range_m : preset.sensor.max_range_m;
    const bool lidar = preset.sensor.kind == SensorKind::kLidar;
    std::vector<Config> configs;
    std::vector<std::string> specs = o->configs;
    if (specs.empty()) {
      if (lidar) {
        specs = {"pcl={\"path\":\"lidar\",\"lidar\":{\"extractor\":\"pcl\"}}",
                 "voxelplane={\"path\":\"lidar\",\"lidar\":{\"extractor\":\"voxelplane\"}}"};
      } else {
        specs = {"mono={\"path\":\"mono\"}"};
      }
    }
    for (const std::string& spec : specs) {
      const auto eq = spec.find('=');
      if (eq == std::string::npos || eq == 0) throw InputError("--config \"" + spec + "\": expected LABEL=JSON");
      Config c;
      c.label = spec.substr(0, eq);
      try {
        c.overrides = nlohmann::json::parse(spec.substr(eq + 1));
      } catch (const std::exception& e) {
        throw InputError("--config " + c.label + ": not valid JSON: " + e.what());
      }
      if (lidar && !c.overrides.contains("path")) c.overrides["path"] = "lidar";
      try {
        apply_overrides(c.params, c.overrides);
      } catch (const InputError& e) {
        throw InputError("--config " + c.label + ": " + e.what());
      }
      configs.push_back(std::move(c));
    }
    PerfectObservationParams pp;
    pp.max_range_m = range_m;
    pp.num_rays = 0;
    pp.blocking.open_doors_block = false;  // the scan renders doors as the plan has them: walls seen through open doors count
    pp.blocking.cut_height_m = preset.geometry.camera_height_m;
    SegmentAccuracyParams ap;
    std::vector<double> slice_coverage;
    double truth_total_m = 0.0;
    int scans = 0;
    std::ostringstream per_scan;
    for (std::size_t pi = 0; pi < o->plans.size(); ++pi) {
      const FloorPlan plan = load_floor_plan(o->plans[pi]);
      const RayScene scene(extrude_plan(plan));
      const PerfectObserver observer(plan, pp);
      const std::vector<Pose2> poses =
          sample_observation_poses(plan, o->points, o->seed, static_cast<int>(pi), o->clearance_m);
      for (std::size_t k = 0; k < poses.size(); ++k) {
        const std::vector<Segment2> truth = observer.observe(poses[k]).segments_m;
        std::vector<Segment2> truth_opaque;
        for (const LabeledSegment& s : observer.visible_world_segments(poses[k].position_m())) {
          if (s.label == SurfaceLabel::kGlass) continue;
          truth_opaque.push_back({poses[k].inverse_transform(s.segment_m.a_m), poses[k].inverse_transform(s.segment_m.b_m)});
        }
        ScanParams sp = preset;
        sp.seed = o->seed + k;
        const Scan scan = simulate_scan(scene, poses[k], sp).scan;
        ++scans;
        for (const Segment2& t : truth) truth_total_m += t.length_m();
        if (lidar) {
          slice_coverage.push_back(
              point_coverage(lidar_slice(scan, configs.front().params, 0.2), truth, ap.max_distance_m / 2.0));
        }
        for (Config& c : configs) {
          const ObservationResult r = observe_scan(scan, c.params);
          const SegmentAccuracy a = segment_accuracy(r.observation.segments_m, truth, ap);
          c.total.add(a);
          c.opaque.add(segment_accuracy(r.observation.segments_m, truth_opaque, ap));
          c.recall_per_scan.push_back(a.recall());
          c.segments_per_scan.push_back(a.segments);
          c.time_s.push_back(r.total_s);
          if (o->per_scan) {
            per_scan << "  " << plan.name << " #" << k << " " << c.label << ": truth " << a.truth_length_m
                     << " m, recall " << a.recall() << ", precision " << a.precision() << ", " << a.segments
                     << " segments (" << a.spurious_segments << " spurious)"
                     << (lidar ? ", slice coverage " + std::to_string(slice_coverage.back()) : "") << "\n";
          }
        }
      }
    }
    nlohmann::ordered_json j;
    j["plans"] = o->plans;
    j["points_per_plan"] = o->points;
    j["seed"] = o->seed;
    j["sensor"] = o->sensor;
    j["truth_range_m"] = range_m;
    j["scans"] = scans;
    j["truth_length_m"] = truth_total_m;
    j["match"] = {{"max_distance_m", ap.max_distance_m},
                  {"max_angle_deg", ap.max_angle_deg},
                  {"min_on_truth_fraction", ap.min_on_truth_fraction}};
    if (lidar) {
      j["slice_coverage_median"] = quantile(slice_coverage, 0.5);
      double mean = 0.0;
      for (double v : slice_coverage) mean += v / static_cast<double>(slice_coverage.size());
      j["slice_coverage_mean"] = mean;
    }
    for (const Config& c : configs) {
      nlohmann::ordered_json d;
      d["overrides"] = c.overrides;
      d["recall"] = c.total.recall();
      d["recall_opaque"] = c.opaque.recall();
      d["recall_median_per_scan"] = quantile(c.recall_per_scan, 0.5);
      d["precision"] = c.total.precision();
      d["segments_median"] = quantile(c.segments_per_scan, 0.5);
      d["segments_total"] = c.total.segments;
      d["spurious_segments"] = c.total.spurious_segments;
      d["angle_error_median_deg"] = quantile(c.total.angle_errors_deg, 0.5);
      d["angle_error_p90_deg"] = quantile(c.total.angle_errors_deg, 0.9);
      d["offset_error_median_m"] = quantile(c.total.offset_errors_m, 0.5);
      d["offset_error_p90_m"] = quantile(c.total.offset_errors_m, 0.9);
      d["time_median_s"] = quantile(c.time_s, 0.5);
      j["configs"][c.label] = d;
    }
    if (o->json) {
      std::cout << j.dump(2) << "\n";
      return;
    }
    std::cout << std::fixed << std::setprecision(3) << "bench walls: " << scans << " " << o->sensor
              << " scans, truth = perfect observation (doors as in the plan) within " << range_m << " m (" << truth_total_m
              << " m of visible wall)\n";
    if (lidar) {
      std::cout << "  slice coverage (truth length with a LiDAR point within " << ap.max_distance_m / 2.0
                << " m in the +-0.2 m band): mean " << j["slice_coverage_mean"].get<double>() << "\n";
    }
    std::cout << per_scan.str();
    for (const Config& c : configs) {
      const auto& d = j["configs"][c.label];
      std::cout << "  " << c.label << ": recall " << d["recall"].get<double>() << " (median per scan "
                << d["recall_median_per_scan"].get<double>() << "; without glass " << d["recall_opaque"].get<double>()
                << "), precision " << d["precision"].get<double>()
                << ", segments median " << d["segments_median"].get<double>() << " (" << c.total.spurious_segments
                << "/" << c.total.segments << " spurious), angle error median " << d["angle_error_median_deg"].get<double>()
                << " deg p90 " << d["angle_error_p90_deg"].get<double>() << ", offset median "
                << d["offset_error_median_m"].get<double>() << " m p90 " << d["offset_error_p90_m"].get<double>()
                << ", time median " << d["time_median_s"].get<double>() << " s\n";
    }
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_bench_walls);
}  // namespace floorcast::cli
