#include "floorcast/bench/walls_bench.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "floorcast/core/fields.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/scenarios/sampling.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "floorcast/sim/scan_sim.hpp"

namespace floorcast {
namespace {

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

}  // namespace

std::vector<WallsBenchConfig> walls_bench_configs(const std::vector<std::string>& given, const std::string& sensor) {
  const bool lidar = scan_preset(sensor).sensor.kind == SensorKind::kLidar;
  std::vector<std::string> specs = given;
  if (specs.empty()) {
    if (lidar) {
      specs = {"pcl={\"path\":\"lidar\",\"lidar\":{\"extractor\":\"pcl\"}}",
               "voxelplane={\"path\":\"lidar\",\"lidar\":{\"extractor\":\"voxelplane\"}}"};
    } else {
      specs = {"mono={\"path\":\"mono\"}"};
    }
  }
  std::vector<WallsBenchConfig> configs;
  for (const std::string& spec : specs) {
    const auto eq = spec.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError("--config \"" + spec + "\": expected LABEL=JSON");
    WallsBenchConfig c;
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
  return configs;
}

WallsBenchReport run_walls_bench(const std::vector<WallsBenchPlan>& plans, const std::vector<WallsBenchConfig>& configs,
                                 const WallsBenchParams& params,
                                 const std::function<void(const std::string&, const cv::Mat&)>& on_picture) {
  if (configs.empty()) throw InputError("bench walls: no configuration");
  const ScanParams preset = scan_preset(params.sensor);
  WallsBenchReport report;
  WallsBenchSummary& sum = report.summary;
  sum.truth_range_m = params.range_m > 0.0 ? params.range_m : preset.sensor.max_range_m;
  sum.lidar = preset.sensor.kind == SensorKind::kLidar;
  const double range_m = sum.truth_range_m;
  const bool lidar = sum.lidar;
  for (const WallsBenchConfig& c : configs) report.configs.push_back({c, {}, {}, {}, {}, {}});
  PerfectObservationParams pp;
  pp.max_range_m = range_m;
  pp.num_rays = 0;
  pp.blocking.open_doors_block = false;  // the scan renders doors as the plan has them: walls seen through open doors count
  pp.blocking.cut_height_m = preset.geometry.camera_height_m;
  const SegmentAccuracyParams ap = sum.match;
  PerfectObservationParams pp_ref = pp;
  pp_ref.max_range_m = std::max(params.reference_range_m, range_m);
  sum.reference_range_m = pp_ref.max_range_m;
  std::vector<double> slice_coverage, returns_coverage, confident_coverage;
  std::vector<double> truth_ref_segments;
  double truth_total_m = 0.0, truth_ref_total_m = 0.0;
  for (std::size_t pi = 0; pi < plans.size(); ++pi) {
    const FloorPlan& plan = plans[pi].plan;
    const RayScene scene(extrude_plan(plan));
    const PerfectObserver observer(plan, pp);
    const PerfectObserver observer_ref(plan, pp_ref);
    const std::vector<Room>& rooms = plans[pi].rooms;
    if (!params.region_kinds.empty() && rooms.empty()) {
      throw InputError(plans[pi].path + ": --region-kinds needs room labels (the plan has none; give --rooms)");
    }
    const std::vector<Pose2> poses =
        sample_observation_poses(plan, params.points, params.seed, static_cast<int>(pi), params.clearance_m, 0.1,
                                 params.region_kinds.empty() ? std::vector<Room>{} : rooms, params.region_kinds);
    for (std::size_t k = 0; k < poses.size(); ++k) {
      const std::vector<Segment2> truth = observer.observe(poses[k]).segments_m;
      std::vector<Segment2> truth_opaque;
      for (const LabeledSegment& s : observer.visible_world_segments(poses[k].position_m())) {
        if (s.label == SurfaceLabel::kGlass) continue;
        truth_opaque.push_back({poses[k].inverse_transform(s.segment_m.a_m), poses[k].inverse_transform(s.segment_m.b_m)});
      }
      ScanParams sp = preset;
      sp.seed = params.seed + k;
      const Scan scan = simulate_scan(scene, poses[k], sp).scan;
      ++sum.scans;
      double truth_m = 0.0, truth_ref_m = 0.0;
      for (const Segment2& t : truth) truth_m += t.length_m();
      const std::vector<Segment2> truth_ref = observer_ref.observe(poses[k]).segments_m;
      for (const Segment2& t : truth_ref) truth_ref_m += t.length_m();
      truth_total_m += truth_m;
      truth_ref_total_m += truth_ref_m;
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
      for (WallsBenchConfigResult& c : report.configs) {
        const ObservationResult r = observe_scan(scan, c.config.params);
        const SegmentAccuracy a = segment_accuracy(r.observation.segments_m, truth, ap);
        c.total.add(a);
        c.opaque.add(segment_accuracy(r.observation.segments_m, truth_opaque, ap));
        c.recall_per_scan.push_back(a.recall());
        c.segments_per_scan.push_back(a.segments);
        c.time_s.push_back(r.total_s);
        if (params.pictures && on_picture) {
          std::ostringstream title, file;
          title << std::fixed << std::setprecision(2) << plan.name << " #" << k << " " << c.config.label << " at ("
                << poses[k].x_m << ", " << poses[k].y_m << ")\nrecall " << a.recall() << ", precision " << a.precision()
                << ", " << a.segments << " segments";
          file << "plan" << pi << "_scan" << std::setw(3) << std::setfill('0') << k << "_" << c.config.label << ".png";
          on_picture(file.str(), draw_scan_walls(truth, r.observation.segments_m, band, range_m, ap, title.str()));
        }
        WallsBenchScan scan_row;
        scan_row.plan_name = plan.name;
        scan_row.pose_index = static_cast<int>(k);
        scan_row.label = c.config.label;
        scan_row.accuracy = a;
        scan_row.reference_truth_m = truth_ref_m;
        scan_row.reference_segments = static_cast<int>(truth_ref.size());
        if (lidar) {
          scan_row.returns_coverage = returns_coverage.back();
          scan_row.confident_coverage = confident_coverage.back();
          scan_row.slice_coverage = slice_coverage.back();
        }
        report.per_scan.push_back(std::move(scan_row));
      }
    }
  }
  for (const WallsBenchPlan& p : plans) sum.plans.push_back(p.path);
  sum.points_per_plan = params.points;
  sum.seed = params.seed;
  sum.sensor = params.sensor;
  sum.truth_length_m = truth_total_m;
  sum.region_kinds = params.region_kinds;
  sum.reference_truth_length_m = truth_ref_total_m;
  sum.reference_segments_median = quantile(truth_ref_segments, 0.5);
  if (lidar) {
    sum.slice_coverage_median = quantile(slice_coverage, 0.5);
    sum.slice_coverage_mean = mean_of(slice_coverage);
    sum.returns_coverage_mean = mean_of(returns_coverage);
    sum.confident_coverage_mean = mean_of(confident_coverage);
  }
  for (const WallsBenchConfigResult& c : report.configs) {
    WallsBenchConfigSummary d;
    d.label = c.config.label;
    d.overrides = c.config.overrides;
    d.recall = c.total.recall();
    d.recall_opaque = c.opaque.recall();
    d.recall_median_per_scan = quantile(c.recall_per_scan, 0.5);
    d.precision = c.total.precision();
    d.segments_median = quantile(c.segments_per_scan, 0.5);
    d.segments_total = c.total.segments;
    d.spurious_segments = c.total.spurious_segments;
    d.angle_error_median_deg = quantile(c.total.angle_errors_deg, 0.5);
    d.angle_error_p90_deg = quantile(c.total.angle_errors_deg, 0.9);
    d.offset_error_median_m = quantile(c.total.offset_errors_m, 0.5);
    d.offset_error_p90_m = quantile(c.total.offset_errors_m, 0.9);
    d.time_median_s = quantile(c.time_s, 0.5);
    sum.configs.push_back(std::move(d));
  }
  return report;
}

nlohmann::ordered_json to_json(const WallsBenchSummary& summary) {
  using S = WallsBenchSummary;
  using C = WallsBenchConfigSummary;
  constexpr double kAny = 1e300;
  constexpr int kMany = 1 << 30;
  static const FieldList<C> config =
      FieldList<C>("walls bench configuration")
          .json("overrides", &C::overrides, "observation-parameter overrides of the configuration")
          .number("recall", &C::recall, 0.0, 1.0, "recovered share of the visible wall length")
          .number("recall_opaque", &C::recall_opaque, 0.0, 1.0, "the same without glass")
          .number("recall_median_per_scan", &C::recall_median_per_scan, 0.0, 1.0, "median of the per-scan recalls")
          .number("precision", &C::precision, 0.0, 1.0, "share of the observed length on true walls")
          .number("segments_median", &C::segments_median, 0.0, kAny, "median segments per scan")
          .integer("segments_total", &C::segments_total, 0, kMany, "segments of all scans")
          .integer("spurious_segments", &C::spurious_segments, 0, kMany, "segments on no true wall")
          .number("angle_error_median_deg", &C::angle_error_median_deg, 0.0, kAny, "direction error, median, deg")
          .number("angle_error_p90_deg", &C::angle_error_p90_deg, 0.0, kAny, "direction error, 90th percentile, deg")
          .number("offset_error_median_m", &C::offset_error_median_m, 0.0, kAny, "distance to the true wall, median, m")
          .number("offset_error_p90_m", &C::offset_error_p90_m, 0.0, kAny, "distance to the true wall, 90th percentile, m")
          .number("time_median_s", &C::time_median_s, 0.0, kAny, "observation module time per scan, median, s");
  static const FieldList<SegmentAccuracyParams> match =
      FieldList<SegmentAccuracyParams>("match")
          .number("max_distance_m", &SegmentAccuracyParams::max_distance_m, 0.0, kAny, "a sample on a wall within this, m")
          .number("max_angle_deg", &SegmentAccuracyParams::max_angle_deg, 0.0, 180.0, "and directions within this, deg")
          .number("min_on_truth_fraction", &SegmentAccuracyParams::min_on_truth_fraction, 0.0, 1.0,
                  "a segment with less of its length on walls is spurious");
  static const FieldList<S> f =
      FieldList<S>("walls bench")
          .texts("plans", &S::plans, "the plans")
          .integer("points_per_plan", &S::points_per_plan, 0, kMany, "poses per plan")
          .unsigned_integer("seed", &S::seed, "pose sampling seed")
          .text("sensor", &S::sensor, "scan preset")
          .number("truth_range_m", &S::truth_range_m, 0.0, kAny, "truth range, m")
          .integer("scans", &S::scans, 0, kMany, "scans simulated")
          .number("truth_length_m", &S::truth_length_m, 0.0, kAny, "visible wall length within the truth range, m")
          .texts("region_kinds", &S::region_kinds, "poses only in rooms of these kinds")
          .number("reference_range_m", &S::reference_range_m, 0.0, kAny, "range of the reference observation, m")
          .number("reference_truth_length_m", &S::reference_truth_length_m, 0.0, kAny, "wall length within it, m")
          .number("reference_segments_median", &S::reference_segments_median, 0.0, kAny, "its segments per scan, median")
          .section("match", &S::match, match)
          .number("slice_coverage_median", &S::slice_coverage_median, 0.0, 1.0, "LiDAR: truth covered by band points, median")
          .optional([](const S& s) { return s.lidar; })
          .number("slice_coverage_mean", &S::slice_coverage_mean, 0.0, 1.0, "LiDAR: the same, mean")
          .optional([](const S& s) { return s.lidar; })
          .number("returns_coverage_mean", &S::returns_coverage_mean, 0.0, 1.0, "LiDAR: by any return, mean")
          .optional([](const S& s) { return s.lidar; })
          .number("confident_coverage_mean", &S::confident_coverage_mean, 0.0, 1.0, "LiDAR: by confident returns, mean")
          .optional([](const S& s) { return s.lidar; })
          .custom(
              "configs",
              [](nlohmann::ordered_json& j, const S& s) {
                for (const C& c : s.configs) j["configs"][c.label] = config.write(c);
              },
              [](ParamReader&, S&) {}, "{label: {...}}", "per configuration of the observation module");
  return f.write(summary);
}

}  // namespace floorcast
