// The observation module end to end: mono (PALMS+) and LiDAR (PALMS) paths.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "floorcast/observe/observation_module.hpp"

#include "floorcast/core/limits.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/core/format.hpp"

namespace floorcast {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Union of the view clouds in the scan frame, each with its depth scale; every `stride`-th point
/// of each view.
PointCloud3f merge_views(const std::vector<ViewCloud>& views, const std::vector<double>& scales,
                         int stride = 1) {
  const std::size_t step = static_cast<std::size_t>(std::max(1, stride));
  std::vector<std::size_t> offset(views.size() + 1, 0);
  for (std::size_t k = 0; k < views.size(); ++k) {
    offset[k + 1] = offset[k] + (views[k].points_camera.size() + step - 1) / step;
  }
  PointCloud3f out(offset.back());
  tbb::parallel_for(std::size_t(0), views.size(), [&](std::size_t k) {
    const Eigen::Matrix3f R = (views[k].T_scan_camera.linear() * scales[k]).cast<float>();
    const Eigen::Vector3f t = views[k].T_scan_camera.translation().cast<float>();
    const PointCloud3f& src = views[k].points_camera;
    for (std::size_t i = 0, o = offset[k]; i < src.size(); i += step, ++o) out[o] = R * src[i] + t;
  });
  return out;
}


void observe_mono(const Scan& scan, const ObservationParams& params, ObservationResult& out) {
  ObservationDiagnostics& diag = out.diagnostics;
  auto t = Clock::now();
  BackProjectionResult bp = back_project_scan(scan, params.back_projection);
  out.stage_s["back_project"] = seconds_since(t);
  diag.views_dropped_far = bp.dropped_views;
  for (const int v : bp.dropped_views) {
    diag.warnings.push_back("view " + std::to_string(v) + " dropped: max depth >= " +
                            format_general(params.back_projection.max_view_depth_m) + " m");
  }
  std::vector<ViewCloud>& views = bp.views;
  const double H = params.scale.camera_height_m;

  // Scales.
  std::vector<double> rel(views.size(), 1.0);
  t = Clock::now();
  if (params.scale.mode == ScaleAlignment::kFull && views.size() >= 2) {
    if (params.scale.reference_view >= static_cast<int>(views.size())) {
      diag.warnings.push_back("scale.reference_view " + std::to_string(params.scale.reference_view) + ": only " +
                              std::to_string(views.size()) + " views kept, the last kept view is the reference");
    }
    diag.relative = estimate_relative_scales(views, params.scale);
    rel = diag.relative.scales;
    out.stage_s["scale_alignment.setup"] = diag.relative.setup_s;
    out.stage_s["scale_alignment.association"] = diag.relative.association_s;
    out.stage_s["scale_alignment.solve"] = diag.relative.solve_s;
  } else if (params.scale.mode == ScaleAlignment::kGround) {
    // Each view scaled by its own ground plane; views without one are dropped (PALMS+ Table 4).
    std::vector<GroundPlaneResult> g(views.size());
    tbb::parallel_for(std::size_t(0), views.size(), [&](std::size_t k) {
      g[k] = detect_ground_plane(merge_views({views[k]}, {1.0}, params.ground.point_stride), params.ground);
    });
    std::vector<ViewCloud> kept;
    std::vector<double> kept_scale;
    for (std::size_t k = 0; k < views.size(); ++k) {
      if (g[k].found && g[k].height_m < 0.0) {
        kept.push_back(std::move(views[k]));
        kept_scale.push_back(H / -g[k].height_m);
      } else {
        diag.views_dropped_no_ground.push_back(views[k].view_index);
        diag.warnings.push_back("view " + std::to_string(views[k].view_index) +
                                " dropped: no ground plane (" +
                                (g[k].found ? std::string("ground above camera") : g[k].reason) + ")");
      }
    }
    views = std::move(kept);
    rel = kept_scale;
  }
  out.stage_s["scale_alignment"] = seconds_since(t);
  for (const auto& v : views) {
    diag.views_used.push_back(v.view_index);
    diag.points_back_projected += v.points_camera.size();
    diag.pixels_edge_removed += v.pixels_edge_removed;
    diag.pixels_glass_removed += v.pixels_glass_removed;
  }
  diag.relative_scales = rel;
  if (views.empty()) {
    diag.warnings.push_back("no view left: empty observation");
    return;
  }

  // Ground plane on the views at their relative scales, global scale.
  t = Clock::now();
  diag.ground = detect_ground_plane(merge_views(views, rel, params.ground.point_stride), params.ground);
  out.stage_s["ground"] = seconds_since(t);
  double global = 1.0;
  if (params.scale.mode == ScaleAlignment::kFull) {
    if (diag.ground.found && diag.ground.height_m < 0.0) {
      global = H / -diag.ground.height_m;
    } else {
      diag.warnings.push_back("no ground plane (" +
                              (diag.ground.found ? std::string("ground above camera") : diag.ground.reason) +
                              "): global scale left at 1");
    }
  }
  diag.global_scale = global;
  diag.ground_height_after_m = diag.ground.found ? global * diag.ground.height_m : 0.0;
  diag.view_scales.resize(views.size());
  for (std::size_t k = 0; k < views.size(); ++k) diag.view_scales[k] = rel[k] * global;

  t = Clock::now();
  PointCloud3f cloud = merge_views(views, diag.view_scales);
  out.stage_s["merge"] = seconds_since(t);
  // Voxelise and slice, band by band (fallbacks when empty). Only the slab of whole voxels that
  // can reach the band is voxelised: identical result, a fraction of the points.
  std::vector<Eigen::Vector2d> pts;
  const double coarse_m = params.slice.subsample_voxel_m > 0.0 ? params.slice.subsample_voxel_m
                                                               : params.slice.merge_voxel_m;
  double voxelise_s = 0.0, slice_s = 0.0;
  for (const double half : params.slice.band_half_heights_m) {
    t = Clock::now();
    const PointCloud3f slab = slice_slab(cloud, half, coarse_m, params.slice.max_range_m);
    const PointCloud3f sub = voxel_downsample_two_level(slab, params.slice.merge_voxel_m,
                                                        params.slice.subsample_voxel_m, &diag.points_merged);
    diag.points_subsampled = sub.size();
    voxelise_s += seconds_since(t);
    t = Clock::now();
    pts = slice_points(sub, half, params.slice.max_range_m);
    slice_s += seconds_since(t);
    diag.band_half_height_m = half;
    if (!pts.empty()) break;
    diag.warnings.push_back("slice band +-" + format_general(half) + " m is empty");
  }
  out.stage_s["voxelise"] = voxelise_s;
  out.stage_s["slice"] = slice_s;
  diag.points_in_slice = pts.size();
  if (pts.empty()) diag.warnings.push_back("every slice band is empty: no segments");

  t = Clock::now();
  SegmentExtractionResult seg = extract_segments_2d(pts, params.segments, params.slice.max_range_m);
  out.observation.segments_m = std::move(seg.segments_m);
  out.observation.ray_ranges_m = std::move(seg.ray_ranges_m);
  out.observation.max_range_m = params.slice.max_range_m;
  out.stage_s["segments"] = seconds_since(t);

  if (params.planes.mono) {
    // Plane patches: the voxel-plane extractor on a thinned, voxelised copy of the cloud.
    t = Clock::now();
    PointCloud3f thin = voxel_downsample(merge_views(views, diag.view_scales, params.planes.mono_point_stride),
                                         params.planes.mono_voxel_m);
    const double r2 = params.slice.max_range_m * params.slice.max_range_m;
    thin.erase(std::remove_if(thin.begin(), thin.end(),
                              [r2](const Eigen::Vector3f& p) { return double(p.x()) * p.x() + double(p.y()) * p.y() > r2; }),
               thin.end());
    const VoxelPlaneResult vp = extract_planes_voxel(thin, params.lidar.voxel_plane);
    diag.planes_total = vp.planes.size();
    out.observation.planes = plane_patches(thin, vp.planes, params.planes);
    out.observation.plane_cell_m = params.planes.cell_m;
    out.stage_s["plane_patches"] = seconds_since(t);
  }
}

void observe_lidar(const Scan& scan, const ObservationParams& params, ObservationResult& out) {
  ObservationDiagnostics& diag = out.diagnostics;
  auto t = Clock::now();
  BackProjectionResult bp = back_project_scan(scan, params.lidar.back_projection);
  out.stage_s["back_project"] = seconds_since(t);
  diag.views_dropped_far = bp.dropped_views;
  for (const int v : bp.dropped_views) {
    diag.warnings.push_back("view " + std::to_string(v) + " dropped: max depth >= " +
                            format_general(params.lidar.back_projection.max_view_depth_m) + " m");
  }
  for (const auto& v : bp.views) {
    diag.views_used.push_back(v.view_index);
    diag.points_back_projected += v.points_camera.size();
    diag.pixels_edge_removed += v.pixels_edge_removed;
    diag.pixels_glass_removed += v.pixels_glass_removed;
  }
  diag.view_scales.assign(bp.views.size(), 1.0);
  diag.relative_scales.assign(bp.views.size(), 1.0);
  out.observation.max_range_m = params.lidar.max_range_m;
  if (bp.views.empty()) {
    diag.warnings.push_back("no view left: empty observation");
    return;
  }
  t = Clock::now();
  PointCloud3f cloud = merge_views(bp.views, diag.view_scales);
  cloud = voxel_downsample(cloud, params.lidar.voxel_m);
  {
    const double r2 = params.lidar.max_range_m * params.lidar.max_range_m;
    PointCloud3f kept;
    kept.reserve(cloud.size());
    for (const auto& p : cloud) {
      if (double(p.x()) * p.x() + double(p.y()) * p.y() <= r2) kept.push_back(p);
    }
    cloud = std::move(kept);
  }
  diag.points_merged = diag.points_subsampled = cloud.size();
  out.stage_s["voxelise"] = seconds_since(t);

  t = Clock::now();
  WallPlaneResult walls = extract_wall_segments(cloud, params.lidar);
  diag.planes_total = walls.planes.size();
  diag.wall_planes = walls.wall_planes.size();
  out.observation.segments_m = std::move(walls.segments_m);
  out.stage_s["planes"] = seconds_since(t);
  if (params.planes.lidar) {
    t = Clock::now();
    out.observation.planes = plane_patches(cloud, walls.planes, params.planes);
    out.observation.plane_cell_m = params.planes.cell_m;
    out.stage_s["plane_patches"] = seconds_since(t);
  }

  t = Clock::now();
  std::vector<Eigen::Vector2d> pts;
  for (const double half : params.slice.band_half_heights_m) {
    pts = slice_points(cloud, half, params.lidar.max_range_m);
    diag.band_half_height_m = half;
    if (!pts.empty()) break;
  }
  diag.points_in_slice = pts.size();
  out.observation.ray_ranges_m = ray_ranges_2d(pts, params.segments.num_rays,
                                               params.segments.ray_tolerance_deg, params.lidar.max_range_m);
  out.stage_s["rays"] = seconds_since(t);
}

}  // namespace

/// Points of a band |z| <= half around camera height (z = 0) within max_range_m horizontally,
/// projected to 2D.
std::vector<Eigen::Vector2d> slice_points(const PointCloud3f& cloud, double half, double max_range_m) {
  std::vector<Eigen::Vector2d> pts;
  const double r2 = max_range_m * max_range_m;
  for (const auto& p : cloud) {
    if (std::abs(p.z()) > half) continue;
    const double x = p.x(), y = p.y();
    if (x * x + y * y > r2) continue;
    pts.emplace_back(x, y);
  }
  return pts;
}

/// The points that can contribute to a slice of half height `half` after voxelisation with
/// voxel `voxel_m`: those in voxel layers (and horizontal range) within two voxels of the band.
/// Voxels are kept whole (their layers are either all in or all out), so voxelising this slab
/// and slicing gives exactly what voxelising everything and slicing gives.
PointCloud3f slice_slab(const PointCloud3f& cloud, double half, double voxel_m, double max_range_m) {
  const double margin = voxel_m > 0.0 ? 2.0 * voxel_m : 0.0;
  PointCloud3f out;
  double z_lo = -half, z_hi = half;
  if (voxel_m > 0.0) {
    z_lo = (std::floor(-half / voxel_m) - 2.0) * voxel_m;
    z_hi = (std::floor(half / voxel_m) + 3.0) * voxel_m;
  }
  const double r = max_range_m + 2.0 * margin;
  const double r2 = r * r;
  for (const auto& p : cloud) {
    if (p.z() < z_lo || p.z() >= z_hi) continue;
    if (double(p.x()) * p.x() + double(p.y()) * p.y() > r2) continue;
    out.push_back(p);
  }
  return out;
}

ObservationResult observe_scan(const Scan& scan, const ObservationParams& params) {
  const auto t0 = Clock::now();
  validate(params);
  check_limit("max_views", static_cast<double>(scan.views.size()), "scan", "views");
  {
    // Back-projected points, bounded before any cloud is allocated.
    const BackProjectionParams& bp = params.path == ObservationPath::kMono ? params.back_projection : params.lidar.back_projection;
    const double stride = std::max(1, bp.pixel_stride);
    double points = 0.0;
    for (const DepthView& v : scan.views) {
      points += std::ceil(v.intrinsics.width_px / stride) * std::ceil(v.intrinsics.height_px / stride);
    }
    check_limit("max_points", points, "scan back-projection (pixels of every view / pixel_stride^2)", "points");
  }
  if (params.path == ObservationPath::kMono && params.scale.mode == ScaleAlignment::kFull &&
      params.scale.reference_view >= static_cast<int>(scan.views.size())) {
    throw ParameterError("observation parameters: \"scale.reference_view\": " +
                             std::to_string(params.scale.reference_view) + " is not a view of this scan (it has " +
                             std::to_string(scan.views.size()) + " views: 0 to " +
                             std::to_string(static_cast<long long>(scan.views.size()) - 1) + ")",
                         "scale.reference_view");
  }
  ObservationResult out;
  out.diagnostics.path = to_string(params.path);
  out.diagnostics.scale_alignment =
      params.path == ObservationPath::kMono ? to_string(params.scale.mode) : "none";
  out.diagnostics.views_total = scan.views.size();
  if (params.path == ObservationPath::kMono) {
    observe_mono(scan, params, out);
  } else {
    observe_lidar(scan, params, out);
  }
  if (params.bev.enabled) {
    const auto tb = Clock::now();
    BevPredictionResult bev = predict_bev(scan, params.bev);
    out.observation.bev = std::move(bev.bev);
    out.diagnostics.bev_views_used = bev.views_used;
    out.diagnostics.bev_views_brought = bev.views_brought;
    out.diagnostics.bev_columns = bev.columns;
    out.diagnostics.bev_events = bev.events;
    for (std::string& w : bev.warnings) out.diagnostics.warnings.push_back(std::move(w));
    out.stage_s["bev"] = seconds_since(tb);
  }
  out.total_s = seconds_since(t0);
  return out;
}

}  // namespace floorcast
