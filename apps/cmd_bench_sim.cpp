// `floorcast bench sim`: throughput of the scan renderer against raw Embree streams on the same
// scene and rays, measured in one run, plus the time of one default mono scan.
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/sim/gl_renderer.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/ray_scene.hpp"
#include "floorcast/sim/scan_sim.hpp"

namespace floorcast::cli {
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

void register_bench_sim(CLI::App& root) {
  CLI::App& bench = group(root, "bench", "Benchmarks (medians over repeats, same-run ratios)");
  struct Options {
    std::string plan;
    int repeats = 9;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = bench.add_subcommand("sim", "Scan renderer vs raw Embree stream throughput; default mono scan time");
  cmd->add_option("--plan", o->plan, "Floor plan (default: floorplans/buildings/campus.json)");
  cmd->add_option("--repeats", o->repeats, "Repeats per measurement (median reported)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->callback([o] {
    std::string plan_path = o->plan;
    if (plan_path.empty()) plan_path = source_dir() + "/floorplans/buildings/campus.json";
    const FloorPlan plan = load_floor_plan(plan_path);
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
    for (int r = 0; r < o->repeats; ++r) {
      render_ms.push_back(time_ms([&] { (void)simulate_scan(scene, pose, render_params); }));
      raw_ms.push_back(time_ms([&] { hits = scene.intersect_prepared(prepared); }));
    }
    ScanParams mono = scan_preset("mono");
    ScanParams lidar = scan_preset("lidar");
    ScanParams phone = scan_preset("phone");
    for (int r = 0; r < o->repeats; ++r) {
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
      for (int r = 0; r < o->repeats; ++r) {
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
    nlohmann::ordered_json j;
    j["scan_ms"] = median(mono_ms);
    j["renderer_mrays_per_s"] = renderer;
    j["embree_raw_mrays_per_s"] = raw;
    j["ratio"] = renderer / raw;
    j["plan"] = std::filesystem::path(plan_path).filename().string();
    j["triangles"] = scene.mesh().num_triangles();
    j["threads"] = tbb::info::default_concurrency();
    j["rays_per_scan"] = rays.size();
    j["hit_fraction"] = static_cast<double>(hits) / n_rays;
    j["scene_build_ms"] = scene_ms;
    j["scan_cpu_ms"] = median(mono_cpu_ms);
    j["load_average_1min"] = load_before[0];
    j["lidar_scan_ms"] = median(lidar_ms);
    j["phone_scan_ms"] = median(phone_ms);
    j["osmesa_6_views_ms"] = median(gl_ms);
    j["rgb_6_views_ms"] = median(rgb_ms);
    j["rgb_frames_per_s_640x480"] = rgb_fps;
    j["gl_first_use_ms"] = gl_setup_ms;
    j["gl_renderer"] = gl_name;
    j["repeats"] = o->repeats;
    if (o->json) {
      std::cout << j.dump(2) << "\n";
      return;
    }
    std::cout << std::fixed << std::setprecision(2) << "plan:                  " << plan_path << " ("
              << scene.mesh().num_triangles() << " triangles, scene built in " << scene_ms << " ms)\n"
              << "pose:                  " << pose.x_m << ", " << pose.y_m << " (most open interior point)\n"
              << "threads:               " << tbb::info::default_concurrency() << "\n"
              << "rays per mono scan:    " << rays.size() << " (6 x 640x480), " << 100.0 * hits / n_rays << "% hit\n"
              << "renderer:              " << renderer << " Mrays/s (median of " << o->repeats << ")\n"
              << "raw Embree stream:     " << raw << " Mrays/s (rtcIntersect1M, 256-ray chunks)\n"
              << "ratio:                 " << renderer / raw << " (target >= 0.60)\n"
              << "mono scan (default):   " << median(mono_ms) << " ms (target < 100); CPU time "
              << median(mono_cpu_ms) << " ms (all threads)\n"
              << "load average (1 min):  " << load_before[0] << " (other processes compete for the cores)\n"
              << "lidar scan (default):  " << median(lidar_ms) << " ms\n"
              << "phone scan (default):  " << median(phone_ms) << " ms\n"
              << "OSMesa depth, 6 views: " << median(gl_ms) << " ms (llvmpipe rasteriser, reference)\n"
              << "RGB views, 640x480:    " << rgb_fps << " frames/s (colour + depth + labels; 6 views in "
              << median(rgb_ms) << " ms)\n"
              << "OpenGL first use:      " << gl_setup_ms << " ms (module load, context, shaders, mesh upload; "
              << gl_name << ")\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_bench_sim);
}  // namespace floorcast::cli
