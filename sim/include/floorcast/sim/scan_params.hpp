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

/// Monocular metric depth from a depth foundation model (Depth Pro, UniDepth, Metric3D, Depth
/// Anything), error components as documented for such networks (sim/README.md, "mono"). Per view
/// k and pixel p, with z the ray-cast depth after the glass outcome:
///
///   z1 = compress(z * t_k(face))          texture-less wall faces, compression at range
///   z2 = bleed(flying(z1))                flying pixels and smearing across depth edges
///   depth = (s_scan * s_k * warp_k(p) * z2 + shift_k) * (1 + noise_sigma_rel * n_p)
///
/// and, in views drawn as having no usable ground plane, no depth on the floor. The member
/// initialisers are the "depth_pro" preset (mono_model_preset); every value is validated by
/// validate_scan_params.
struct MonoModel {
  /// Name of the preset these values started from (mono_model_preset). A label written next to
  /// results; the values below are what is simulated.
  std::string model = "depth_pro";
  /// Shared by every view of one scan (same camera, same building): ln(s_scan) ~
  /// N(scan_scale_mean_ln, scan_scale_sigma_ln^2), one draw per scan.
  double scan_scale_mean_ln = 0.0;
  double scan_scale_sigma_ln = 0.109;
  double scale_sigma_ln = 0.109;  ///< per view: ln(s_k) ~ N(0, scale_sigma_ln^2)
  double shift_sigma_m = 0.05;    ///< per view: additive shift_k ~ N(0, shift_sigma_m^2), metres
  /// Compression at range (bounded network outputs, training depths mostly indoors): beyond the
  /// knee, z -> knee + (ceiling - knee) * tanh((z - knee) / (ceiling - knee)) (slope 1 at the knee,
  /// never reaching the ceiling). compression_knee_m = 0: off (then the ceiling must be 0 too).
  double compression_knee_m = 0.0;
  double compression_ceiling_m = 0.0;
  /// Smooth low-frequency warp: a warp_grid_x x warp_grid_y grid of N(0, warp_sigma_ln^2) log
  /// values (zero mean per view), exponentiated and upsampled over the image with Catmull-Rom
  /// splines (separable, C1), multiplied into the depth.
  double warp_sigma_ln = 0.05;
  int warp_grid_x = 3;
  int warp_grid_y = 3;
  double noise_sigma_rel = 0.01;     ///< per-pixel relative Gaussian noise (spatially white)
  double flying_pixel_prob = 0.5;    ///< probability that a depth-edge pixel becomes a flying pixel
  int flying_pixel_width_px = 1;     ///< how far from an edge (pixels) a pixel counts as on it
  double edge_threshold_rel = 0.05;  ///< relative depth jump between 4-neighbours that makes a depth edge
  /// Edge bleeding: every pixel within edge_bleed_px (Chebyshev distance) of a depth edge takes
  /// the mean inverse depth of the valid pixels in its (2 edge_bleed_px + 1)^2 window, a ramp
  /// across the discontinuity (networks predict inverse depth and blur it across edges). 0 = off.
  int edge_bleed_px = 1;
  /// Texture-less walls: each wall or closed-door face (one plane) is, independently per view,
  /// misjudged with probability textureless_prob; its depth is then multiplied by
  /// exp(N(0, textureless_sigma_ln^2)).
  double textureless_prob = 0.1;
  double textureless_sigma_ln = 0.1;
  /// Views without a usable ground plane (floor occluded, out of view or not trusted): with this
  /// probability per view, the view has no depth on floor pixels.
  double no_ground_prob = 0.1;
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

/// Monocular error levels of published metric depth networks (sim/README.md lists the numbers
/// and their sources): "depth_pro" (the MonoModel defaults), "unidepth_v2", "metric3d_v2",
/// "depth_anything_v2", and "per_view_lognormal" (floorcast's former model: per-view scale only,
/// sigma 0.12, no shared bias, shift, compression, bleeding or failures).
/// Throws InputError for an unknown name.
MonoModel mono_model_preset(const std::string& name);
const std::vector<std::string>& mono_model_names();

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
