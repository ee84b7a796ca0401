#include "floorcast/bench/sim_bench.hpp"

#include <tbb/info.h>

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <memory>

#include "floorcast/core/fields.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/sim/gl_renderer.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "floorcast/sim/scan_sim.hpp"

namespace floorcast {
namespace {

double process_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

template <typename F>
double time_ms(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// The most open interior point of the plan (largest distance to any wall or obstacle): a
/// deterministic, valid observer position.
Pose2 most_open_pose(const FloorPlan& plan) {
  RasterOptions ro;
  ro.resolution_m_per_px = 0.1;
  ro.blocking.obstacles_block = true;  // obstacles of any height count
  ro.blocking.cut_height_m = 0.01;
  const PlanRasters r = make_plan_rasters(plan, ro);
  double best = -1.0;
  Pose2 pose;
  for (int row = 0; row < r.valid.rows; ++row)
    for (int col = 0; col < r.valid.cols; ++col) {
      if (!r.valid.at<unsigned char>(row, col)) continue;
      const double d = r.distance_m.at<float>(row, col);
      if (d > best) {
        best = d;
        const Vec2 c = r.grid.cell_center_m(row, col);
        pose = {c.x(), c.y(), 0.0};
      }
    }
  if (best < 0.0) throw InputError("bench sim: the plan has no interior");
  check_observer_pose(plan, pose, "bench sim");
  return pose;
}

}  // namespace

SimBenchResult bench_sim(const FloorPlan& plan, const std::string& plan_name, const SimBenchParams& params) {
  const Pose2 pose = most_open_pose(plan);
  const auto t_scene0 = std::chrono::steady_clock::now();
  const RayScene scene(extrude_plan(plan));
  const double scene_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_scene0).count();

  // Renderer: the default mono view geometry with exact depth (ray casting and depth output).
  const ScanParams render_params = scan_preset("perfect");
  const std::vector<Ray3> rays = scan_camera_rays(pose, render_params);
  const double n_rays = static_cast<double>(rays.size());
  PreparedRays prepared = scene.prepare(rays);
  (void)simulate_scan(scene, pose, render_params);  // warm-up (thread pool, caches)
  (void)scene.intersect_prepared(prepared);

  // Interleave the two measurements so machine noise hits both alike.
  double load_before[3] = {0.0, 0.0, 0.0};
  if (getloadavg(load_before, 3) < 1) load_before[0] = -1.0;
  std::vector<double> render_ms, raw_ms, mono_ms, mono_cpu_ms, lidar_ms, phone_ms;
  std::size_t hits = 0;
  for (int r = 0; r < params.repeats; ++r) {
    render_ms.push_back(time_ms([&] { (void)simulate_scan(scene, pose, render_params); }));
    raw_ms.push_back(time_ms([&] { hits = scene.intersect_prepared(prepared); }));
  }
  ScanParams mono = scan_preset("mono");
  ScanParams lidar = scan_preset("lidar");
  ScanParams phone = scan_preset("phone");
  for (int r = 0; r < params.repeats; ++r) {
    mono.seed = lidar.seed = phone.seed = static_cast<std::uint64_t>(r);
    const double cpu0 = process_cpu_ms();
    mono_ms.push_back(time_ms([&] { (void)simulate_scan(scene, pose, mono); }));
    mono_cpu_ms.push_back(process_cpu_ms() - cpu0);
    lidar_ms.push_back(time_ms([&] { (void)simulate_scan(scene, pose, lidar); }));
    phone_ms.push_back(time_ms([&] { (void)simulate_scan(scene, pose, phone); }));
  }
  // OpenGL (OSMesa, llvmpipe) on the same six views: depth only (the independent rasteriser) and
  // colour + depth + labels (the RGB views of `sim scan --rgb`), 640x480 each.
  std::vector<double> gl_ms, rgb_ms;
  double gl_setup_ms = 0.0;
  std::string gl_name;
  {
    const Scan views = simulate_scan(scene, pose, render_params).scan;
    std::unique_ptr<GlRenderer> gl;
    gl_setup_ms = time_ms([&] {
      gl = std::make_unique<GlRenderer>(scene.mesh(), render_params.geometry.width_px, render_params.geometry.height_px);
    });
    gl_name = gl->renderer_name();
    const Eigen::Isometry3d T_world_scan = scan_frame_in_world(pose, render_params.geometry.camera_height_m);
    for (const DepthView& v : views.views) (void)gl->render(T_world_scan * v.T_scan_camera, v.intrinsics);  // warm-up
    for (int r = 0; r < params.repeats; ++r) {
      gl_ms.push_back(time_ms([&] {
        for (const DepthView& v : views.views) (void)gl->render_depth(T_world_scan * v.T_scan_camera, v.intrinsics);
      }));
      rgb_ms.push_back(time_ms([&] {
        for (const DepthView& v : views.views) (void)gl->render(T_world_scan * v.T_scan_camera, v.intrinsics);
      }));
    }
  }
  const double rgb_fps = 6.0 / (median(rgb_ms) / 1e3);
  const double renderer = n_rays / median(render_ms) / 1e3;  // Mrays/s
  const double raw = n_rays / median(raw_ms) / 1e3;
  SimBenchResult out;
  out.pose = pose;
  out.scan_ms = median(mono_ms);
  out.renderer_mrays_per_s = renderer;
  out.embree_raw_mrays_per_s = raw;
  out.ratio = renderer / raw;
  out.plan = plan_name;
  out.triangles = scene.mesh().num_triangles();
  out.threads = tbb::info::default_concurrency();
  out.rays_per_scan = rays.size();
  out.hit_fraction = static_cast<double>(hits) / n_rays;
  out.scene_build_ms = scene_ms;
  out.scan_cpu_ms = median(mono_cpu_ms);
  out.load_average_1min = load_before[0];
  out.lidar_scan_ms = median(lidar_ms);
  out.phone_scan_ms = median(phone_ms);
  out.osmesa_6_views_ms = median(gl_ms);
  out.rgb_6_views_ms = median(rgb_ms);
  out.rgb_frames_per_s_640x480 = rgb_fps;
  out.gl_first_use_ms = gl_setup_ms;
  out.gl_renderer = gl_name;
  out.repeats = params.repeats;
  return out;
}

nlohmann::ordered_json to_json(const SimBenchResult& r) {
  using R = SimBenchResult;
  constexpr double kAny = 1e300;
  static const FieldList<R> f =
      FieldList<R>("sim bench")
          .number("scan_ms", &R::scan_ms, 0.0, kAny, "default mono scan, median wall ms")
          .number("renderer_mrays_per_s", &R::renderer_mrays_per_s, 0.0, kAny, "scan renderer (exact depth), Mrays/s")
          .number("embree_raw_mrays_per_s", &R::embree_raw_mrays_per_s, 0.0, kAny, "raw Embree stream, Mrays/s")
          .number("ratio", &R::ratio, 0.0, kAny, "renderer / raw (target >= 0.60)")
          .text("plan", &R::plan, "the plan file's name")
          .unsigned_integer("triangles", &R::triangles, "triangles of the extruded plan")
          .integer("threads", &R::threads, 0, 1 << 20, "TBB threads")
          .unsigned_integer("rays_per_scan", &R::rays_per_scan, "rays of a mono scan (6 x 640x480)")
          .number("hit_fraction", &R::hit_fraction, 0.0, 1.0, "share of the rays that hit")
          .number("scene_build_ms", &R::scene_build_ms, 0.0, kAny, "extrusion and Embree scene, ms")
          .number("scan_cpu_ms", &R::scan_cpu_ms, 0.0, kAny, "default mono scan, median CPU ms (all threads)")
          .number("load_average_1min", &R::load_average_1min, -1.0, kAny, "load average before (-1: unknown)")
          .number("lidar_scan_ms", &R::lidar_scan_ms, 0.0, kAny, "default LiDAR scan, median ms")
          .number("phone_scan_ms", &R::phone_scan_ms, 0.0, kAny, "default phone scan, median ms")
          .number("osmesa_6_views_ms", &R::osmesa_6_views_ms, 0.0, kAny, "OSMesa depth of six views, median ms")
          .number("rgb_6_views_ms", &R::rgb_6_views_ms, 0.0, kAny, "colour + depth + labels of six views, median ms")
          .number("rgb_frames_per_s_640x480", &R::rgb_frames_per_s_640x480, 0.0, kAny, "RGB frames per second")
          .number("gl_first_use_ms", &R::gl_first_use_ms, 0.0, kAny, "module load, context, shaders, mesh upload, ms")
          .text("gl_renderer", &R::gl_renderer, "the OpenGL renderer's name")
          .integer("repeats", &R::repeats, 0, 1 << 20, "repeats per measurement");
  return f.write(r);
}

}  // namespace floorcast
