// `floorcast bench walls`: the front of run_walls_bench (bench/walls_bench.hpp): parses, loads the
// plans, prints.
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "floorcast/bench/walls_bench.hpp"
#include "floorcast/core/image_io.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/scenarios/scenario.hpp"

namespace floorcast::cli {
namespace {

void register_bench_walls(CLI::App& root) {
  CLI::App& bench = group(root, "bench", "Benchmarks (medians over repeats, same-run ratios)");
  struct Options {
    std::vector<std::string> plans;
    int points = 12;
    std::uint64_t seed = 21;
    double clearance_m = 0.5;
    std::string sensor = "lidar";
    double range_m = 0.0;
    double reference_range_m = 10.0;
    std::vector<std::string> rooms;
    std::vector<std::string> region_kinds;
    std::vector<std::string> configs;
    bool json = false;
    bool per_scan = false;
    std::string dump_dir;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = bench.add_subcommand(
      "walls", "Observed wall segments vs the perfect observation (recovered wall length, precision, errors)");
  cmd->add_option("--plan", o->plans, "Floor plans (default: the shipped apartment and office)");
  cmd->add_option("--points", o->points, "Poses per plan (sampled like `floorcast run`)")
      ->capture_default_str()
      ->check(in_range(1, 1000));
  cmd->add_option("--seed", o->seed, "Pose sampling seed (scan noise seed = seed + pose index)")->capture_default_str();
  cmd->add_option("--clearance", o->clearance_m, "Minimum distance of a pose to walls, metres")
      ->capture_default_str()
      ->check(in_range(0.0, 100.0));
  cmd->add_option("--sensor", o->sensor, "Scan preset")->capture_default_str()->check(
      CLI::IsMember({"lidar", "mono", "phone", "perfect"}));
  cmd->add_option("--range", o->range_m, "Truth range, metres (default: the preset's maximum range)")->check(above(0.0, 1e4));
  cmd->add_option("--reference-range", o->reference_range_m,
                  "Range of the perfect observation the scan is compared with beyond the sensor's range, metres")
      ->capture_default_str()
      ->check(in_range(0.5, 100.0));
  cmd->add_option("--rooms", o->rooms, "Rooms file per plan (labels for --region-kinds, for plans without rooms), in --plan order");
  cmd->add_option("--region-kinds", o->region_kinds,
                  "Sample poses only inside rooms of these kinds (e.g. walkway corridor hallway lobby)");
  cmd->add_option("--config", o->configs,
                  "LABEL=JSON observation-parameter overrides (keys as `observe`'s params); repeatable. "
                  "Default for lidar: pcl and voxelplane extractors with the default parameters");
  cmd->add_flag("--per-scan", o->per_scan, "Also print one line per scan and configuration");
  cmd->add_option("--dump", o->dump_dir, "Write one picture per scan and configuration into this folder");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->callback([o] {
    if (o->plans.empty()) {
      o->plans = {data_dir() + "/floorplans/buildings/apartment.json", data_dir() + "/floorplans/buildings/office.json"};
    }
    if (!o->rooms.empty() && o->rooms.size() != o->plans.size()) {
      throw InputError("bench walls: --rooms needs one rooms file per --plan");
    }
    WallsBenchParams params;
    params.points = o->points;
    params.seed = o->seed;
    params.clearance_m = o->clearance_m;
    params.sensor = o->sensor;
    params.range_m = o->range_m;
    params.reference_range_m = o->reference_range_m;
    params.region_kinds = o->region_kinds;
    params.pictures = !o->dump_dir.empty();
    const std::vector<WallsBenchConfig> configs = walls_bench_configs(o->configs, o->sensor);
    std::vector<WallsBenchPlan> plans;
    for (std::size_t pi = 0; pi < o->plans.size(); ++pi) {
      WallsBenchPlan p;
      p.path = o->plans[pi];
      p.plan = load_floor_plan(o->plans[pi]);
      p.rooms = o->rooms.empty() ? p.plan.rooms : load_rooms_file(o->rooms[pi]);
      plans.push_back(std::move(p));
    }
    const WallsBenchReport report = run_walls_bench(plans, configs, params, [&](const std::string& name, const cv::Mat& img) {
      std::filesystem::create_directories(o->dump_dir);
      write_png(o->dump_dir + "/" + name, img);
    });
    const WallsBenchSummary& sum = report.summary;
    if (o->json) {
      std::cout << to_json(sum).dump(2) << "\n";
      return;
    }
    std::ostringstream per_scan;
    if (o->per_scan) {
      for (const WallsBenchScan& s : report.per_scan) {
        const SegmentAccuracy& a = s.accuracy;
        per_scan << "  " << s.plan_name << " #" << s.pose_index << " " << s.label << ": truth " << a.truth_length_m
                 << " m (" << s.reference_truth_m << " m, " << s.reference_segments << " segments within "
                 << sum.reference_range_m << " m), recall " << a.recall() << ", precision " << a.precision() << ", "
                 << a.segments << " segments (" << a.spurious_segments << " spurious)"
                 << (sum.lidar ? ", coverage returns " + std::to_string(s.returns_coverage) + " confident " +
                                     std::to_string(s.confident_coverage) + " slice " + std::to_string(s.slice_coverage)
                               : "")
                 << "\n";
      }
    }
    std::cout << std::fixed << std::setprecision(3) << "bench walls: " << sum.scans << " " << o->sensor
              << " scans, truth = perfect observation (doors as in the plan) within " << sum.truth_range_m << " m ("
              << sum.truth_length_m << " m of visible wall; " << sum.reference_truth_length_m << " m within "
              << sum.reference_range_m << " m, median " << sum.reference_segments_median << " segments)\n";
    if (sum.lidar) {
      std::cout << "  coverage of the truth within range by LiDAR points within " << sum.match.max_distance_m / 2.0
                << " m (means per scan): any return between floor and ceiling " << sum.returns_coverage_mean
                << ", kept by the confidence filter " << sum.confident_coverage_mean << ", kept and in the +-0.2 m band "
                << sum.slice_coverage_mean << "\n";
    }
    std::cout << per_scan.str();
    for (const WallsBenchConfigSummary& d : sum.configs) {
      std::cout << "  " << d.label << ": recall " << d.recall << " (median per scan " << d.recall_median_per_scan
                << "; without glass " << d.recall_opaque << "), precision " << d.precision << ", segments median "
                << d.segments_median << " (" << d.spurious_segments << "/" << d.segments_total
                << " spurious), angle error median " << d.angle_error_median_deg << " deg p90 " << d.angle_error_p90_deg
                << ", offset median " << d.offset_error_median_m << " m p90 " << d.offset_error_p90_m
                << ", time median " << d.time_median_s << " s\n";
    }
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_bench_walls);
}  // namespace floorcast::cli
