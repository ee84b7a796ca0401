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
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "floorcast/core/image_io.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/scenarios/sampling.hpp"
#include "floorcast/scenarios/scenario.hpp"
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

/// The LiDAR path's voxelised cloud (scan frame) with the given minimum confidence.
PointCloud3f lidar_cloud(const Scan& scan, const ObservationParams& p, int min_confidence) {
  BackProjectionParams bp_params = p.lidar.back_projection;
  bp_params.min_confidence = min_confidence;
  const BackProjectionResult bp = back_project_scan(scan, bp_params);
  PointCloud3f cloud;
  for (const ViewCloud& v : bp.views) {
    const PointCloud3f pts = view_points_scan(v, 1.0);
    cloud.insert(cloud.end(), pts.begin(), pts.end());
  }
  return voxel_downsample(cloud, p.lidar.voxel_m);
}

/// The cloud's points between z_lo and z_hi (scan frame, camera at z = 0), projected to 2D.
std::vector<Eigen::Vector2d> band_points(const PointCloud3f& cloud, double z_lo, double z_hi) {
  std::vector<Eigen::Vector2d> out;
  for (const Eigen::Vector3f& q : cloud) {
    if (q.z() >= z_lo && q.z() <= z_hi) out.emplace_back(q.x(), q.y());
  }
  return out;
}

/// A picture of one scan for people: the truth within range (recovered parts green, missed red),
/// the observed segments (blue), the LiDAR points kept in the band at camera height (grey), the
/// observer (black), a 1 m scale bar and a title.
cv::Mat draw_scan_walls(const std::vector<Segment2>& truth, const std::vector<Segment2>& observed,
                        const std::vector<Eigen::Vector2d>& band, double range_m, const SegmentAccuracyParams& ap,
                        const std::string& title) {
  const double px_per_m = 60.0, half = range_m + 0.5;
  const int size = static_cast<int>(2.0 * half * px_per_m), top = 58;
  cv::Mat img(size + top, size, CV_8UC3, cv::Scalar(255, 255, 255));
  const auto to_px = [&](const Vec2& p) {
    return cv::Point2d((p.x() + half) * px_per_m, top + (half - p.y()) * px_per_m);
  };
  const double cos_max = std::cos(ap.max_angle_deg * kPi / 180.0);
  for (const Eigen::Vector2d& q : band) cv::circle(img, to_px(q), 1, cv::Scalar(170, 170, 170), cv::FILLED);
  for (const Segment2& t : truth) {
    const Vec2 d = t.b_m - t.a_m;
    const double len = d.norm();
    const int n = std::max(1, static_cast<int>(std::ceil(len / ap.sample_step_m)));
    for (int i = 0; i < n; ++i) {
      const Vec2 a = t.a_m + d * (static_cast<double>(i) / n), b = t.a_m + d * (static_cast<double>(i + 1) / n);
      const Vec2 mid = 0.5 * (a + b);
      bool found = false;
      for (const Segment2& o : observed) {
        const Vec2 od = o.b_m - o.a_m;
        if (od.norm() <= 0.0 || std::abs(od.dot(d)) < cos_max * od.norm() * len) continue;
        if (point_segment_distance(mid, o) <= ap.max_distance_m) {
          found = true;
          break;
        }
      }
      cv::line(img, to_px(a), to_px(b), found ? cv::Scalar(60, 180, 60) : cv::Scalar(40, 40, 220), 5, cv::LINE_AA);
    }
  }
  for (const Segment2& o : observed) cv::line(img, to_px(o.a_m), to_px(o.b_m), cv::Scalar(200, 90, 20), 2, cv::LINE_AA);
  cv::circle(img, to_px(Vec2::Zero()), 5, cv::Scalar(0, 0, 0), cv::FILLED);
  cv::line(img, to_px(Vec2::Zero()), to_px(Vec2(0.5, 0.0)), cv::Scalar(0, 0, 0), 2);
  cv::line(img, cv::Point(10, size + top - 15), cv::Point(10 + static_cast<int>(px_per_m), size + top - 15),
           cv::Scalar(0, 0, 0), 3);
  cv::putText(img, "1 m", cv::Point(14, size + top - 22), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1);
  // The title's lines (split at '\n'; a long plan name does not fit on one line of a 5 m picture).
  std::istringstream title_lines(title);
  std::string line;
  for (int row = 0; std::getline(title_lines, line); ++row) {
    cv::putText(img, line, cv::Point(8, 18 + 18 * row), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
  }
  cv::putText(img, "truth within range: green recovered, red missed; blue observed; grey LiDAR points +-0.2 m",
              cv::Point(8, 52), cv::FONT_HERSHEY_SIMPLEX, 0.42, cv::Scalar(60, 60, 60), 1, cv::LINE_AA);
  return img;
}

double mean_of(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m += x / static_cast<double>(v.size());
  return v.empty() ? 0.0 : m;
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
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--seed", o->seed, "Pose sampling seed (scan noise seed = seed + pose index)")->capture_default_str();
  cmd->add_option("--clearance", o->clearance_m, "Minimum distance of a pose to walls, metres")->capture_default_str();
  cmd->add_option("--sensor", o->sensor, "Scan preset")->capture_default_str()->check(
      CLI::IsMember({"lidar", "mono", "phone", "perfect"}));
  cmd->add_option("--range", o->range_m, "Truth range, metres (default: the preset's maximum range)");
  cmd->add_option("--reference-range", o->reference_range_m,
                  "Range of the perfect observation the scan is compared with beyond the sensor's range, metres")
      ->capture_default_str()
      ->check(CLI::Range(0.5, 100.0));
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
      c.overrides = parse_json_text(spec.substr(eq + 1), "--config " + c.label);
      if (lidar && !c.overrides.contains("path")) c.overrides["path"] = "lidar";
      try {
        apply_overrides(c.params, c.overrides);
      } catch (const InputError& e) {
        throw InputError("--config " + c.label + ": " + e.what());
      }
      configs.push_back(std::move(c));
    }
    if (!o->rooms.empty() && o->rooms.size() != o->plans.size()) {
      throw InputError("bench walls: --rooms needs one rooms file per --plan");
    }
    PerfectObservationParams pp;
    pp.max_range_m = range_m;
    pp.num_rays = 0;
    pp.blocking.open_doors_block = false;  // the scan renders doors as the plan has them: walls seen through open doors count
    pp.blocking.cut_height_m = preset.geometry.camera_height_m;
    SegmentAccuracyParams ap;
    PerfectObservationParams pp_ref = pp;
    pp_ref.max_range_m = std::max(o->reference_range_m, range_m);
    std::vector<double> slice_coverage, returns_coverage, confident_coverage;
    std::vector<double> truth_per_scan, truth_ref_per_scan, truth_ref_segments;
    double truth_total_m = 0.0, truth_ref_total_m = 0.0;
    int scans = 0;
    std::ostringstream per_scan;
    for (std::size_t pi = 0; pi < o->plans.size(); ++pi) {
      const FloorPlan plan = load_floor_plan(o->plans[pi]);
      const RayScene scene(extrude_plan(plan));
      const PerfectObserver observer(plan, pp);
      const PerfectObserver observer_ref(plan, pp_ref);
      const std::vector<Room> rooms = o->rooms.empty() ? plan.rooms : load_rooms_file(o->rooms[pi]);
      if (!o->region_kinds.empty() && rooms.empty()) {
        throw InputError(o->plans[pi] + ": --region-kinds needs room labels (the plan has none; give --rooms)");
      }
      const std::vector<Pose2> poses = sample_observation_poses(plan, o->points, o->seed, static_cast<int>(pi),
                                                                o->clearance_m, 0.1, o->region_kinds.empty() ? std::vector<Room>{} : rooms,
                                                                o->region_kinds);
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
        double truth_m = 0.0, truth_ref_m = 0.0;
        for (const Segment2& t : truth) truth_m += t.length_m();
        const std::vector<Segment2> truth_ref = observer_ref.observe(poses[k]).segments_m;
        for (const Segment2& t : truth_ref) truth_ref_m += t.length_m();
        truth_total_m += truth_m;
        truth_ref_total_m += truth_ref_m;
        truth_per_scan.push_back(truth_m);
        truth_ref_per_scan.push_back(truth_ref_m);
        truth_ref_segments.push_back(static_cast<double>(truth_ref.size()));
        std::vector<Eigen::Vector2d> band;
        if (lidar) {
          // Where the walls within range go: any return on them (floor and ceiling excluded), the
          // returns the path keeps (confidence), the band at camera height.
          const ObservationParams& p0 = configs.front().params;
          const double tol = ap.max_distance_m / 2.0;
          const double z_lo = -sp.geometry.camera_height_m + 0.1;
          const double z_hi = ExtrusionParams{}.wall_height_m - sp.geometry.camera_height_m - 0.1;
          returns_coverage.push_back(point_coverage(band_points(lidar_cloud(scan, p0, 0), z_lo, z_hi), truth, tol));
          const PointCloud3f kept = lidar_cloud(scan, p0, p0.lidar.back_projection.min_confidence);
          confident_coverage.push_back(point_coverage(band_points(kept, z_lo, z_hi), truth, tol));
          band = band_points(kept, -0.2, 0.2);
          slice_coverage.push_back(point_coverage(band, truth, tol));
        }
        for (Config& c : configs) {
          const ObservationResult r = observe_scan(scan, c.params);
          const SegmentAccuracy a = segment_accuracy(r.observation.segments_m, truth, ap);
          c.total.add(a);
          c.opaque.add(segment_accuracy(r.observation.segments_m, truth_opaque, ap));
          c.recall_per_scan.push_back(a.recall());
          c.segments_per_scan.push_back(a.segments);
          c.time_s.push_back(r.total_s);
          if (!o->dump_dir.empty()) {
            std::filesystem::create_directories(o->dump_dir);
            std::ostringstream title, file;
            title << std::fixed << std::setprecision(2) << plan.name << " #" << k << " " << c.label << " at ("
                  << poses[k].x_m << ", " << poses[k].y_m << ")\nrecall " << a.recall() << ", precision "
                  << a.precision() << ", " << a.segments << " segments";
            file << o->dump_dir << "/plan" << pi << "_scan" << std::setw(3) << std::setfill('0') << k << "_" << c.label
                 << ".png";
            write_png(file.str(), draw_scan_walls(truth, r.observation.segments_m, band, range_m, ap, title.str()));
          }
          if (o->per_scan) {
            per_scan << "  " << plan.name << " #" << k << " " << c.label << ": truth " << a.truth_length_m
                     << " m (" << truth_ref_m << " m, " << truth_ref.size() << " segments within "
                     << pp_ref.max_range_m << " m), recall " << a.recall() << ", precision " << a.precision() << ", "
                     << a.segments << " segments (" << a.spurious_segments << " spurious)"
                     << (lidar ? ", coverage returns " + std::to_string(returns_coverage.back()) + " confident " +
                                     std::to_string(confident_coverage.back()) + " slice " +
                                     std::to_string(slice_coverage.back())
                               : "")
                     << "\n";
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
    j["region_kinds"] = o->region_kinds;
    j["reference_range_m"] = pp_ref.max_range_m;
    j["reference_truth_length_m"] = truth_ref_total_m;
    j["reference_segments_median"] = quantile(truth_ref_segments, 0.5);
    j["match"] = {{"max_distance_m", ap.max_distance_m},
                  {"max_angle_deg", ap.max_angle_deg},
                  {"min_on_truth_fraction", ap.min_on_truth_fraction}};
    if (lidar) {
      j["slice_coverage_median"] = quantile(slice_coverage, 0.5);
      j["slice_coverage_mean"] = mean_of(slice_coverage);
      j["returns_coverage_mean"] = mean_of(returns_coverage);
      j["confident_coverage_mean"] = mean_of(confident_coverage);
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
              << " m of visible wall; " << truth_ref_total_m << " m within " << pp_ref.max_range_m << " m, median "
              << j["reference_segments_median"].get<double>() << " segments)\n";
    if (lidar) {
      std::cout << "  coverage of the truth within range by LiDAR points within " << ap.max_distance_m / 2.0
                << " m (means per scan): any return between floor and ceiling " << j["returns_coverage_mean"].get<double>()
                << ", kept by the confidence filter " << j["confident_coverage_mean"].get<double>()
                << ", kept and in the +-0.2 m band " << j["slice_coverage_mean"].get<double>() << "\n";
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
