#include "floorcast/scenarios/dataset_export.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <sstream>

#include "floorcast/core/depth_io.hpp"
#include "floorcast/core/file_io.hpp"
#include "floorcast/core/format.hpp"
#include "floorcast/core/hash.hpp"
#include "floorcast/core/image_io.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/pose_json.hpp"
#include "floorcast/core/scan_io.hpp"
#include "floorcast/core/trajectory_io.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/floorplans/render.hpp"
#include "floorcast/scenarios/runner.hpp"
#include "floorcast/sim/gl_renderer.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/sim/scan_io.hpp"
#include "floorcast/sim/scan_sim.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;
using OJson = nlohmann::ordered_json;

constexpr int kMaxMapSidePx = 16384;
/// F3Loc's loaders: GridSeqDataset takes L source frames and one reference frame per sample
/// (eval_observation.py: L = 3), named rgb/NNNNN-l.png (l = 0..L, the reference last), with L + 1
/// lines per sample in poses.txt and the depth files.
constexpr int kF3LocSources = 3;
/// F3Loc hard-codes focal length / image width (get_ray_from_depth, its networks): F_W = 3/8,
/// i.e. a horizontal field of view of 2 atan(4/3) = 106.26 degrees.
constexpr double kF3LocFocalPerWidth = 3.0 / 8.0;

std::string padded(std::size_t v, int width) {
  std::ostringstream s;
  s << std::setw(width) << std::setfill('0') << v;
  return s.str();
}

std::string num(double v) { return format_general(v, 10); }

/// The F3Loc map of a plan: 255 free, 0 blocked (walls, closed doors, glass; every door closed),
/// and its grid (row 0 = the top of the picture).
struct MapImage {
  cv::Mat image;
  GridSpec grid;
};

MapImage f3loc_map(const FloorPlan& plan, double resolution_m, std::vector<std::string>& notes, const std::string& where) {
  const Eigen::Vector4d e = drawing_extent_m(plan);
  const double margin = 1.0;
  double res = resolution_m;
  const double w_m = e[2] - e[0] + 2 * margin, h_m = e[3] - e[1] + 2 * margin;
  if (std::max(w_m, h_m) / res > kMaxMapSidePx) {
    res = std::max(w_m, h_m) / kMaxMapSidePx;
    notes.push_back(where + ": map coarsened to " + format_general(res, 4) + " m/px (the plan is " + format_general(w_m, 4) +
                    " x " + format_general(h_m, 4) + " m; at most " + std::to_string(kMaxMapSidePx) + " px a side)");
  }
  MapImage m;
  m.grid.origin_x_m = e[0] - margin;
  m.grid.origin_y_m = e[1] - margin;
  m.grid.resolution_m_per_px = res;
  m.grid.width_px = static_cast<int>(std::ceil(w_m / res));
  m.grid.height_px = static_cast<int>(std::ceil(h_m / res));
  const cv::Mat occupancy = rasterize_occupancy(plan, m.grid, closed_door_map());
  cv::Mat free_space = 255 - occupancy;
  cv::flip(free_space, m.image, 0);  // grid rows grow with +y; images grow downwards
  return m;
}

/// Per view of one scan, what the F3Loc side needs.
struct ViewRecord {
  Eigen::Isometry3d T_world_camera;
  double yaw_rad = 0.0;  ///< heading of the optical axis projected on the floor
  CameraIntrinsics K;
  cv::Mat rgb;
  cv::Mat depth_m;     ///< the sensor's (noisy) z-depth
};

/// F3Loc's frame choice for one scan: the reference (l = L) is the view looking closest to the
/// scan's heading; the L sources are its neighbours in rotation order (k-1, k+1, k+2, ...),
/// repeated cyclically when the scan has fewer views.
std::vector<std::size_t> f3loc_frames(const std::vector<ViewRecord>& views, double scan_yaw_rad) {
  const std::size_t V = views.size();
  std::size_t ref = 0;
  for (std::size_t k = 1; k < V; ++k)
    if (angle_distance_rad(views[k].yaw_rad, scan_yaw_rad) < angle_distance_rad(views[ref].yaw_rad, scan_yaw_rad)) ref = k;
  std::vector<std::size_t> others;
  for (std::size_t d = 1; d < V; ++d) {
    // -1, +1, +2, -2, +3, ... around the reference
    const long off = (d % 2 == 1) ? -static_cast<long>((d + 1) / 2) : static_cast<long>(d / 2);
    others.push_back(static_cast<std::size_t>((static_cast<long>(ref) + off % static_cast<long>(V) + static_cast<long>(V)) % static_cast<long>(V)));
  }
  std::vector<std::size_t> frames;
  for (int l = 0; l < kF3LocSources; ++l) frames.push_back(others.empty() ? ref : others[static_cast<std::size_t>(l) % others.size()]);
  frames.push_back(ref);
  return frames;
}

/// The horizontal depth of an F3Loc depth line: for `columns` equally spaced image columns, the
/// distance along the view's floor-projected optical axis at camera height. From the plan
/// (structural, ground truth: F3Loc's depthNN.txt), or from the sensor's depth map at the pixel of
/// each column whose ray is horizontal (what the sensor measured there; 0 = no return).
std::string depth_line_plan(const PerfectObserver& rays, const ViewRecord& v, int columns) {
  std::string line;
  for (int c = 0; c < columns; ++c) {
    const double u = (c + 0.5) * v.K.width_px / columns - 0.5;
    const double a = std::atan((u - v.K.cx_px) / v.K.fx_px);  // right of the axis = clockwise
    const Vec2 p(v.T_world_camera.translation().x(), v.T_world_camera.translation().y());
    const double r = rays.ray_ranges(p, v.yaw_rad - a, 1).front();
    line += (c ? " " : "") + format_general(r * std::cos(a), 6);
  }
  return line + "\n";
}

std::string depth_line_sensor(const ViewRecord& v, int columns) {
  const Eigen::Matrix3d R = v.T_world_camera.rotation();
  const Eigen::Vector3d fwd(std::cos(v.yaw_rad), std::sin(v.yaw_rad), 0.0);
  std::string line;
  for (int c = 0; c < columns; ++c) {
    const double u = (c + 0.5) * v.K.width_px / columns - 0.5;
    // Row where the ray through column u is horizontal: R.row(2) . K^-1 [u, v, 1] = 0.
    const double r20 = R(2, 0), r21 = R(2, 1), r22 = R(2, 2);
    double row = v.K.cy_px;
    if (std::abs(r21) > 1e-9) row = v.K.cy_px - v.K.fy_px * (r22 + r20 * (u - v.K.cx_px) / v.K.fx_px) / r21;
    const int ri = static_cast<int>(std::lround(row)), ci = static_cast<int>(std::lround(u));
    double d = 0.0;
    if (ri >= 0 && ci >= 0 && ri < v.depth_m.rows && ci < v.depth_m.cols) {
      const double z = v.depth_m.at<float>(ri, ci);
      if (z > 0.0) {
        const Eigen::Vector3d p_cam((u - v.K.cx_px) / v.K.fx_px * z, (row - v.K.cy_px) / v.K.fy_px * z, z);
        d = (R * p_cam).dot(fwd);
      }
    }
    line += (c ? " " : "") + format_general(d, 6);
  }
  return line + "\n";
}

}  // namespace

DatasetExportReport export_scenario_dataset(const Scenario& scenario_in, const std::string& out_dir,
                                            const DatasetExportOptions& options,
                                            const std::function<void(std::size_t, std::size_t)>& progress) {
  DatasetExportReport report;
  Scenario scenario = scenario_in;
  if (!options.camera.empty() && options.camera != "scenario" && options.camera != "f3loc") {
    throw InputError("export: unknown camera preset \"" + options.camera + "\" (scenario or f3loc)");
  }
  for (const std::string& id : options.cells) {
    if (std::none_of(scenario.cells.begin(), scenario.cells.end(), [&id](const CellSpec& c) { return c.id == id; })) {
      throw InputError("scenario \"" + scenario.name + "\": no cell \"" + id + "\"");
    }
  }
  std::vector<const CellSpec*> cells;
  for (CellSpec& c : scenario.cells) {
    if (!options.cells.empty() && std::find(options.cells.begin(), options.cells.end(), c.id) == options.cells.end()) continue;
    if (c.observation.source != ObservationSource::kScan) {
      report.notes.push_back("cell " + c.id + ": perfect observations (no scans), skipped");
      continue;
    }
    ScanGeometry& g = c.observation.scan.geometry;
    if (options.camera == "f3loc") {
      // F3Loc's camera: F_W = 3/8 (106.26 deg across) and gravity-aligned (no pitch).
      g.hfov_deg = 2.0 * std::atan(0.5 / kF3LocFocalPerWidth) * 180.0 / kPi;
      g.pitch_deg = 0.0;
    } else {
      const double f_w = 0.5 / std::tan(0.5 * g.hfov_deg * kPi / 180.0);
      if (std::abs(f_w - kF3LocFocalPerWidth) > 0.002) {
        report.notes.push_back("cell " + c.id + ": the camera's focal length / width is " + format_general(f_w, 4) + " (" +
                               format_general(g.hfov_deg, 4) + " deg across), F3Loc's code assumes F_W = 3/8 (106.26 deg): "
                               "its get_ray_from_depth samples the depth lines at other angles than they were taken; "
                               "export with --camera f3loc to match it");
      }
      if (std::abs(g.pitch_deg) > 1e-9) {
        report.notes.push_back("cell " + c.id + ": the views are pitched " + format_general(g.pitch_deg, 3) +
                               " deg, F3Loc's datasets are gravity-aligned (roll = pitch = 0): use F3Loc's gravity "
                               "alignment, or --camera f3loc");
      }
    }
    cells.push_back(&c);
  }
  if (cells.empty()) {
    throw InputError("scenario \"" + scenario.name + "\": no cell simulates scans (observation.source: scan); nothing to export");
  }
  if (std::abs(options.map_resolution_m - 0.01) > 1e-12) {
    report.notes.push_back("map.png at " + format_general(options.map_resolution_m, 4) +
                           " m/px: F3Loc's evaluation scripts assume 0.01 m/px (poses.txt -> pixels as x / 0.01 + W / 2)");
  }
  const ScenarioRunner runner(scenario);
  create_directories_or_throw(out_dir);
  const std::size_t total = cells.size() * scenario.buildings.size() * static_cast<std::size_t>(scenario.sampling.count);
  std::size_t done = 0;

  for (const CellSpec* cell : cells) {
    // F3Loc reads a dataset folder's scenes from split.yaml (train / val / test lists of scene
    // folder names): every building is a test scene.
    {
      std::ostringstream split;
      split << "# F3Loc split (floorcast export): scene folders of this dataset; every building is a test scene\n"
            << "train: []\nval: []\ntest:\n";
      for (const BuildingSpec& b : scenario.buildings) split << "  - " << b.label << "\n";
      create_directories_or_throw((fs::path(out_dir) / cell->id).string());
      write_text_file_atomic((fs::path(out_dir) / cell->id / "split.yaml").string(), split.str());
    }
    for (std::size_t b = 0; b < scenario.buildings.size(); ++b) {
      const std::string label = scenario.buildings[b].label;
      const fs::path root = fs::path(out_dir) / cell->id / label;
      create_directories_or_throw((root / "rgb").string());
      create_directories_or_throw((root / "scans").string());
      const FloorPlan& plan = runner.building_plan(static_cast<int>(b));
      const std::string plan_hash_hex = hex64(plan_hash(plan));
      const MapImage map = f3loc_map(plan, options.map_resolution_m, report.notes, cell->id + "/" + label);
      write_png((root / "map.png").string(), map.image);
      const double W = map.grid.width_px, H = map.grid.height_px, res = map.grid.resolution_m_per_px;
      const double cx_world = map.grid.origin_x_m + 0.5 * W * res;
      const double cy_world = map.grid.origin_y_m + 0.5 * H * res;
      {
        std::ostringstream y;
        y << "# F3Loc-style occupancy map of " << label << " (floorcast export)\n"
          << "image: map.png\nfree: 255  # everything else blocks (walls, closed doors, glass; every door drawn closed)\n"
          << "resolution_m_per_px: " << num(res) << "\nwidth_px: " << map.grid.width_px << "\nheight_px: " << map.grid.height_px << "\n"
          << "# world (floorcast: x right, y up, yaw CCW) -> map frame (F3Loc: metres from the image centre, x right,\n"
          << "# y down, theta = -yaw): x_map = x - centre_x_m, y_map = centre_y_m - y, theta = -yaw;\n"
          << "# pixel: col = x_map / resolution + width / 2, row = y_map / resolution + height / 2\n"
          << "centre_x_m: " << num(cx_world) << "\ncentre_y_m: " << num(cy_world) << "\n"
          << "plan_hash: " << plan_hash_hex << "\n";
        write_text_file_atomic((root / "map.yaml").string(), y.str());
      }
      std::unique_ptr<GlRenderer> gl;
      const PerfectObserver rays(plan, [] {
        PerfectObservationParams p;
        p.max_range_m = 100.0;
        p.num_rays = 0;
        return p;
      }());
      std::string poses_txt, depth40_txt, depth160_txt, depth40_sensor_txt;
      std::vector<StampedPose> scan_poses;
      for (int point = 0; point < scenario.sampling.count; ++point) {
        WorkUnit unit;
        unit.cell = cell->index;
        unit.building = static_cast<int>(b);
        unit.point = point;
        SimulatedScan sim = runner.unit_scan(unit);
        sim.truth.plan_hash = plan_hash_hex;
        const ScanGeometry& geo = sim.params.geometry;
        if (options.rgb && !gl) {
          const Mesh* mesh = runner.building_mesh(static_cast<int>(b));
          if (!mesh) throw InputError("building " + label + ": no mesh (internal: scan cells build one)");
          gl = std::make_unique<GlRenderer>(*mesh, geo.width_px, geo.height_px);
        }
        // Colour, labels and the noise-free depth come from one OpenGL render at the true camera
        // poses.
        const Eigen::Isometry3d T_world_scan = scan_frame_in_world(sim.truth.T_world_scan, sim.truth.camera_height_m);
        std::vector<cv::Mat> labels, depth_gt;
        if (gl) {
          const double near_m = std::max(1e-3, 0.5 * sim.params.sensor.min_range_m);
          for (std::size_t k = 0; k < sim.scan.views.size(); ++k) {
            GlFrame f = gl->render(T_world_scan * sim.truth.T_scan_camera_true[k], sim.scan.views[k].intrinsics, near_m, 1000.0);
            sim.scan.views[k].rgb = f.bgr;
            labels.push_back(f.label);
            depth_gt.push_back(f.depth_m);
          }
        }
        const fs::path sdir = fs::path(out_dir) / unit_scan_folder(scenario, unit, 0);
        save_simulated_scan(sdir.string(), sim);
        OJson intr = OJson::array();
        std::string rgb_txt = "# timestamp filename (view index as timestamp)\n";
        std::string depth_txt = "# timestamp filename (16-bit, 1000 units per metre, 0 = no return; the sensor's)\n";
        std::string gt = "# timestamp tx ty tz qx qy qz qw (each view's true camera pose in the world, OpenCV camera)\n";
        std::vector<ViewRecord> views;
        for (std::size_t k = 0; k < sim.scan.views.size(); ++k) {
          const DepthView& v = sim.scan.views[k];
          const CameraIntrinsics& K = v.intrinsics;
          intr.push_back({{"view", k},
                          {"width_px", K.width_px},
                          {"height_px", K.height_px},
                          {"K", {{K.fx_px, 0.0, K.cx_px}, {0.0, K.fy_px, K.cy_px}, {0.0, 0.0, 1.0}}},
                          {"depth_scale", 1000.0}});
          const std::string ts = std::to_string(k);
          if (!v.rgb.empty()) rgb_txt += ts + " " + scan_view_file(k, "rgb") + "\n";
          depth_txt += ts + " " + scan_view_file(k, "depth") + "\n";
          if (k < labels.size()) write_png((sdir / scan_view_file(k, "label")).string(), labels[k]);
          if (k < depth_gt.size()) write_depth_file((sdir / scan_view_file(k, "depth_gt")).string(), depth_gt[k]);
          const Eigen::Isometry3d T = T_world_scan * sim.truth.T_scan_camera_true[k];
          const Eigen::Quaterniond q(T.rotation());
          char line[256];
          std::snprintf(line, sizeof line, "%zu %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", k, T.translation().x(), T.translation().y(),
                        T.translation().z(), q.x(), q.y(), q.z(), q.w());
          gt += line;
          const Eigen::Vector3d axis = T.rotation().col(2);
          views.push_back({T, std::atan2(axis.y(), axis.x()), K, v.rgb, v.depth_m});
          ++report.images;
        }
        // F3Loc: L sources and the reference per sample (the scan), their poses in the map frame
        // and their depth lines: from the plan at camera height (ground truth, doors closed:
        // depth40 / depth160) and from the sensor (depth40_sensor).
        const std::vector<std::size_t> frames = f3loc_frames(views, sim.truth.T_world_scan.yaw_rad);
        for (std::size_t l = 0; l < frames.size(); ++l) {
          const ViewRecord& v = views[frames[l]];
          const double x = v.T_world_camera.translation().x(), y = v.T_world_camera.translation().y();
          poses_txt += num(x - cx_world) + " " + num(cy_world - y) + " " + num(-v.yaw_rad) + "\n";
          depth40_txt += depth_line_plan(rays, v, 40);
          depth160_txt += depth_line_plan(rays, v, 160);
          depth40_sensor_txt += depth_line_sensor(v, 40);
          if (!v.rgb.empty()) {
            const std::string idx = padded(static_cast<std::size_t>(point), 5);
            const fs::path grid_name = root / "rgb" / (idx + "-" + std::to_string(l) + ".png");
            write_png(grid_name.string(), v.rgb);
            // The same frame under TrajDataset's sequential name (line number of poses.txt).
            const fs::path seq_name =
                root / "rgb" / (padded(static_cast<std::size_t>(point) * frames.size() + l, 5) + ".png");
            std::error_code ec;
            fs::remove(seq_name, ec);
            fs::create_hard_link(grid_name, seq_name, ec);
            if (ec) fs::copy_file(grid_name, seq_name, fs::copy_options::overwrite_existing);
          }
        }
        write_text_file_atomic((sdir / "intrinsics.json").string(), intr.dump(1) + "\n");
        if (gl) write_text_file_atomic((sdir / "rgb.txt").string(), rgb_txt);
        write_text_file_atomic((sdir / "depth.txt").string(), depth_txt);
        write_text_file_atomic((sdir / "groundtruth.txt").string(), gt);
        OJson truth;
        truth["x_m"] = sim.truth.T_world_scan.x_m;
        truth["y_m"] = sim.truth.T_world_scan.y_m;
        truth["yaw_deg"] = sim.truth.T_world_scan.yaw_rad * 180.0 / kPi;
        truth["camera_height_m"] = sim.truth.camera_height_m;
        truth["view_depth_scale"] = sim.truth.view_depth_scale;
        truth["plan"] = label;
        truth["plan_hash"] = plan_hash_hex;
        truth["cell"] = cell->id;
        truth["cell_axes"] = cell->axes;
        OJson f3 = OJson::array();
        for (std::size_t k : frames) f3.push_back(k);
        truth["f3loc_frames"] = f3;
        write_text_file_atomic((sdir / "truth.json").string(), truth.dump(2) + "\n");
        scan_poses.push_back({static_cast<double>(point), sim.truth.T_world_scan});
        ++report.scans;
        // Walks (sequential cells): the scans at the later scheduled steps, as floorcast scan
        // folders with their colour views (what observation.depth_dir's depth maps are made from).
        for (int step : runner.unit_observation_steps(unit)) {
          if (step == 0) continue;
          SimulatedScan at = runner.unit_scan(unit, step);
          at.truth.plan_hash = plan_hash_hex;
          if (gl) {
            const Eigen::Isometry3d T_ws = scan_frame_in_world(at.truth.T_world_scan, at.truth.camera_height_m);
            for (std::size_t k = 0; k < at.scan.views.size(); ++k) {
              at.scan.views[k].rgb = gl->render(T_ws * at.truth.T_scan_camera_true[k], at.scan.views[k].intrinsics,
                                                std::max(1e-3, 0.5 * at.params.sensor.min_range_m), 1000.0)
                                         .bgr;
            }
          }
          save_simulated_scan((fs::path(out_dir) / unit_scan_folder(scenario, unit, step)).string(), at);
          ++report.walk_scans;
        }
        ++done;
        if (progress) progress(done, total);
      }
      write_text_file_atomic((root / "poses.txt").string(), poses_txt);
      write_text_file_atomic((root / "depth40.txt").string(), depth40_txt);
      write_text_file_atomic((root / "depth160.txt").string(), depth160_txt);
      write_text_file_atomic((root / "depth40_sensor.txt").string(), depth40_sensor_txt);
      save_tum((root / "scans.tum").string(), scan_poses, "true scan poses in the world (plan) frame; timestamp = point index");
    }
  }

  std::ostringstream readme;
  readme << "# " << scenario.name << ": exported dataset\n\n"
         << "Written by `floorcast export` from scenario hash `" << scenario_in.hash << "`"
         << (options.camera == "f3loc" ? " with F3Loc's camera (F_W = 3/8, 106.26 deg across, no pitch)" : "") << ": "
         << report.scans << " scans, " << report.images << " views. Each cell folder is an F3Loc dataset folder "
         << "(`split.yaml` and one scene folder per building, read by F3Loc's `GridSeqDataset` and `TrajDataset` as "
         << "they are); floorcast's own scan folders sit beside the F3Loc files. Per cell and building:\n\n"
         << "| file | content |\n|---|---|\n"
         << "| `../split.yaml` | F3Loc: `train` / `val` / `test` lists of scene folders (every building under `test`) |\n"
         << "| `map.png`, `map.yaml` | F3Loc occupancy map: 255 free, 0 blocked (every door closed), metres per pixel (F3Loc assumes 0.01) and the world <-> map transform in map.yaml |\n"
         << "| `poses.txt` | F3Loc: 4 lines per scan (3 source frames, then the reference), `x y theta`: metres from the map centre, y down, theta = -yaw (radians) |\n"
         << "| `depth40.txt`, `depth160.txt` | F3Loc: ground-truth depth lines, one per line of poses.txt: 40 / 160 horizontal depths (m) at camera height along equally spaced image columns, from the plan (doors closed) |\n"
         << "| `depth40_sensor.txt` | the same 40 columns as the simulated sensor measured them (noise, scale error, clutter, glass; 0 = no return): F3Loc's `depth_suffix=\"depth40_sensor\"` |\n"
         << "| `rgb/NNNNN-l.png` | F3Loc GridSeqDataset: scan NNNNN, frame l = 0..2 the sources (the views beside the reference in rotation order), l = 3 the reference (the view along the scan's heading); scans with fewer than 4 views repeat views |\n"
         << "| `rgb/NNNNN.png` | the same frames under TrajDataset's names (NNNNN = line of poses.txt; hard links) |\n"
         << "| `scans.tum` | true scan poses in the world frame (TUM, evo reads it; timestamp = point index) |\n"
         << "| `scans/pNNNN/` | a floorcast scan folder (`floorcast observe` reads it): scan.json, view_NNN_depth.png (the sensor's z-depth, 16-bit mm), view_NNN_depth_gt.png (noise-free z-depth of the first surface, glass included, 16-bit mm; with colour only), view_NNN_rgb.png, view_NNN_glass.png, view_NNN_confidence.png, view_NNN_label.png (0 wall, 1 closed door, 2 glass, 3 clutter, 4 floor, 5 ceiling, 255 none), simulation.json; intrinsics.json (K, depth_scale 1000), rgb.txt / depth.txt (TUM RGB-D lists), groundtruth.txt (TUM: each view's true camera pose in the world, OpenCV camera axes), truth.json (pose, camera height, depth scales, the views used as F3Loc frames) |\n"
         << "| `scans/pNNNN/step_SSSS/` | walks (sequential cells): the scan at walk step SSSS, a floorcast scan folder with its colour views |\n\n"
         << "Bring your own depth: a depth network's maps for these scans in a folder laid out as this one (DEPTH/<cell>/<building>/scans/pNNNN[/step_SSSS]/, one map per view named after its colour image, e.g. view_000_rgb.npy) replace the simulated depth in `floorcast run` with the scenario key `observation: {depth_dir: DEPTH}` (export with `--camera scenario`).\n\n"
         << "Frames: world = plan metres, x right, y up, z up; camera = OpenCV (x right, y down, z forward); depth = z-depth.\n"
         << "F3Loc's distance volumes (`desdf/<scene>/desdf.npy`) are made from map.png by F3Loc's own `utils/generate_desdf.py`.\n";
  for (const std::string& n : report.notes) readme << "\nNote: " << n << "\n";
  write_text_file_atomic((fs::path(out_dir) / "README.md").string(), readme.str());
  return report;
}

}  // namespace floorcast
