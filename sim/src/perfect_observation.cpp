#include "floorcast/sim/perfect_observation.hpp"
#include "floorcast/core/limits.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/ray_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace floorcast {
namespace {


double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Clips segment a-b to the disk of radius r around o. False if nothing remains.
bool clip_to_disk(const Vec2& o, double r, Vec2& a, Vec2& b) {
  const Vec2 d = b - a;
  const Vec2 f = a - o;
  const double A = d.squaredNorm();
  const double B = 2.0 * f.dot(d);
  const double C = f.squaredNorm() - r * r;
  const double disc = B * B - 4.0 * A * C;
  if (disc <= 0.0) return false;
  const double s = std::sqrt(disc);
  const double t0 = std::max(0.0, (-B - s) / (2.0 * A));
  const double t1 = std::min(1.0, (-B + s) / (2.0 * A));
  if (t1 - t0 <= 1e-12) return false;
  const Vec2 a0 = a;
  a = a0 + t0 * d;
  b = a0 + t1 * d;
  return true;
}

/// Point where the ray from o at angle theta meets the line through segment s.
Vec2 ray_line_point(const Vec2& o, double theta, const Segment2& s) {
  const Vec2 dir(std::cos(theta), std::sin(theta));
  const Vec2 e = s.b_m - s.a_m;
  const double denom = cross(dir, e);
  const double t = cross(s.a_m - o, e) / denom;
  return o + t * dir;
}

}  // namespace

/// The perfect 3-D planes' scene: the extrusion as the observer's blocking options see it (open
/// doors closed when they block, glass and obstacles only when they block), its faces grouped
/// into planes, and the Embree scene that decides what the camera sees.
struct PerfectObserver::Planes {
  std::vector<ExtrudedFace> faces;
  std::vector<ExtrudedPlane> planes;
  std::vector<Eigen::Vector3d> centre_m;  ///< per plane: centre of its faces' vertices
  std::vector<double> radius_m;           ///< ... and the largest distance of a vertex from it
  std::unique_ptr<RayScene> scene;
};

PerfectObserver::PerfectObserver(const FloorPlan& plan, const PerfectObservationParams& params)
    : params_(params) {
  check_limit("max_rays", params.num_rays, "perfect observer", "rays");
  check_limit("max_rays", params.bev_columns, "perfect observer: bev_columns", "columns");
  outline_ = blocking_outline(plan, params.blocking);
  if (params.bev_columns > 0) {
    semantic_lines_ = semantic_plan_lines(plan, BevClasses::kSemantic, params.blocking.cut_height_m);
    occupancy_lines_ = semantic_plan_lines(plan, BevClasses::kOccupancy, params.blocking.cut_height_m);
  }
  if (!(params.plane_cell_m >= 0.01 && params.plane_cell_m <= 10.0)) {
    throw InputError("perfect observer: plane_cell_m must be in [0.01, 10] m");
  }
  if (!params.planes) return;
  FloorPlan drawn = plan;
  if (params.blocking.open_doors_block) {
    for (Door& d : drawn.doors) d.closed = true;
  }
  planes_ = std::make_unique<Planes>();
  Planes& P = *planes_;
  for (ExtrudedFace& f : extrude_faces(drawn, params.extrusion)) {
    if (f.label == MeshLabel::kGlass && !params.blocking.glass_blocks) continue;
    if (f.label == MeshLabel::kClutter && !params.blocking.obstacles_block) continue;
    P.faces.push_back(std::move(f));
  }
  P.planes = group_coplanar_faces(P.faces);
  for (const ExtrudedPlane& pl : P.planes) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    int n = 0;
    for (int f : pl.faces) {
      for (const Eigen::Vector3f& v : P.faces[static_cast<std::size_t>(f)].polygon_m) {
        c += v.cast<double>();
        ++n;
      }
    }
    c /= std::max(n, 1);
    double r = 0.0;
    for (int f : pl.faces) {
      for (const Eigen::Vector3f& v : P.faces[static_cast<std::size_t>(f)].polygon_m) r = std::max(r, (v.cast<double>() - c).norm());
    }
    P.centre_m.push_back(c);
    P.radius_m.push_back(r);
  }
  if (!P.faces.empty()) P.scene = std::make_unique<RayScene>(mesh_from_faces(P.faces));
}

PerfectObserver::~PerfectObserver() = default;
PerfectObserver::PerfectObserver(PerfectObserver&&) noexcept = default;
PerfectObserver& PerfectObserver::operator=(PerfectObserver&&) noexcept = default;

std::vector<PlanePatch> PerfectObserver::visible_planes(const Pose2& T_world_observer) const {
  std::vector<PlanePatch> out;
  if (!planes_ || !planes_->scene) return out;
  const Planes& P = *planes_;
  const double R = params_.max_range_m;
  const double step = 0.5 * params_.plane_cell_m;
  const Eigen::Vector3d eye(T_world_observer.x_m, T_world_observer.y_m, params_.camera_height_m);
  // Samples on a grid of half a cell in each front-facing plane within range, one ray each.
  std::vector<Ray3> rays;
  std::vector<int> ray_plane;
  for (std::size_t k = 0; k < P.planes.size(); ++k) {
    const ExtrudedPlane& pl = P.planes[k];
    if ((P.centre_m[k] - eye).head<2>().norm() - P.radius_m[k] > R) continue;
    if (pl.normal.dot(eye) - pl.offset_m <= 1e-9) continue;  // the eye is behind it
    const Eigen::Matrix3d B = plane_cell_basis(pl.normal);
    for (int fi : pl.faces) {
      const ExtrudedFace& f = P.faces[static_cast<std::size_t>(fi)];
      const std::vector<Vec2> poly = face_in_plane_axes(f, B);
      double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
      for (const Vec2& q : poly) {
        u0 = std::min(u0, q.x());
        u1 = std::max(u1, q.x());
        v0 = std::min(v0, q.y());
        v1 = std::max(v1, q.y());
      }
      const Eigen::Vector3d foot = pl.offset_m * pl.normal;
      for (double u = (std::floor(u0 / step) + 0.5) * step; u < u1; u += step) {
        for (double v = (std::floor(v0 / step) + 0.5) * step; v < v1; v += step) {
          if (!point_in_convex_polygon(poly, Vec2(u, v))) continue;
          const Eigen::Vector3d q = foot + u * B.col(0) + v * B.col(1);
          const Eigen::Vector3d d = q - eye;
          if (d.head<2>().norm() > R) continue;
          Ray3 ray;
          ray.origin_m = eye.cast<float>();
          ray.direction = d.cast<float>();
          ray.t_near = 0.0f;
          ray.t_far = static_cast<float>(1.0 - 0.005 / std::max(d.norm(), 0.01));
          rays.push_back(ray);
          ray_plane.push_back(static_cast<int>(k));
        }
      }
    }
  }
  std::vector<RayHit3> hits(rays.size());
  if (!rays.empty()) P.scene->intersect_stream(rays.data(), hits.data(), rays.size(), false);
  // Visible samples per plane, in the observer's 3D frame.
  const double c = std::cos(T_world_observer.yaw_rad), s = std::sin(T_world_observer.yaw_rad);
  Eigen::Isometry3d T_obs_world = Eigen::Isometry3d::Identity();
  T_obs_world.linear() << c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0;
  T_obs_world.translation() = -(T_obs_world.linear() * eye);
  std::vector<std::vector<Eigen::Vector3d>> seen(P.planes.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (hits[i].hit()) continue;
    const Eigen::Vector3d q = rays[i].origin_m.cast<double>() + rays[i].direction.cast<double>();
    seen[static_cast<std::size_t>(ray_plane[i])].push_back(T_obs_world * q);
  }
  const double cell_area = params_.plane_cell_m * params_.plane_cell_m;
  for (std::size_t k = 0; k < P.planes.size(); ++k) {
    if (seen[k].empty()) continue;
    const Eigen::Vector3d n = T_obs_world.linear() * P.planes[k].normal;
    const double offset = P.planes[k].offset_m + n.dot(T_obs_world.translation());
    PlanePatch patch = make_plane_patch(n, offset, seen[k], params_.plane_cell_m, 1);
    patch.support_points = 0;  // from geometry, not measured
    if (static_cast<double>(patch.cells_m.size()) * cell_area < params_.min_plane_area_m2) continue;
    out.push_back(std::move(patch));
  }
  return out;
}

BevPrediction PerfectObserver::bev(const Pose2& T_world_observer, BevClasses classes, int columns) const {
  if (columns <= 0) return {};
  BevDepthBins bins;
  bins.count = params_.bev_depth_bins;
  bins.min_m = params_.bev_min_depth_m;
  bins.max_m = params_.max_range_m;
  const SemanticPlanLines& lines = classes == BevClasses::kSemantic ? semantic_lines_ : occupancy_lines_;
  const std::vector<double> azimuths = full_circle_azimuths(columns);
  std::vector<std::vector<SemanticHit>> hits(azimuths.size());
  for (std::size_t w = 0; w < azimuths.size(); ++w) {
    hits[w] = semantic_ray_hits(lines, T_world_observer.position_m(), T_world_observer.yaw_rad + azimuths[w],
                                params_.max_range_m);
  }
  return one_hot_bev(hits, azimuths, classes, bins);
}

std::vector<LabeledSegment> PerfectObserver::visible_world_segments(const Vec2& o) const {
  const double R = params_.max_range_m;

  // Front-facing outline pieces (observer on their free side), clipped to the range disk. Any ray
  // from a free point meets a front face before a back face, so back faces never matter.
  struct Candidate {
    Segment2 seg;
    int source;
  };
  std::vector<Candidate> cands;
  std::vector<double> angles;
  for (std::size_t i = 0; i < outline_.size(); ++i) {
    const Segment2& s = outline_[i].segment_m;
    if (cross(s.b_m - s.a_m, o - s.a_m) <= 1e-12) continue;  // back-facing or collinear
    Vec2 a = s.a_m, b = s.b_m;
    if (!clip_to_disk(o, R, a, b)) continue;
    cands.push_back({{a, b}, static_cast<int>(i)});
    angles.push_back(std::atan2(a.y() - o.y(), a.x() - o.x()));
    angles.push_back(std::atan2(b.y() - o.y(), b.x() - o.x()));
  }
  if (cands.empty()) return {};
  std::sort(angles.begin(), angles.end());
  angles.erase(std::unique(angles.begin(), angles.end(),
                           [](double x, double y) { return std::abs(x - y) < 1e-12; }),
               angles.end());

  // Between consecutive critical angles the nearest front face is fixed (outline pieces never
  // cross), so one probe ray per interval decides what is seen there.
  std::vector<LabeledSegment> visible;
  int last_source = -1;
  int first_source = -1;
  const std::size_t n = angles.size();
  for (std::size_t k = 0; k < n; ++k) {
    const double t0 = angles[k];
    const double t1 = (k + 1 < n) ? angles[k + 1] : angles[0] + 2.0 * kPi;
    if (t1 - t0 < 1e-12) continue;
    const double mid = 0.5 * (t0 + t1);
    const Vec2 dir(std::cos(mid), std::sin(mid));
    double best = std::numeric_limits<double>::infinity();
    int best_idx = -1;
    for (std::size_t c = 0; c < cands.size(); ++c) {
      const double t = ray_segment_distance(o, dir, cands[c].seg);
      if (t >= 0.0 && t < best) {
        best = t;
        best_idx = static_cast<int>(c);
      }
    }
    if (best_idx < 0) {
      last_source = -1;
      continue;
    }
    const Candidate& c = cands[static_cast<std::size_t>(best_idx)];
    // Visible piece: the face between the two bounding rays. A front face (observer on its free,
    // left side) runs counter-clockwise around the observer, so it goes from the t0 ray to t1.
    const Vec2 p0 = ray_line_point(o, t0, c.seg);
    const Vec2 p1 = ray_line_point(o, t1, c.seg);
    if (c.source == last_source && !visible.empty()) {
      visible.back().segment_m.b_m = p1;  // extends the previous piece of the same face
    } else {
      LabeledSegment piece;
      piece.segment_m = {p0, p1};
      piece.label = outline_[static_cast<std::size_t>(c.source)].label;
      visible.push_back(piece);
      if (visible.size() == 1) first_source = c.source;
    }
    last_source = c.source;
  }
  // The sweep wraps around: the last and first pieces may be one face.
  if (visible.size() > 1 && last_source >= 0 && last_source == first_source &&
      (visible.back().segment_m.b_m - visible.front().segment_m.a_m).norm() < 1e-9) {
    visible.front().segment_m.a_m = visible.back().segment_m.a_m;
    visible.pop_back();
  }
  visible.erase(std::remove_if(visible.begin(), visible.end(),
                               [](const LabeledSegment& s) { return s.segment_m.length_m() < 1e-9; }),
                visible.end());
  return visible;
}

std::vector<double> PerfectObserver::ray_ranges(const Vec2& o, double start_rad, int num_rays) const {
  std::vector<double> ranges(static_cast<std::size_t>(std::max(num_rays, 0)), params_.max_range_m);
  for (int i = 0; i < num_rays; ++i) {
    const double a = start_rad + 2.0 * kPi * i / num_rays;
    const Vec2 dir(std::cos(a), std::sin(a));
    double best = params_.max_range_m;
    for (const LabeledSegment& l : outline_) {
      const double t = ray_segment_distance(o, dir, l.segment_m);
      if (t >= 0.0 && t < best) best = t;
    }
    ranges[static_cast<std::size_t>(i)] = best;
  }
  return ranges;
}

Observation2D PerfectObserver::observe(const Pose2& T_world_observer) const {
  const Vec2 o = T_world_observer.position_m();
  Observation2D obs;
  obs.max_range_m = params_.max_range_m;
  for (const LabeledSegment& s : visible_world_segments(o)) {
    obs.segments_m.push_back({T_world_observer.inverse_transform(s.segment_m.a_m),
                              T_world_observer.inverse_transform(s.segment_m.b_m)});
  }
  obs.ray_ranges_m = ray_ranges(o, T_world_observer.yaw_rad, params_.num_rays);
  if (params_.bev_columns > 0) {
    obs.bev.push_back(bev(T_world_observer, BevClasses::kSemantic, params_.bev_columns));
    obs.bev.push_back(bev(T_world_observer, BevClasses::kOccupancy, params_.bev_columns));
  }
  if (params_.planes) {
    obs.planes = visible_planes(T_world_observer);
    obs.plane_cell_m = params_.plane_cell_m;
  }
  return obs;
}

const FieldList<PerfectObservationParams>& PerfectObservationParams::fields() {
  using P = PerfectObservationParams;
  static const FieldList<P> f =
      FieldList<P>("perfect observer")
          .number("max_range_m", &P::max_range_m, 0.1, 1000.0, "visible geometry within this range, m (PALMS+ sec. 4.4: 10)")
          .flatten(&P::blocking, blocking_fields())
          .integer("num_rays", &P::num_rays, 0, 3600, "equiangular rays (F3Loc: 36); 0 = none")
          .integer("bev_columns", &P::bev_columns, 0, 3600,
                   "equiangular columns of the perfect BEVs (the thesis' one-hot ray casting of the plan); 0 = none")
          .integer("bev_depth_bins", &P::bev_depth_bins, 1, 255, "log-spaced depth bins of the perfect BEVs")
          .number("bev_min_depth_m", &P::bev_min_depth_m, 0.01, 100.0, "first depth bin edge of the perfect BEVs, m (the last is max_range_m)")
          .flag("planes", &P::planes, "perfect 3-D planes: the visible planar surfaces as plane patches")
          .number("plane_cell_m", &P::plane_cell_m, 0.01, 10.0, "cell edge of the patches, m (VoxelPlane-Reloc's l)")
          .number("camera_height_m", &P::camera_height_m, 0.0, 100.0, "the observer's eye above the floor (the scan frame's origin), m")
          .number("min_plane_area_m2", &P::min_plane_area_m2, 0.0, 1e6,
                  "visible patches smaller than this are left out (slivers of jambs and soffits), m^2")
          .number("wall_height_m", [](auto& p) -> auto& { return p.extrusion.wall_height_m; }, 0.1, 100.0,
                  "the 3D building's wall (= ceiling) height, as the simulator extrudes it, m")
          .number("door_height_m", [](auto& p) -> auto& { return p.extrusion.door_height_m; }, 0.05, 100.0,
                  "the 3D building's door height, m")
          .check([](const P& p, const ParamReader& r) {
            if (p.bev_columns > 0 && !(p.bev_min_depth_m < p.max_range_m)) r.fail("bev_min_depth_m", "must be below max_range_m");
            if (!(p.extrusion.door_height_m < p.extrusion.wall_height_m)) r.fail("door_height_m", "must be below wall_height_m");
          });
  return f;
}

nlohmann::ordered_json PerfectObservationParams::to_json() const { return fields().write(*this); }

void PerfectObservationParams::apply_overrides(const nlohmann::json& overrides) { fields().read(*this, overrides); }

void PerfectObservationParams::apply_shared(const SharedParams& shared) {
  max_range_m = shared.range_m;
  blocking = shared.blocking;
}

}  // namespace floorcast
