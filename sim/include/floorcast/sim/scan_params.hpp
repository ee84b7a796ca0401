// Parameters of a simulated rotating scan: view geometry, sensor model, setting, seed. Plain
// structs whose member initialisers are the single source of defaults; presets fill them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace floorcast {

/// Where the views look. View k (k = 0..num_views-1) has yaw k * view_step_deg in the scan frame
/// (counter-clockwise, view 0 looks along the scan's +x = the observer's heading) and the same
/// pitch (negative looks down). The camera centre is at the scan origin, or, with
/// rotation_radius_m > 0, that far ahead of the origin along the view's yaw (a phone swung
/// around the user's body).
struct ScanGeometry {
  int num_views = 6;
  double view_step_deg = 60.0;
  double hfov_deg = 108.0;   ///< horizontal field of view of every view
  int width_px = 640;
  int height_px = 480;
  double pitch_deg = -15.0;
  double camera_height_m = 1.5;  ///< camera centre above the floor
  double rotation_radius_m = 0.0;
};

/// What a ray that hits glass reports. Probabilities of the three outcomes (return = the rest).
struct GlassModel {
  double p_see_through = 0.0;  ///< the ray continues to what is behind the pane
  double p_reflect = 0.0;      ///< mirror reflection: phantom depth of the total path length
  /// false: one decision per glass pane and view (a pane looks the same across a view);
  /// true: an independent decision per pixel.
  bool per_pixel = false;
  /// At most this many panes are seen through along one ray; the next one returns.
  int max_interactions = 4;
};

/// Axial noise sigma(z) = sigma_base_m + sigma_quad_per_m * (z - sigma_z0_m)^2 (Nguyen, Izadi,
/// Lovell 2012, Kinect-style), lateral jitter, dropouts, ARKit-style confidence.
struct LidarModel {
  double sigma_base_m = 0.0012;
  double sigma_quad_per_m = 0.0019;
  double sigma_z0_m = 0.4;
  double lateral_sigma_px = 0.5;   ///< ray direction jitter, pixels (Gaussian per axis)
  double dropout_prob = 0.01;      ///< random missing returns
  /// Grazing incidence: above this angle the dropout probability rises linearly to
  /// grazing_dropout_prob at 90 deg.
  double grazing_start_deg = 70.0;
  double grazing_dropout_prob = 0.6;
  /// Confidence (2 high, 1 medium, 0 low): medium above medium_incidence_deg, beyond
  /// medium_range_fraction of the range, or next to a depth edge; low on glass, above
  /// low_incidence_deg, or beyond low_range_fraction of the range.
  double medium_incidence_deg = 60.0;
  double low_incidence_deg = 78.0;
  double medium_range_fraction = 0.7;
  double low_range_fraction = 0.95;
  double edge_threshold_rel = 0.05;  ///< depth jump (relative) that makes a depth edge
};

/// Monocular metric depth (foundation model): depth = lambda_view * exp(warp(u, v)) *
/// true_depth * (1 + noise_sigma_rel * n), then flying pixels at depth edges.
struct MonoModel {
  double scale_sigma_ln = 0.12;  ///< ln(lambda_view) ~ N(0, scale_sigma_ln^2), per view
  /// Smooth low-frequency warp: a warp_grid_x x warp_grid_y grid of N(0, warp_sigma_ln^2) log
  /// values (zero mean per view), exponentiated and upsampled over the image with Catmull-Rom
  /// splines (separable, C1), multiplied into the depth.
  double warp_sigma_ln = 0.05;
  int warp_grid_x = 3;
  int warp_grid_y = 3;
  double noise_sigma_rel = 0.01;     ///< per-pixel relative Gaussian noise
  double flying_pixel_prob = 0.5;    ///< probability that a depth-edge pixel becomes a flying pixel
  int flying_pixel_width_px = 1;     ///< how far from an edge (pixels) a pixel counts as on it
  double edge_threshold_rel = 0.05;  ///< relative depth jump that makes a depth edge
};

/// Pose-tracker noise on the reported view poses (the rendering uses the true poses).
struct TrackerModel {
  double rotation_sigma_deg = 0.0;   ///< per axis, per view
  double translation_sigma_m = 0.0;  ///< per axis, per view
};

enum class SensorKind { kPerfect, kLidar, kMono };

struct SensorParams {
  SensorKind kind = SensorKind::kPerfect;
  double min_range_m = 0.05;  ///< closer surfaces give no return
  double max_range_m = 65.0;  ///< Euclidean range limit; farther surfaces give no return
  GlassModel glass;
  LidarModel lidar;   ///< used when kind == kLidar
  MonoModel mono;     ///< used when kind == kMono
  TrackerModel tracker;
};

/// PALMS+ settings: all views; 3 consecutive views centred on center_view; center_view only.
enum class ScanSetting { kFull, kPartial, kSingle };

struct ScanParams {
  std::string preset = "perfect";
  ScanGeometry geometry;
  SensorParams sensor;
  ScanSetting setting = ScanSetting::kFull;
  int center_view = 0;  ///< view the partial and single settings are centred on
  std::uint64_t seed = 0;
};

/// Presets (sim/README.md):
/// - "mono": PALMS+ Structured3D setting, 6 views at 60 deg, 108 deg HFOV, 640x480, pitch -15
///   deg, monocular-depth model, 40 m range.
/// - "phone": PALMS+ campus setting, 18 portrait views 20 deg apart, 60 deg HFOV, 480x640,
///   pitch -10 deg, monocular-depth model, tracker noise.
/// - "lidar": PALMS iPhone LiDAR, 18 views 20 deg apart, 60 deg HFOV, 256x192, pitch -10 deg,
///   5 m range, LiDAR model, tracker noise.
/// - "perfect": the mono geometry with exact depth (glass returns), 65 m range.
/// Throws InputError for an unknown name.
ScanParams scan_preset(const std::string& name);
const std::vector<std::string>& scan_preset_names();

const char* sensor_kind_name(SensorKind kind);
const char* scan_setting_name(ScanSetting setting);
/// Parse "perfect|lidar|mono" / "full|partial|single"; false if unknown.
bool parse_sensor_kind(const std::string& s, SensorKind& kind);
bool parse_scan_setting(const std::string& s, ScanSetting& setting);

/// Indices of the views a setting keeps (in rotation order), e.g. partial with 6 views and
/// center 0 -> {5, 0, 1}.
std::vector<int> setting_views(const ScanGeometry& geometry, ScanSetting setting, int center_view);

/// Checks ranges of every parameter; throws InputError naming the parameter and the reason.
void validate_scan_params(const ScanParams& params);

}  // namespace floorcast
