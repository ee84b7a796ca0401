#include "floorcast/sim/scan_sim.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/core/random.hpp"
#include "floorcast/core/math.hpp"

namespace floorcast {
namespace {

constexpr double kDeg = kPi / 180.0;
constexpr int kTile = 16;  // tiles of kTile x kTile pixels: one Embree stream each

/// Everything stage 1 (ray casting) needs for one view.
struct ViewJob {
  int view_index = 0;
  Eigen::Matrix3f R_world_camera;
  Eigen::Vector3f origin_world_m;
  cv::Mat clean;    ///< CV_32F z-depth after glass effects, before sensor noise; 0 = none
  cv::Mat cos_inc;  ///< CV_32F |cos| of the incidence angle at the returned surface
  cv::Mat glass;    ///< CV_8U 255 where glass affected the value
  cv::Mat first;    ///< CV_32F first-surface depth (only with keep_true_depth)
  cv::Mat surface;  ///< CV_32S triangle that produced the depth, -1 = none (mono model only)
};

struct Tracer {
  const RayScene& scene;
  const SensorParams& sensor;
  std::uint64_t seed;

  struct Result {
    float depth = 0.0f;
    float cos_inc = 0.0f;
    bool glass = false;
    int triangle = -1;  ///< the surface that produced the depth
  };

  bool is_glass(int tri) const { return scene.mesh().labels[static_cast<std::size_t>(tri)] == MeshLabel::kGlass; }

  float cos_incidence(int tri, const Eigen::Vector3f& d, float d_len) const {
    return std::abs(scene.normals()[static_cast<std::size_t>(tri)].dot(d)) / d_len;
  }

  enum class Outcome { kReturn, kThrough, kReflect };

  /// What glass triangle `tri` does to the ray of `pixel` at its `interaction`-th pane.
  Outcome decide(int tri, int interaction, int view_index, std::uint64_t pixel) const {
    const GlassModel& g = sensor.glass;
    if (interaction >= g.max_interactions) return Outcome::kReturn;  // seen through enough panes
    const CounterRng view_rng(seed, kRngGlass, static_cast<std::uint64_t>(view_index));
    const int part = scene.mesh().part_ids[static_cast<std::size_t>(tri)];
    const CounterRng rng = g.per_pixel ? view_rng.child((std::uint64_t{1} << 40) + pixel)
                                       : view_rng.child(static_cast<std::uint64_t>(part + 1));
    const double u = rng.uniform(static_cast<std::uint64_t>(interaction));
    if (u < g.p_see_through) return Outcome::kThrough;
    if (u < g.p_see_through + g.p_reflect) return Outcome::kReflect;
    return Outcome::kReturn;
  }

  /// The ray that follows outcome `out` at the glass hit (t, tri) of camera ray o + t d.
  /// Through: the same ray, starting behind the pane (its slab thickness along the ray);
  /// reflect: the mirrored ray from the hit point, limited to the remaining range.
  Ray3 secondary_ray(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t, int tri, Outcome out,
                     float t_far, float eps) const {
    const Eigen::Vector3f& n = scene.normals()[static_cast<std::size_t>(tri)];
    const float nd = n.dot(d);
    if (out == Outcome::kThrough) {
      const float thickness = scene.part_thickness(scene.mesh().part_ids[static_cast<std::size_t>(tri)]);
      const float skip = std::abs(nd) > 1e-6f ? thickness / std::abs(nd) : 0.0f;
      return {o, d, t + std::min(skip, 0.5f * (t_far - t)) + eps, t_far};
    }
    const Eigen::Vector3f p = o + t * d + 1e-4f * (nd < 0.0f ? n : Eigen::Vector3f(-n));
    return {p, d - 2.0f * nd * n, 0.0f, t_far - t};
  }

  /// Finishes a ray whose first hit (t, tri) is glass, given the outcome there and the hit of the
  /// secondary ray (already cast). Further panes are handled here with single rays.
  Result glass_chain(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t, int tri, Outcome out, RayHit3 h,
                     int view_index, std::uint64_t pixel) const {
    Result r;
    r.glass = true;
    const float d_len = d.norm();
    const float t_far = static_cast<float>(sensor.max_range_m) / d_len;
    const float eps = 1e-4f / d_len;
    for (int interaction = 0;;) {
      if (out == Outcome::kReturn) {
        r.depth = t;
        r.cos_inc = cos_incidence(tri, d, d_len);
        r.triangle = tri;
        return finish(r, d_len);
      }
      if (out == Outcome::kReflect) {
        if (!h.hit()) return r;  // the mirrored path meets nothing within range
        const Eigen::Vector3f& n = scene.normals()[static_cast<std::size_t>(tri)];
        r.depth = t + h.t;
        r.cos_inc = cos_incidence(h.triangle, d - 2.0f * n.dot(d) * n, d_len);
        r.triangle = h.triangle;
        return finish(r, d_len);
      }
      // Through: skip faces we leave (a pane's back face), stop at the next surface we enter.
      for (int guard = 0; guard < 64 && h.hit(); ++guard) {
        const bool leaving = scene.normals()[static_cast<std::size_t>(h.triangle)].dot(d) > 0.0f;
        if (!(leaving && is_glass(h.triangle))) break;
        h = scene.intersect({o, d, h.t + eps, t_far});
      }
      if (!h.hit()) return r;  // nothing behind within range: no return
      if (!is_glass(h.triangle)) {
        r.depth = h.t;
        r.cos_inc = cos_incidence(h.triangle, d, d_len);
        r.triangle = h.triangle;
        return finish(r, d_len);
      }
      // Another pane: decide again.
      t = h.t;
      tri = h.triangle;
      out = decide(tri, ++interaction, view_index, pixel);
      if (out != Outcome::kReturn) h = scene.intersect(secondary_ray(o, d, t, tri, out, t_far, eps));
    }
  }

  /// Applies the minimum range (the maximum is enforced by every ray's t_far).
  Result finish(Result r, float d_len) const {
    const double range = static_cast<double>(r.depth) * d_len;
    if (range < sensor.min_range_m) {
      r.depth = 0.0f;
      r.cos_inc = 0.0f;
    }
    return r;
  }
};

/// Per-pixel camera-ray geometry shared by all views of a scan (same intrinsics).
struct PixelRays {
  std::vector<float> x, y;    ///< (u - cx) / fx per column, (v - cy) / fy per row
  std::vector<float> inv_norm;  ///< 1 / |(x, y, 1)| per pixel (empty when rays are jittered)
};

PixelRays pixel_rays(const CameraIntrinsics& K, bool jitter) {
  PixelRays p;
  p.x.resize(static_cast<std::size_t>(K.width_px));
  p.y.resize(static_cast<std::size_t>(K.height_px));
  for (int u = 0; u < K.width_px; ++u) p.x[static_cast<std::size_t>(u)] = static_cast<float>((u - K.cx_px) / K.fx_px);
  for (int v = 0; v < K.height_px; ++v) p.y[static_cast<std::size_t>(v)] = static_cast<float>((v - K.cy_px) / K.fy_px);
  if (!jitter) {
    p.inv_norm.resize(static_cast<std::size_t>(K.width_px) * static_cast<std::size_t>(K.height_px));
    for (int v = 0; v < K.height_px; ++v)
      for (int u = 0; u < K.width_px; ++u) {
        const float x = p.x[static_cast<std::size_t>(u)], y = p.y[static_cast<std::size_t>(v)];
        p.inv_norm[static_cast<std::size_t>(v) * static_cast<std::size_t>(K.width_px) + static_cast<std::size_t>(u)] =
            1.0f / std::sqrt(x * x + y * y + 1.0f);
      }
  }
  return p;
}

/// Fills the camera rays of one tile (row-major inside the tile); returns their count.
int tile_rays(const ViewJob& job, const CameraIntrinsics& K, const ScanParams& params, const PixelRays& pr,
              int tiles_x, int local, StreamRayHit* rays, int* px_u, int* px_v) {
  const int W = K.width_px, H = K.height_px;
  const int u0 = (local % tiles_x) * kTile, v0 = (local / tiles_x) * kTile;
  const int u1 = std::min(u0 + kTile, W), v1 = std::min(v0 + kTile, H);
  const bool jitter = pr.inv_norm.empty();
  const double jitter_sigma = params.sensor.lidar.lateral_sigma_px;
  const CounterRng jitter_rng(params.seed, kRngPixelJitter, static_cast<std::uint64_t>(job.view_index));
  const float inv_fx = static_cast<float>(1.0 / K.fx_px), inv_fy = static_cast<float>(1.0 / K.fy_px);
  const float max_range = static_cast<float>(params.sensor.max_range_m);
  const Eigen::Matrix3f& R = job.R_world_camera;
  int n = 0;
  for (int v = v0; v < v1; ++v) {
    for (int u = u0; u < u1; ++u) {
      float x = pr.x[static_cast<std::size_t>(u)], y = pr.y[static_cast<std::size_t>(v)];
      float inv_norm;
      if (jitter) {
        const CounterRng rng = jitter_rng.child(static_cast<std::uint64_t>(v) * W + u);
        x += static_cast<float>(jitter_sigma * rng.normal(0)) * inv_fx;
        y += static_cast<float>(jitter_sigma * rng.normal(1)) * inv_fy;
        inv_norm = 1.0f / std::sqrt(x * x + y * y + 1.0f);
      } else {
        inv_norm = pr.inv_norm[static_cast<std::size_t>(v) * static_cast<std::size_t>(W) + static_cast<std::size_t>(u)];
      }
      // World direction = R * (x, y, 1): unit z in the camera frame, so t is z-depth.
      const Eigen::Vector3f d = R.col(0) * x + R.col(1) * y + R.col(2);
      rays[n].set(job.origin_world_m, d, 0.0f, max_range * inv_norm);
      px_u[n] = u;
      px_v[n] = v;
      ++n;
    }
  }
  return n;
}

void trace_views(const RayScene& scene, const ScanParams& params, const CameraIntrinsics& K,
                 std::vector<ViewJob>& jobs, bool keep_first) {
  const int W = K.width_px;
  const int tiles_x = (W + kTile - 1) / kTile, tiles_y = (K.height_px + kTile - 1) / kTile;
  const int tiles_per_view = tiles_x * tiles_y;
  const int total = tiles_per_view * static_cast<int>(jobs.size());
  const Tracer tracer{scene, params.sensor, params.seed};
  const bool glass_effects = params.sensor.glass.p_see_through > 0.0 || params.sensor.glass.p_reflect > 0.0;
  const std::vector<MeshLabel>& labels = scene.mesh().labels;
  const bool need_incidence = params.sensor.kind == SensorKind::kLidar;
  const bool need_min_range = params.sensor.min_range_m > 0.0;
  const float min_range2 = static_cast<float>(params.sensor.min_range_m * params.sensor.min_range_m);
  const float max_range = static_cast<float>(params.sensor.max_range_m);
  const PixelRays pr =
      pixel_rays(K, params.sensor.kind == SensorKind::kLidar && params.sensor.lidar.lateral_sigma_px > 0.0);

  tbb::parallel_for(tbb::blocked_range<int>(0, total, 1), [&](const tbb::blocked_range<int>& range) {
    StreamRayHit rays[kTile * kTile], sec[kTile * kTile];
    Tracer::Result results[kTile * kTile];
    Tracer::Outcome sec_outcome[kTile * kTile];
    int px_u[kTile * kTile], px_v[kTile * kTile], sec_pixel[kTile * kTile];
    for (int tile = range.begin(); tile != range.end(); ++tile) {
      ViewJob& job = jobs[static_cast<std::size_t>(tile / tiles_per_view)];
      const int n = tile_rays(job, K, params, pr, tiles_x, tile % tiles_per_view, rays, px_u, px_v);
      scene.intersect_stream(rays, static_cast<std::size_t>(n), true);
      int n_sec = 0;
      for (int i = 0; i < n; ++i) {
        Tracer::Result& r = results[i];
        r = Tracer::Result{};
        const StreamRayHit& h = rays[i];
        if (!h.hit()) continue;
        const int tri = static_cast<int>(h.primID);
        const bool glass = labels[static_cast<std::size_t>(tri)] == MeshLabel::kGlass;
        if (glass && glass_effects) {
          const std::uint64_t pixel = static_cast<std::uint64_t>(px_v[i]) * W + px_u[i];
          const Tracer::Outcome out = tracer.decide(tri, 0, job.view_index, pixel);
          if (out != Tracer::Outcome::kReturn) {
            const Eigen::Vector3f d = h.direction();
            const float d_len = d.norm();
            const Ray3 ray = tracer.secondary_ray(h.origin(), d, h.tfar, tri, out, max_range / d_len, 1e-4f / d_len);
            sec[n_sec].set(ray.origin_m, ray.direction, ray.t_near, ray.t_far);
            sec_pixel[n_sec] = i;
            sec_outcome[n_sec] = out;
            ++n_sec;
            continue;
          }
        }
        // An opaque surface or a glass return.
        r.depth = h.tfar;
        r.glass = glass;
        r.triangle = tri;
        if (need_incidence) {
          const Eigen::Vector3f d = h.direction();
          const float d_len = d.norm();
          r.cos_inc = tracer.cos_incidence(tri, d, d_len);
          r = tracer.finish(r, d_len);
        } else if (need_min_range) {
          // range^2 = t^2 |d|^2 (no square root needed)
          const float d2 = h.dir_x * h.dir_x + h.dir_y * h.dir_y + h.dir_z * h.dir_z;
          if (h.tfar * h.tfar * d2 < min_range2) r.depth = 0.0f;
        }
      }
      if (n_sec > 0) {
        // Secondary rays of the tile's glass pixels as one (incoherent) stream.
        scene.intersect_stream(sec, static_cast<std::size_t>(n_sec), false);
        for (int k = 0; k < n_sec; ++k) {
          const int i = sec_pixel[k];
          const std::uint64_t pixel = static_cast<std::uint64_t>(px_v[i]) * W + px_u[i];
          RayHit3 sh;
          if (sec[k].hit()) {
            sh.t = sec[k].tfar;
            sh.triangle = static_cast<int>(sec[k].primID);
          }
          results[i] = tracer.glass_chain(rays[i].origin(), rays[i].direction(), rays[i].tfar,
                                          static_cast<int>(rays[i].primID), sec_outcome[k], sh, job.view_index, pixel);
        }
      }
      for (int i = 0; i < n; ++i) {
        const int u = px_u[i], v = px_v[i];
        const Tracer::Result& r = results[i];
        job.clean.ptr<float>(v)[u] = r.depth;
        if (need_incidence) job.cos_inc.ptr<float>(v)[u] = r.cos_inc;
        job.glass.ptr<unsigned char>(v)[u] = r.glass ? 255 : 0;
        if (!job.surface.empty()) job.surface.ptr<int>(v)[u] = r.depth > 0.0f ? r.triangle : -1;
        if (keep_first) {
          float f = rays[i].hit() ? rays[i].tfar : 0.0f;
          const double range_m = static_cast<double>(f) * rays[i].direction().norm();
          if (range_m < params.sensor.min_range_m) f = 0.0f;
          job.first.ptr<float>(v)[u] = f;
        }
      }
    }
  });
}

/// Largest relative depth jump to a valid neighbour within `width` pixels along the image axes;
/// outputs that neighbour's depth.
inline float max_edge_jump(const cv::Mat& depth, int u, int v, int width, float threshold, float& other) {
  const float z = depth.ptr<float>(v)[u];
  float best = 0.0f;
  other = z;
  for (int k = 1; k <= width; ++k) {
    const int cand[4][2] = {{u - k, v}, {u + k, v}, {u, v - k}, {u, v + k}};
    for (const auto& c : cand) {
      if (c[0] < 0 || c[1] < 0 || c[0] >= depth.cols || c[1] >= depth.rows) continue;
      const float q = depth.ptr<float>(c[1])[c[0]];
      if (q <= 0.0f) continue;
      const float diff = std::abs(q - z), lo = std::min(q, z);
      if (diff <= threshold * lo) continue;  // not an edge: skip the division
      const float rel = diff / lo;
      if (rel > best) {
        best = rel;
        other = q;
      }
    }
  }
  return best;
}

/// Whether any 4-neighbour is missing or differs by more than `threshold` (relative).
inline bool next_to_edge(const cv::Mat& depth, int u, int v, float threshold) {
  const float z = depth.at<float>(v, u);
  const int cand[4][2] = {{u - 1, v}, {u + 1, v}, {u, v - 1}, {u, v + 1}};
  for (const auto& c : cand) {
    if (c[0] < 0 || c[1] < 0 || c[0] >= depth.cols || c[1] >= depth.rows) continue;
    const float q = depth.at<float>(c[1], c[0]);
    if (q <= 0.0f) return true;
    if (std::abs(q - z) > threshold * std::min(q, z)) return true;
  }
  return false;
}

void apply_lidar(const ScanParams& params, const CameraIntrinsics& K, const ViewJob& job, DepthView& out) {
  const LidarModel& m = params.sensor.lidar;
  const int W = K.width_px, H = K.height_px;
  out.depth_m = cv::Mat::zeros(H, W, CV_32F);
  out.confidence = cv::Mat::zeros(H, W, CV_8U);
  const CounterRng view_rng(params.seed, kRngPixelNoise, static_cast<std::uint64_t>(job.view_index));
  const double cos_grazing = std::cos(m.grazing_start_deg * kDeg);
  const double cos_medium = std::cos(m.medium_incidence_deg * kDeg);
  const double cos_low = std::cos(m.low_incidence_deg * kDeg);
  const double max_range = params.sensor.max_range_m;
  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v != rows.end(); ++v) {
      for (int u = 0; u < W; ++u) {
        const float z = job.clean.at<float>(v, u);
        if (z <= 0.0f) continue;
        const CounterRng rng = view_rng.child(static_cast<std::uint64_t>(v) * W + u);
        const double c = job.cos_inc.at<float>(v, u);
        double p_drop = m.dropout_prob;
        if (c < cos_grazing) {
          const double angle = std::acos(std::clamp(c, 0.0, 1.0)) / kDeg;
          p_drop += m.grazing_dropout_prob * (angle - m.grazing_start_deg) / std::max(1e-9, 90.0 - m.grazing_start_deg);
        }
        if (rng.uniform(0) < p_drop) continue;
        const double sigma = m.sigma_base_m + m.sigma_quad_per_m * (z - m.sigma_z0_m) * (z - m.sigma_z0_m);
        const double zn = z + sigma * rng.normal(1);
        if (zn <= 0.0) continue;
        out.depth_m.at<float>(v, u) = static_cast<float>(zn);
        const double xn = (u - K.cx_px) / K.fx_px, yn = (v - K.cy_px) / K.fy_px;
        const double range_frac = z * std::sqrt(xn * xn + yn * yn + 1.0) / max_range;
        unsigned char conf = 2;
        if (c < cos_medium || range_frac > m.medium_range_fraction ||
            next_to_edge(job.clean, u, v, static_cast<float>(m.edge_threshold_rel))) {
          conf = 1;
        }
        if (job.glass.at<unsigned char>(v, u) || c < cos_low || range_frac > m.low_range_fraction) conf = 0;
        out.confidence.at<unsigned char>(v, u) = conf;
      }
    }
  });
}

/// Catmull-Rom interpolation of n control points spread evenly over pixels 0..size-1: for each
/// pixel the four (clamped) control indices and their weights.
struct Spline1D {
  std::vector<std::array<int, 4>> idx;
  std::vector<std::array<float, 4>> w;
};

Spline1D catmull_rom(int size, int n) {
  Spline1D sp;
  sp.idx.resize(static_cast<std::size_t>(size));
  sp.w.resize(static_cast<std::size_t>(size));
  for (int p = 0; p < size; ++p) {
    const double s = size > 1 ? static_cast<double>(p) / (size - 1) * (n - 1) : 0.0;
    const int k = std::min(static_cast<int>(s), n - 2);
    const double f = s - k, f2 = f * f, f3 = f2 * f;
    const double w[4] = {0.5 * (-f3 + 2.0 * f2 - f), 0.5 * (3.0 * f3 - 5.0 * f2 + 2.0), 0.5 * (-3.0 * f3 + 4.0 * f2 + f),
                         0.5 * (f3 - f2)};
    for (int j = 0; j < 4; ++j) {
      sp.idx[static_cast<std::size_t>(p)][static_cast<std::size_t>(j)] = std::clamp(k - 1 + j, 0, n - 1);
      sp.w[static_cast<std::size_t>(p)][static_cast<std::size_t>(j)] = static_cast<float>(w[j]);
    }
  }
  return sp;
}

/// What the monocular model draws once per view (and once per scan, shared by the views).
struct MonoViewDraws {
  double scale = 1.0;    ///< scan-shared scale times the view's own
  double shift_m = 0.0;
  bool floor_masked = false;
};

double mono_scan_scale(const ScanParams& params) {
  const MonoModel& m = params.sensor.mono;
  const CounterRng rng(params.seed, kRngScanScale);
  return std::exp(m.scan_scale_mean_ln + m.scan_scale_sigma_ln * rng.normal(0));
}

MonoViewDraws mono_view_draws(const ScanParams& params, int view_index, double scan_scale) {
  const MonoModel& m = params.sensor.mono;
  const auto k = static_cast<std::uint64_t>(view_index);
  MonoViewDraws d;
  d.scale = scan_scale * std::exp(m.scale_sigma_ln * CounterRng(params.seed, kRngViewScale, k).normal(0));
  d.shift_m = m.shift_sigma_m * CounterRng(params.seed, kRngViewShift, k).normal(0);
  d.floor_masked = m.no_ground_prob > 0.0 && CounterRng(params.seed, kRngNoGround, k).uniform(0) < m.no_ground_prob;
  return d;
}

/// Identity of the planar face a wall or closed-door triangle lies on (quantised unit normal and
/// plane offset, so the triangles of one face share it); 0 for every other label.
std::vector<std::uint64_t> wall_face_keys(const Mesh& mesh) {
  std::vector<std::uint64_t> keys(mesh.num_triangles(), 0);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (mesh.labels[i] != MeshLabel::kWall && mesh.labels[i] != MeshLabel::kDoorClosed) continue;
    const Eigen::Vector3f n = mesh.normal(i);
    const Eigen::Vector3f& a = mesh.vertices_m[static_cast<std::size_t>(mesh.triangles[i][0])];
    const auto q = [](double v, double step) { return static_cast<std::uint64_t>(std::llround(v / step) + (1LL << 40)); };
    std::uint64_t h = mix64(q(n.x(), 1e-3));
    h = mix64(h ^ q(n.y(), 1e-3));
    h = mix64(h ^ q(n.z(), 1e-3));
    h = mix64(h ^ q(n.dot(a), 0.01));
    keys[i] = h | 1;  // never 0
  }
  return keys;
}

/// Soft compression beyond the knee towards the ceiling (identity below the knee; 0 = off).
inline float compress_depth(float z, float knee, float ceiling) {
  if (knee <= 0.0f || z <= knee) return z;
  const float span = ceiling - knee;
  return knee + span * std::tanh((z - knee) / span);
}

/// Stage 1 of the monocular model on one view: floor masking, texture-less faces, compression.
cv::Mat mono_surface_stage(const ScanParams& params, const ViewJob& job, const MonoViewDraws& draws,
                           const std::vector<MeshLabel>& labels, const std::vector<std::uint64_t>& face_keys) {
  const MonoModel& m = params.sensor.mono;
  const bool textureless = m.textureless_prob > 0.0;
  const bool per_surface = !job.surface.empty() && (textureless || draws.floor_masked);
  const bool compress = m.compression_knee_m > 0.0;
  if (!per_surface && !compress) return job.clean;  // shared, not copied: later stages only read it
  cv::Mat out(job.clean.size(), CV_32F);
  const CounterRng face_rng(params.seed, kRngTextureless, static_cast<std::uint64_t>(job.view_index));
  const float knee = static_cast<float>(m.compression_knee_m), ceiling = static_cast<float>(m.compression_ceiling_m);
  tbb::parallel_for(tbb::blocked_range<int>(0, job.clean.rows), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v != rows.end(); ++v) {
      const float* z = job.clean.ptr<float>(v);
      const int* tri = per_surface ? job.surface.ptr<int>(v) : nullptr;
      float* dst = out.ptr<float>(v);
      for (int u = 0; u < job.clean.cols; ++u) {
        float d = z[u];
        if (d > 0.0f && tri && tri[u] >= 0) {
          const auto t = static_cast<std::size_t>(tri[u]);
          if (draws.floor_masked && labels[t] == MeshLabel::kFloor) {
            d = 0.0f;
          } else if (textureless && face_keys[t] != 0) {
            const CounterRng face = face_rng.child(face_keys[t]);
            if (face.uniform(0) < m.textureless_prob) d *= static_cast<float>(std::exp(m.textureless_sigma_ln * face.normal(1)));
          }
        }
        dst[u] = compress ? compress_depth(d, knee, ceiling) : d;
      }
    }
  });
  return out;
}

/// Edge bleeding: pixels within `width` (Chebyshev) of a depth edge take the mean inverse depth of
/// the valid pixels of their (2 width + 1)^2 window. Per-pixel sums in a fixed order: the same
/// bytes at any thread count.
cv::Mat bleed_edges(const cv::Mat& depth, int width, float threshold) {
  const int H = depth.rows, W = depth.cols;
  cv::Mat edge = cv::Mat::zeros(H, W, CV_8U);
  for (int v = 0; v < H; ++v) {
    const float* row = depth.ptr<float>(v);
    const float* down = v + 1 < H ? depth.ptr<float>(v + 1) : nullptr;
    unsigned char* e = edge.ptr<unsigned char>(v);
    unsigned char* e_down = down ? edge.ptr<unsigned char>(v + 1) : nullptr;
    for (int u = 0; u < W; ++u) {
      const float z = row[u];
      if (z <= 0.0f) continue;
      const auto jump = [&](float q) { return q > 0.0f && std::abs(q - z) > threshold * std::min(q, z); };
      if (u + 1 < W && jump(row[u + 1])) e[u] = e[u + 1] = 255;
      if (down && jump(down[u])) e[u] = e_down[u] = 255;
    }
  }
  cv::Mat band;
  cv::dilate(edge, band, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * width + 1, 2 * width + 1)));
  cv::Mat out = depth.clone();
  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v != rows.end(); ++v) {
      const unsigned char* b = band.ptr<unsigned char>(v);
      float* dst = out.ptr<float>(v);
      for (int u = 0; u < W; ++u) {
        if (!b[u] || depth.ptr<float>(v)[u] <= 0.0f) continue;
        double inv = 0.0;
        int count = 0;
        for (int y = std::max(0, v - width); y <= std::min(H - 1, v + width); ++y) {
          const float* src = depth.ptr<float>(y);
          for (int x = std::max(0, u - width); x <= std::min(W - 1, u + width); ++x) {
            if (src[x] > 0.0f) {
              inv += 1.0 / src[x];
              ++count;
            }
          }
        }
        dst[u] = static_cast<float>(count / inv);
      }
    }
  });
  return out;
}

void apply_mono(const ScanParams& params, const CameraIntrinsics& K, const ViewJob& job, const MonoViewDraws& draws,
                const std::vector<MeshLabel>& labels, const std::vector<std::uint64_t>& face_keys, DepthView& out) {
  const MonoModel& m = params.sensor.mono;
  const int W = K.width_px, H = K.height_px;
  // Low-frequency warp: zero-mean (in log) random grid, exponentiated, upsampled with
  // Catmull-Rom splines (separable, C1-smooth).
  const int gx = m.warp_grid_x, gy = m.warp_grid_y;
  std::vector<float> grid(static_cast<std::size_t>(gx * gy));
  {
    const CounterRng rng(params.seed, kRngViewWarp, static_cast<std::uint64_t>(job.view_index));
    double mean = 0.0;
    std::vector<double> g(grid.size());
    for (std::size_t j = 0; j < g.size(); ++j) {
      g[j] = m.warp_sigma_ln * rng.normal(j);
      mean += g[j];
    }
    mean /= static_cast<double>(g.size());
    for (std::size_t j = 0; j < g.size(); ++j) grid[j] = static_cast<float>(std::exp(g[j] - mean));
  }
  const Spline1D su = catmull_rom(W, gx), sv = catmull_rom(H, gy);

  // What the network believes the surfaces are: floor masking, texture-less faces, compression.
  const cv::Mat surfaces = mono_surface_stage(params, job, draws, labels, face_keys);

  // Flying pixels at depth edges (random, per pixel).
  const float threshold = static_cast<float>(m.edge_threshold_rel);
  cv::Mat edged = surfaces;
  if (m.flying_pixel_prob > 0.0) {
    edged = surfaces.clone();
    const CounterRng fly_rng(params.seed, kRngFlying, static_cast<std::uint64_t>(job.view_index));
    const int width = m.flying_pixel_width_px;
    tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
      for (int v = rows.begin(); v != rows.end(); ++v) {
        const float* clean = surfaces.ptr<float>(v);
        const float* up = v > 0 ? surfaces.ptr<float>(v - 1) : nullptr;
        const float* down = v + 1 < H ? surfaces.ptr<float>(v + 1) : nullptr;
        float* dst = edged.ptr<float>(v);
        for (int u = 0; u < W; ++u) {
          const float z = clean[u];
          if (z <= 0.0f) continue;
          // Cheap test against the 4-neighbours first; the full search only near edges.
          auto jump = [&](float q) { return q > 0.0f && std::abs(q - z) > threshold * std::min(q, z); };
          bool edge = (u > 0 && jump(clean[u - 1])) || (u + 1 < W && jump(clean[u + 1])) || (up && jump(up[u])) ||
                      (down && jump(down[u]));
          float other = z;
          if (edge || width > 1) edge = max_edge_jump(surfaces, u, v, width, threshold, other) > threshold;
          if (!edge) continue;
          const CounterRng rng = fly_rng.child(static_cast<std::uint64_t>(v) * W + u);
          if (rng.uniform(0) < m.flying_pixel_prob) dst[u] = z + static_cast<float>(rng.uniform(1)) * (other - z);
        }
      }
    });
  }
  // Smearing across the edges.
  const cv::Mat bled = m.edge_bleed_px > 0 ? bleed_edges(edged, m.edge_bleed_px, threshold) : edged;

  out.depth_m.create(H, W, CV_32F);
  const CounterRng view_rng(params.seed, kRngPixelNoise, static_cast<std::uint64_t>(job.view_index));
  const float scale_f = static_cast<float>(draws.scale), shift_f = static_cast<float>(draws.shift_m);
  const float sigma_f = static_cast<float>(m.noise_sigma_rel);
  tbb::parallel_for(tbb::blocked_range<int>(0, H), [&](const tbb::blocked_range<int>& rows) {
    std::vector<float> noise;
    for (int v = rows.begin(); v != rows.end(); ++v) {
      const float* src = bled.ptr<float>(v);
      // This row's warp control values along x, then 4 weights per pixel.
      float row_ctrl[32];
      for (int i = 0; i < gx; ++i) {
        float acc = 0.0f;
        for (int k = 0; k < 4; ++k) acc += sv.w[static_cast<std::size_t>(v)][k] * grid[static_cast<std::size_t>(sv.idx[static_cast<std::size_t>(v)][k] * gx + i)];
        row_ctrl[i] = acc;
      }
      float* dst = out.depth_m.ptr<float>(v);
      // Relative noise for the row, two pixels per hash (pair id = v * ceil(W / 2) + u / 2).
      noise.resize(static_cast<std::size_t>(W) + 1);
      const std::uint64_t pairs_per_row = (static_cast<std::uint64_t>(W) + 1) / 2;
      for (int u = 0; u < W; u += 2) {
        view_rng.item_normal_pair(static_cast<std::uint64_t>(v) * pairs_per_row + static_cast<std::uint64_t>(u / 2),
                                  noise[static_cast<std::size_t>(u)], noise[static_cast<std::size_t>(u) + 1]);
      }
      for (int u = 0; u < W; ++u) {
        const float zf = src[u];
        if (zf <= 0.0f) {
          dst[u] = 0.0f;
          continue;
        }
        const auto& wu = su.w[static_cast<std::size_t>(u)];
        const auto& iu = su.idx[static_cast<std::size_t>(u)];
        const float warp = wu[0] * row_ctrl[iu[0]] + wu[1] * row_ctrl[iu[1]] + wu[2] * row_ctrl[iu[2]] + wu[3] * row_ctrl[iu[3]];
        const float noisy = (scale_f * warp * zf + shift_f) * (1.0f + sigma_f * noise[static_cast<std::size_t>(u)]);
        dst[u] = noisy > 0.0f ? noisy : 0.0f;
      }
    }
  });
}

Eigen::Isometry3d tracker_pose(const ScanParams& params, int view_index, const Eigen::Isometry3d& T_true) {
  const TrackerModel& t = params.sensor.tracker;
  if (t.rotation_sigma_deg <= 0.0 && t.translation_sigma_m <= 0.0) return T_true;
  const CounterRng rng(params.seed, kRngTracker, static_cast<std::uint64_t>(view_index));
  const Eigen::Vector3d w(rng.normal(0), rng.normal(1), rng.normal(2));
  const Eigen::Vector3d dt(rng.normal(3), rng.normal(4), rng.normal(5));
  const Eigen::Vector3d rot = t.rotation_sigma_deg * kDeg * w;
  Eigen::Isometry3d T = T_true;
  if (rot.norm() > 0.0) T.linear() = T_true.linear() * Eigen::AngleAxisd(rot.norm(), rot.normalized()).toRotationMatrix();
  T.translation() += t.translation_sigma_m * dt;
  return T;
}

std::vector<ViewJob> make_jobs(const Pose2& T_world_scan, const ScanParams& params, const CameraIntrinsics& K,
                               bool buffers, bool keep_first) {
  const ScanGeometry& g = params.geometry;
  const Eigen::Isometry3d T_world_scan3 = scan_frame_in_world(T_world_scan, g.camera_height_m);
  const std::vector<int> kept = setting_views(g, params.setting, params.center_view);
  std::vector<ViewJob> jobs(kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) {
    ViewJob& job = jobs[k];
    job.view_index = kept[k];
    const Eigen::Isometry3d T_world_camera = T_world_scan3 * view_pose(g, kept[k]);
    job.R_world_camera = T_world_camera.linear().cast<float>();
    job.origin_world_m = T_world_camera.translation().cast<float>();
    if (!buffers) continue;
    // Every pixel is written by the tracer: no need to clear.
    job.clean.create(K.height_px, K.width_px, CV_32F);
    if (params.sensor.kind == SensorKind::kLidar) job.cos_inc.create(K.height_px, K.width_px, CV_32F);
    const MonoModel& m = params.sensor.mono;
    if (params.sensor.kind == SensorKind::kMono && (m.textureless_prob > 0.0 || m.no_ground_prob > 0.0)) {
      job.surface.create(K.height_px, K.width_px, CV_32S);
    }
    job.glass.create(K.height_px, K.width_px, CV_8U);
    if (keep_first) job.first.create(K.height_px, K.width_px, CV_32F);
  }
  return jobs;
}

}  // namespace

std::vector<std::vector<SemanticHit>> simulate_column_semantics(const RayScene& scene,
                                                                const Eigen::Isometry3d& T_world_camera,
                                                                const CameraIntrinsics& K, double max_range_m,
                                                                double lintel_probe_height_m) {
  const Eigen::Vector3d axis = T_world_camera.linear().col(2);
  const double heading = std::atan2(axis.y(), axis.x());
  const Eigen::Vector3d c = T_world_camera.translation();
  const Mesh& mesh = scene.mesh();
  constexpr int kMaxHits = 64;
  // Faces a horizontal ray enters (outward normal against the ray), nearest first, as (range,
  // label), up to the first face with a label in `stop` or max_range_m.
  auto entered = [&](const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, bool stop_at_wall) {
    std::vector<std::pair<float, MeshLabel>> out;
    float t0 = 0.0f;
    for (int i = 0; i < 4 * kMaxHits; ++i) {
      const RayHit3 h = scene.intersect({origin, dir, t0, static_cast<float>(max_range_m)});
      if (!h.hit()) break;
      const std::size_t tri = static_cast<std::size_t>(h.triangle);
      if (scene.normals()[tri].dot(dir) < 0.0f) {
        out.emplace_back(h.t, mesh.labels[tri]);
        if (stop_at_wall && mesh.labels[tri] == MeshLabel::kWall) break;
        if (static_cast<int>(out.size()) >= kMaxHits) break;
      }
      t0 = h.t + 1e-4f;
    }
    return out;
  };
  std::vector<std::vector<SemanticHit>> columns(static_cast<std::size_t>(K.width_px));
  tbb::parallel_for(0, K.width_px, [&](int u) {
    const double az = heading + std::atan((K.cx_px - u) / K.fx_px);
    const Eigen::Vector3f dir(static_cast<float>(std::cos(az)), static_cast<float>(std::sin(az)), 0.0f);
    const Eigen::Vector3f low(static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z()));
    const Eigen::Vector3f high(low.x(), low.y(), static_cast<float>(lintel_probe_height_m));
    std::vector<SemanticHit>& hits = columns[static_cast<std::size_t>(u)];
    double stop = max_range_m;
    for (const auto& [t, label] : entered(low, dir, true)) {
      SemanticHit hit;
      hit.range_m = t;
      switch (label) {
        case MeshLabel::kWall: hit.label = SemanticClass::kWall; stop = t; break;
        case MeshLabel::kDoorClosed: hit.label = SemanticClass::kDoorClosed; break;
        case MeshLabel::kGlass: hit.label = SemanticClass::kWindow; break;
        case MeshLabel::kClutter: hit.label = SemanticClass::kFurniture; break;
        case MeshLabel::kFloor:
        case MeshLabel::kCeiling: continue;
      }
      // Touching faces of one element (a pane split in two triangles' edges) count once.
      if (!hits.empty() && hits.back().label == hit.label && hit.range_m - hits.back().range_m < 1e-3) continue;
      hits.push_back(hit);
    }
    // Lintels the camera-height ray passes under: open doorways.
    std::vector<SemanticHit> doors;
    for (const auto& [t, label] : entered(high, dir, false)) {
      if (t >= stop - 5e-3) break;  // the stopping wall itself (coplanar above the camera)
      if (label != MeshLabel::kWall) continue;
      const double range_m = t;  // a copy: clang 14 cannot capture a structured binding
      const bool matched = std::any_of(hits.begin(), hits.end(), [&](const SemanticHit& h) {
        // The same wall plane (a closed leaf, a pane or the wall itself under the probe): the
        // probe's face is coplanar with it, so the ranges agree to float precision.
        return h.label != SemanticClass::kFurniture && std::abs(h.range_m - range_m) < 5e-3;
      });
      const bool repeated = !doors.empty() && t - doors.back().range_m < 5e-3;
      if (!matched && !repeated) doors.push_back({SemanticClass::kDoorOpen, t});
    }
    if (!doors.empty()) {
      hits.insert(hits.end(), doors.begin(), doors.end());
      std::stable_sort(hits.begin(), hits.end(), [](const SemanticHit& a, const SemanticHit& b) {
        return a.range_m < b.range_m;
      });
      // The wall that stopped the ray stays last (doors lie before it).
    }
  });
  return columns;
}

CameraIntrinsics view_intrinsics(const ScanGeometry& g) {
  CameraIntrinsics K;
  K.width_px = g.width_px;
  K.height_px = g.height_px;
  K.fx_px = 0.5 * g.width_px / std::tan(0.5 * g.hfov_deg * kDeg);
  K.fy_px = K.fx_px;
  K.cx_px = 0.5 * (g.width_px - 1);
  K.cy_px = 0.5 * (g.height_px - 1);
  return K;
}

Eigen::Isometry3d view_pose(const ScanGeometry& g, int view_index) {
  const double yaw = view_index * g.view_step_deg * kDeg;
  const double pitch = g.pitch_deg * kDeg;
  const Eigen::Vector3d f(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
  const Eigen::Vector3d r(std::sin(yaw), -std::cos(yaw), 0.0);
  const Eigen::Vector3d d = f.cross(r);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = r;
  T.linear().col(1) = d;
  T.linear().col(2) = f;
  T.translation() = g.rotation_radius_m * Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0.0);
  return T;
}

std::vector<Ray3> scan_camera_rays(const Pose2& T_world_scan, const ScanParams& params) {
  validate_scan_params(params);
  const CameraIntrinsics K = view_intrinsics(params.geometry);
  const std::vector<ViewJob> jobs = make_jobs(T_world_scan, params, K, false, false);
  const PixelRays pr =
      pixel_rays(K, params.sensor.kind == SensorKind::kLidar && params.sensor.lidar.lateral_sigma_px > 0.0);
  const int tiles_x = (K.width_px + kTile - 1) / kTile, tiles_y = (K.height_px + kTile - 1) / kTile;
  std::vector<Ray3> out;
  out.reserve(jobs.size() * static_cast<std::size_t>(K.width_px) * static_cast<std::size_t>(K.height_px));
  StreamRayHit rays[kTile * kTile];
  int px_u[kTile * kTile], px_v[kTile * kTile];
  for (const ViewJob& job : jobs) {
    for (int local = 0; local < tiles_x * tiles_y; ++local) {
      const int n = tile_rays(job, K, params, pr, tiles_x, local, rays, px_u, px_v);
      for (int i = 0; i < n; ++i) out.push_back({rays[i].origin(), rays[i].direction(), rays[i].tnear, rays[i].tfar});
    }
  }
  return out;
}

Eigen::Isometry3d scan_frame_in_world(const Pose2& T_world_scan, double camera_height_m) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(T_world_scan.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(T_world_scan.x_m, T_world_scan.y_m, camera_height_m);
  return T;
}

SimulatedScan simulate_scan(const RayScene& scene, const Pose2& T_world_scan, const ScanParams& params,
                   const SimulationOptions& options) {
  validate_scan_params(params);
  if (!std::isfinite(T_world_scan.x_m) || !std::isfinite(T_world_scan.y_m) || !std::isfinite(T_world_scan.yaw_rad)) {
    throw InputError("scan pose must be finite");
  }
  const ScanGeometry& g = params.geometry;
  const CameraIntrinsics K = view_intrinsics(g);
  std::vector<ViewJob> jobs = make_jobs(T_world_scan, params, K, true, options.keep_true_depth);
  trace_views(scene, params, K, jobs, options.keep_true_depth);

  const bool mono = params.sensor.kind == SensorKind::kMono;
  const double scan_scale = mono ? mono_scan_scale(params) : 1.0;
  const std::vector<std::uint64_t> face_keys =
      mono && params.sensor.mono.textureless_prob > 0.0 ? wall_face_keys(scene.mesh()) : std::vector<std::uint64_t>{};

  SimulatedScan scan;
  scan.scan.sensor = params.preset;
  scan.truth.scan_depth_scale = scan_scale;
  scan.params = params;
  scan.truth.T_world_scan = T_world_scan;
  scan.truth.camera_height_m = g.camera_height_m;
  for (ViewJob& job : jobs) {
    DepthView view;
    view.intrinsics = K;
    view.view_index = job.view_index;
    const Eigen::Isometry3d T_true = view_pose(g, job.view_index);
    view.T_scan_camera = tracker_pose(params, job.view_index, T_true);
    view.glass_mask = job.glass;
    MonoViewDraws draws;
    switch (params.sensor.kind) {
      case SensorKind::kPerfect:
        view.depth_m = job.clean;
        break;
      case SensorKind::kLidar:
        apply_lidar(params, K, job, view);
        break;
      case SensorKind::kMono:
        draws = mono_view_draws(params, job.view_index, scan_scale);
        apply_mono(params, K, job, draws, scene.mesh().labels, face_keys, view);
        break;
    }
    if (options.column_semantics) {
      const Eigen::Isometry3d T_world_camera = scan_frame_in_world(T_world_scan, g.camera_height_m) * T_true;
      view.column_semantics = simulate_column_semantics(scene, T_world_camera, K, params.sensor.max_range_m,
                                                        options.lintel_probe_height_m);
    }
    scan.truth.T_scan_camera_true.push_back(T_true);
    scan.truth.view_depth_scale.push_back(draws.scale);
    scan.truth.view_depth_shift_m.push_back(draws.shift_m);
    scan.truth.view_floor_masked.push_back(draws.floor_masked);
    if (options.keep_true_depth) scan.truth.depth_m.push_back(job.first);
    scan.scan.views.push_back(std::move(view));
  }
  return scan;
}

void check_observer_pose(const FloorPlan& plan, const Pose2& pose, const std::string& source) {
  const Vec2 p = pose.position_m();
  std::ostringstream where;
  where << source << ": pose (" << p.x() << ", " << p.y() << ")";
  if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(pose.yaw_rad)) {
    throw InputError(where.str() + ": not finite");
  }
  // Inside anything standing on the floor?
  BlockingOptions solid;
  solid.closed_doors_block = true;
  solid.open_doors_block = false;
  solid.glass_blocks = true;
  solid.obstacles_block = true;
  solid.cut_height_m = 0.01;
  for (const Footprint& f : blocking_footprints(plan, solid)) {
    if (!point_in_convex_polygon(f.polygon_m, p)) continue;
    std::string what;
    if (f.label == SurfaceLabel::kObstacle) {
      what = "obstacle \"" + plan.obstacles[static_cast<std::size_t>(f.source_index)].id + "\"";
    } else {
      const Wall& w = plan.walls[static_cast<std::size_t>(f.source_index)];
      what = (f.label == SurfaceLabel::kDoorClosed ? "the closed door in wall \"" : "wall \"") + w.id + "\"";
    }
    throw InputError(where.str() + " is inside " + what);
  }
  // Inside the building: near an interior cell reachable without crossing the closed envelope.
  const double res = 0.1;
  const GridSpec grid = grid_for_plan(plan, res, 1.0);
  const cv::Mat valid = valid_area_mask(plan, grid, 0.5);
  // Walls, closed doors and glass block the way to the interior; open doorways do not (a pose
  // standing in one reaches the rooms on both sides).
  BlockingOptions envelope;
  envelope.open_doors_block = false;
  envelope.cut_height_m = 1.0;
  std::vector<LabeledSegment> walls = blocking_outline(plan, envelope);
  int row = 0, col = 0;
  bool inside = false;
  if (grid.world_to_cell(p, row, col)) {
    const int reach = 4;
    for (int dr = -reach; dr <= reach && !inside; ++dr) {
      for (int dc = -reach; dc <= reach && !inside; ++dc) {
        const int r = row + dr, c = col + dc;
        if (!grid.contains(r, c) || !valid.at<unsigned char>(r, c)) continue;
        const Vec2 q = grid.cell_center_m(r, c);
        const Vec2 dir = q - p;
        const double len = dir.norm();
        bool crosses = false;
        if (len > 1e-12) {
          for (const LabeledSegment& s : walls) {
            const double t = ray_segment_distance(p, dir / len, s.segment_m);
            if (t >= 0.0 && t <= len) {
              crosses = true;
              break;
            }
          }
        }
        inside = !crosses;
      }
    }
  }
  if (!inside) throw InputError(where.str() + " is outside the building");
}

}  // namespace floorcast
