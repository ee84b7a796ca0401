// Test helper: analytic depth rendering of scenes made of rectangles (walls, floor, ceiling,
// glass panes), independent of the simulator, so the observation module can be tested against
// exact geometry. Conventions as sim/scan.hpp: scan frame z up with the camera centre at the
// origin, camera frame OpenCV (x right, y down, z forward), z-depth, pixel (u, v) at
// ((u - cx) / fx, (v - cy) / fy, 1).
#pragma once

#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "floorcast/core/scan.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/random.hpp"

namespace floorcast::test {


/// A rectangle: corner + two orthogonal edge vectors.
struct Rect {
  Eigen::Vector3d corner;
  Eigen::Vector3d e1;
  Eigen::Vector3d e2;
  bool glass = false;
};

struct Scene {
  std::vector<Rect> rects;

  /// A vertical wall above the 2D segment a->b from z0 to z1.
  void add_wall(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double z0, double z1, bool glass = false) {
    rects.push_back({Eigen::Vector3d(a.x(), a.y(), z0), Eigen::Vector3d(b.x() - a.x(), b.y() - a.y(), 0.0),
                     Eigen::Vector3d(0.0, 0.0, z1 - z0), glass});
  }
  /// A horizontal rectangle [x0,x1] x [y0,y1] at height z.
  void add_horizontal(double x0, double x1, double y0, double y1, double z) {
    rects.push_back({Eigen::Vector3d(x0, y0, z), Eigen::Vector3d(x1 - x0, 0, 0), Eigen::Vector3d(0, y1 - y0, 0), false});
  }
  /// A closed polygon room (counter-clockwise corners), floor at -camera_height, ceiling above.
  void add_room(const std::vector<Eigen::Vector2d>& corners, double camera_height, double room_height) {
    double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
    for (std::size_t i = 0; i < corners.size(); ++i) {
      add_wall(corners[i], corners[(i + 1) % corners.size()], -camera_height, room_height - camera_height);
      x0 = std::min(x0, corners[i].x());
      x1 = std::max(x1, corners[i].x());
      y0 = std::min(y0, corners[i].y());
      y1 = std::max(y1, corners[i].y());
    }
    add_horizontal(x0 - 0.01, x1 + 0.01, y0 - 0.01, y1 + 0.01, -camera_height);
    add_horizontal(x0 - 0.01, x1 + 0.01, y0 - 0.01, y1 + 0.01, room_height - camera_height);
  }

  /// Nearest opaque hit along o + t d (t > 0); whether glass was crossed before it.
  double cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d, bool& through_glass) const {
    double best = std::numeric_limits<double>::infinity();
    for (const Rect& r : rects) {
      if (r.glass) continue;
      const double t = hit(r, o, d);
      if (t < best) best = t;
    }
    through_glass = false;
    for (const Rect& r : rects) {
      if (!r.glass) continue;
      const double t = hit(r, o, d);
      if (t < best) through_glass = true;
    }
    return best;
  }

  static double hit(const Rect& r, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
    const Eigen::Vector3d n = r.e1.cross(r.e2);
    const double den = n.dot(d);
    if (std::abs(den) < 1e-12) return std::numeric_limits<double>::infinity();
    const double t = n.dot(r.corner - o) / den;
    if (t <= 1e-9) return std::numeric_limits<double>::infinity();
    const Eigen::Vector3d q = o + t * d - r.corner;
    const double a = q.dot(r.e1) / r.e1.squaredNorm();
    const double b = q.dot(r.e2) / r.e2.squaredNorm();
    if (a < 0.0 || a > 1.0 || b < 0.0 || b > 1.0) return std::numeric_limits<double>::infinity();
    return t;
  }
};

/// Camera pose in the scan frame: heading yaw (CCW from +x), pitch (negative = looking down),
/// centre at `centre`.
inline Eigen::Isometry3d camera_pose(double yaw_deg, double pitch_deg,
                                     const Eigen::Vector3d& centre = Eigen::Vector3d::Zero()) {
  const double yaw = yaw_deg * kPi / 180.0, pitch = pitch_deg * kPi / 180.0;
  const Eigen::Vector3d f(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
  const Eigen::Vector3d right = f.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = f.cross(right);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = right;
  T.linear().col(1) = down;
  T.linear().col(2) = f;
  T.translation() = centre;
  return T;
}

inline CameraIntrinsics intrinsics(int w, int h, double hfov_deg) {
  CameraIntrinsics K;
  K.width_px = w;
  K.height_px = h;
  K.fx_px = K.fy_px = 0.5 * w / std::tan(0.5 * hfov_deg * kPi / 180.0);
  K.cx_px = 0.5 * (w - 1);
  K.cy_px = 0.5 * (h - 1);
  return K;
}

struct RenderOptions {
  double depth_scale = 1.0;       ///< multiplicative (monocular scale error)
  double noise_sigma_m = 0.0;     ///< Gaussian z-depth noise, sigma = noise_sigma_m * depth
  std::uint32_t seed = 1;
  double max_depth_m = 1e9;       ///< no return beyond
};

/// Standard normal value from a hash of (seed, row, col): per-pixel noise independent of the
/// evaluation order, so rows can render in parallel.
inline double pixel_gaussian(std::uint32_t seed, int r, int c) {
  const auto mix = [](std::uint64_t x) { return mix64(x); };
  const std::uint64_t h1 = mix((std::uint64_t(seed) << 40) ^ (std::uint64_t(r) << 20) ^ std::uint64_t(c));
  const std::uint64_t h2 = mix(h1);
  const double u1 = ((h1 >> 11) + 1) * (1.0 / 9007199254740993.0), u2 = (h2 >> 11) * (1.0 / 9007199254740992.0);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

inline DepthView render_view(const Scene& scene, const CameraIntrinsics& K, const Eigen::Isometry3d& T_scan_camera,
                             const RenderOptions& opt = {}) {
  DepthView v;
  v.intrinsics = K;
  v.T_scan_camera = T_scan_camera;
  v.depth_m = cv::Mat(K.height_px, K.width_px, CV_32F, cv::Scalar(0));
  v.glass_mask = cv::Mat(K.height_px, K.width_px, CV_8U, cv::Scalar(0));
  const Eigen::Matrix3d R = T_scan_camera.linear();
  const Eigen::Vector3d o = T_scan_camera.translation();
  tbb::parallel_for(0, K.height_px, [&](int r) {
    for (int c = 0; c < K.width_px; ++c) {
      const Eigen::Vector3d dc((c - K.cx_px) / K.fx_px, (r - K.cy_px) / K.fy_px, 1.0);
      bool glass = false;
      const double t = scene.cast(o, R * dc, glass);  // t = z-depth since dc.z = 1
      if (!std::isfinite(t) || t > opt.max_depth_m) continue;
      double depth = t * opt.depth_scale;
      if (opt.noise_sigma_m > 0.0) depth += opt.noise_sigma_m * t * pixel_gaussian(opt.seed, r, c);
      v.depth_m.at<float>(r, c) = static_cast<float>(depth);
      if (glass) v.glass_mask.at<std::uint8_t>(r, c) = 255;
    }
  });
  return v;
}

/// A PALMS+-style rotating scan: n views at equal yaw steps from yaw0, given HFOV and pitch.
inline Scan render_scan(const Scene& scene, int n_views = 6, double hfov_deg = 108.0, double pitch_deg = -15.0,
                        int w = 640, int h = 480, const std::vector<double>& scales = {},
                        double noise_sigma_m = 0.0, double yaw0_deg = 0.0) {
  Scan s;
  s.sensor = "synthetic";
  const CameraIntrinsics K = intrinsics(w, h, hfov_deg);
  for (int i = 0; i < n_views; ++i) {
    RenderOptions opt;
    opt.depth_scale = i < static_cast<int>(scales.size()) ? scales[i] : 1.0;
    opt.noise_sigma_m = noise_sigma_m;
    opt.seed = 100u + static_cast<std::uint32_t>(i);
    const Eigen::Isometry3d T = camera_pose(yaw0_deg + 360.0 * i / n_views, pitch_deg);
    s.views.push_back(render_view(scene, K, T, opt));
  }
  return s;
}

/// A box room around the observer: [x0, x1] x [y0, y1], camera 1.5 m above the floor, 2.8 m high.
inline Scene box_room(double x0, double x1, double y0, double y1, double camera_height = 1.5,
                      double room_height = 2.8) {
  Scene sc;
  sc.add_room({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, camera_height, room_height);
  return sc;
}

/// Segments of a rotated box room (observer frame), for rotated-room tests.
inline std::vector<Eigen::Vector2d> rotated_box(double x0, double x1, double y0, double y1, double yaw_deg) {
  const double a = yaw_deg * kPi / 180.0;
  const Eigen::Rotation2Dd R(a);
  return {R * Eigen::Vector2d(x0, y0), R * Eigen::Vector2d(x1, y0), R * Eigen::Vector2d(x1, y1),
          R * Eigen::Vector2d(x0, y1)};
}

}  // namespace floorcast::test
