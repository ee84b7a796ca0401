#include "floorcast/scenarios/dataset_export.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <sstream>

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
constexpr int kDepthColumns = 40;

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

}  // namespace

DatasetExportReport export_scenario_dataset(const Scenario& scenario, const std::string& out_dir,
                                            const DatasetExportOptions& options,
                                            const std::function<void(std::size_t, std::size_t)>& progress) {
  DatasetExportReport report;
  for (const std::string& id : options.cells) {
    if (std::none_of(scenario.cells.begin(), scenario.cells.end(), [&id](const CellSpec& c) { return c.id == id; })) {
      throw InputError("scenario \"" + scenario.name + "\": no cell \"" + id + "\"");
    }
  }
  std::vector<const CellSpec*> cells;
  for (const CellSpec& c : scenario.cells) {
    if (!options.cells.empty() && std::find(options.cells.begin(), options.cells.end(), c.id) == options.cells.end()) continue;
    if (c.observation.source != ObservationSource::kScan) {
      report.notes.push_back("cell " + c.id + ": perfect observations (no scans), skipped");
      continue;
    }
    cells.push_back(&c);
  }
  if (cells.empty()) {
    throw InputError("scenario \"" + scenario.name + "\": no cell simulates scans (observation.source: scan); nothing to export");
  }
  const ScenarioRunner runner(scenario);
  create_directories_or_throw(out_dir);
  const std::size_t total = cells.size() * scenario.buildings.size() * static_cast<std::size_t>(scenario.sampling.count);
  std::size_t done = 0;

  for (const CellSpec* cell : cells) {
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
      std::string poses_txt, depth40_txt;
      std::vector<StampedPose> scan_poses;
      std::size_t image_index = 0;
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
        // Labels come from the same OpenGL render as the colour (true camera poses).
        const Eigen::Isometry3d T_world_scan = scan_frame_in_world(sim.truth.T_world_scan, sim.truth.camera_height_m);
        std::vector<cv::Mat> labels;
        if (gl) {
          const double near_m = std::max(1e-3, 0.5 * sim.params.sensor.min_range_m);
          for (std::size_t k = 0; k < sim.scan.views.size(); ++k) {
            GlFrame f = gl->render(T_world_scan * sim.truth.T_scan_camera_true[k], sim.scan.views[k].intrinsics, near_m, 1000.0);
            sim.scan.views[k].rgb = f.bgr;
            labels.push_back(f.label);
          }
        }
        const std::string scan_name = "p" + padded(static_cast<std::size_t>(point), 4);
        const fs::path sdir = root / "scans" / scan_name;
        save_simulated_scan(sdir.string(), sim);
        OJson intr = OJson::array();
        std::string rgb_txt = "# timestamp filename (view index as timestamp)\n";
        std::string depth_txt = "# timestamp filename (16-bit, 1000 units per metre, 0 = no return)\n";
        std::string gt = "# timestamp tx ty tz qx qy qz qw (each view's true camera pose in the world, OpenCV camera)\n";
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
          const Eigen::Isometry3d T = T_world_scan * sim.truth.T_scan_camera_true[k];
          const Eigen::Quaterniond q(T.rotation());
          char line[256];
          std::snprintf(line, sizeof line, "%zu %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", k, T.translation().x(), T.translation().y(),
                        T.translation().z(), q.x(), q.y(), q.z(), q.w());
          gt += line;

          // F3Loc: one image per view, its camera position and heading in the map frame, and
          // 40 z-depths at camera height across the image (from the plan).
          const Eigen::Vector3d axis = T.rotation().col(2);
          const double yaw_view = std::atan2(axis.y(), axis.x());
          const double x = T.translation().x(), y = T.translation().y();
          poses_txt += num(x - cx_world) + " " + num(cy_world - y) + " " + num(-yaw_view) + "\n";
          for (int c = 0; c < kDepthColumns; ++c) {
            const double u = (c + 0.5) * K.width_px / kDepthColumns - 0.5;
            const double a = std::atan((u - K.cx_px) / K.fx_px);  // right of the axis = clockwise
            const double r = rays.ray_ranges({x, y}, yaw_view - a, 1).front();
            depth40_txt += (c ? " " : "") + format_general(r * std::cos(a), 6);
          }
          depth40_txt += "\n";
          if (!v.rgb.empty()) write_png((root / "rgb" / (padded(image_index, 5) + ".png")).string(), v.rgb);
          ++image_index;
          ++report.images;
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
        write_text_file_atomic((sdir / "truth.json").string(), truth.dump(2) + "\n");
        scan_poses.push_back({static_cast<double>(point), sim.truth.T_world_scan});
        ++report.scans;
        ++done;
        if (progress) progress(done, total);
      }
      write_text_file_atomic((root / "poses.txt").string(), poses_txt);
      write_text_file_atomic((root / "depth40.txt").string(), depth40_txt);
      save_tum((root / "scans.tum").string(), scan_poses, "true scan poses; timestamp = point index");
    }
  }

  std::ostringstream readme;
  readme << "# " << scenario.name << ": exported dataset\n\n"
         << "Written by `floorcast export` from scenario hash `" << scenario.hash << "`: " << report.scans << " scans, "
         << report.images << " images. Layout (per cell and building):\n\n"
         << "| file | content |\n|---|---|\n"
         << "| `map.png`, `map.yaml` | F3Loc-style occupancy map: 255 free, 0 blocked (every door closed), metres per pixel and the world <-> map transform in map.yaml |\n"
         << "| `poses.txt` | F3Loc: one line per image `x y theta`, metres from the map centre, y down, theta = -yaw (radians) |\n"
         << "| `depth40.txt` | F3Loc: per image 40 z-depths (m) at camera height along 40 equally spaced image columns, from the plan |\n"
         << "| `rgb/NNNNN.png` | every view of every scan in poses.txt order (images are pitched like the sensor: F3Loc's gravity alignment applies) |\n"
         << "| `scans.tum` | true scan poses (TUM, evo reads it; timestamp = point index) |\n"
         << "| `scans/pNNNN/` | a floorcast scan folder (`floorcast observe` reads it): scan.json, view_NNN_depth.png (16-bit mm), view_NNN_rgb.png, view_NNN_glass.png, view_NNN_confidence.png, view_NNN_label.png (0 wall, 1 closed door, 2 glass, 3 clutter, 4 floor, 5 ceiling, 255 none), simulation.json; intrinsics.json (K, depth_scale 1000), rgb.txt / depth.txt (TUM RGB-D lists), groundtruth.txt (TUM: each view's true camera pose, OpenCV camera axes), truth.json |\n\n"
         << "Frames: world = plan metres, x right, y up, z up; camera = OpenCV (x right, y down, z forward); depth = z-depth.\n";
  for (const std::string& n : report.notes) readme << "\nNote: " << n << "\n";
  write_text_file_atomic((fs::path(out_dir) / "README.md").string(), readme.str());
  return report;
}

}  // namespace floorcast
