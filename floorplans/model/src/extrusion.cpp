#include "floorcast/floorplans/extrusion.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <opencv2/imgproc.hpp>
#include <tuple>
#include <utility>

#include "floorcast/core/math.hpp"
#include "floorcast/core/plane_patch.hpp"
#include "floorcast/core/union_find.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/raster.hpp"

namespace floorcast {
namespace {

MeshLabel to_mesh_label(SurfaceLabel s) {
  switch (s) {
    case SurfaceLabel::kWall: return MeshLabel::kWall;
    case SurfaceLabel::kDoorClosed: return MeshLabel::kDoorClosed;
    case SurfaceLabel::kGlass: return MeshLabel::kGlass;
    case SurfaceLabel::kObstacle: return MeshLabel::kClutter;
  }
  return MeshLabel::kWall;
}

Eigen::Vector3f v3(const Vec2& p, double z) {
  return {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(z)};
}

void add_face(std::vector<ExtrudedFace>& faces, std::vector<Eigen::Vector3f> polygon, const Eigen::Vector3f& outward,
              MeshLabel label, int part = -1) {
  ExtrudedFace f;
  f.polygon_m = std::move(polygon);
  f.outward = outward;
  f.label = label;
  f.part_id = part;
  faces.push_back(std::move(f));
}

void add_floor_and_ceiling(std::vector<ExtrudedFace>& faces, const FloorPlan& plan, const ExtrusionParams& params) {
  const double res = params.floor_resolution_m;
  const GridSpec grid = grid_for_plan(plan, res, 1.0);
  cv::Mat valid = valid_area_mask(plan, grid, 0.5);
  double max_thickness = 0.0;
  for (const Wall& w : plan.walls) max_thickness = std::max(max_thickness, w.thickness_m);
  const int r = static_cast<int>(std::ceil(0.5 * max_thickness / res)) + 1;
  cv::dilate(valid, valid, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)));

  // Greedy rectangles: runs of a row, extended upwards while the next row has the same run.
  std::map<std::pair<int, int>, int> open;  // (c0, c1) -> first row
  auto emit = [&](int c0, int c1, int r0, int r1) {
    const double x0 = grid.origin_x_m + c0 * res, x1 = grid.origin_x_m + c1 * res;
    const double y0 = grid.origin_y_m + r0 * res, y1 = grid.origin_y_m + r1 * res;
    const double H = params.wall_height_m;
    if (params.floor) {
      add_face(faces, {v3({x0, y0}, 0.0), v3({x1, y0}, 0.0), v3({x1, y1}, 0.0), v3({x0, y1}, 0.0)},
               Eigen::Vector3f::UnitZ(), MeshLabel::kFloor);
    }
    if (params.ceiling) {
      add_face(faces, {v3({x0, y0}, H), v3({x1, y0}, H), v3({x1, y1}, H), v3({x0, y1}, H)},
               -Eigen::Vector3f::UnitZ(), MeshLabel::kCeiling);
    }
  };
  for (int row = 0; row <= valid.rows; ++row) {
    std::map<std::pair<int, int>, int> next;
    if (row < valid.rows) {
      const unsigned char* p = valid.ptr<unsigned char>(row);
      int c = 0;
      while (c < valid.cols) {
        if (!p[c]) {
          ++c;
          continue;
        }
        const int c0 = c;
        while (c < valid.cols && p[c]) ++c;
        const auto key = std::make_pair(c0, c);
        auto it = open.find(key);
        next[key] = (it != open.end()) ? it->second : row;
      }
    }
    for (const auto& [key, r0] : open) {
      if (next.find(key) == next.end()) emit(key.first, key.second, r0, row);
    }
    open.swap(next);
  }
}

}  // namespace

GlassPaneIndex::GlassPaneIndex(const FloorPlan& plan, const WallIdIndex& ids)
    : plan_(plan), windows_(plan.windows.size()) {
  std::vector<IndexBox> boxes;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto add = [&](int id, int wall, double t0, double t1) {
    panes_.push_back({id, wall, t0, t1});
    if (wall < 0) {
      boxes.push_back({nan, nan, nan, nan});  // unresolved: never a candidate (as in the scan)
      return;
    }
    const Wall& w = plan.walls[static_cast<std::size_t>(wall)];
    const Vec2 dir = w.direction();
    const Vec2 n(-dir.y(), dir.x());
    const double h = 0.5 * w.thickness_m + kTol;
    IndexBox b{inf, inf, -inf, -inf};
    for (const double t : {t0 - kTol, t1 + kTol}) {
      for (const double o : {-h, h}) {
        const Vec2 c = w.a_m + t * dir + o * n;
        b.xmin = std::min(b.xmin, c.x());
        b.ymin = std::min(b.ymin, c.y());
        b.xmax = std::max(b.xmax, c.x());
        b.ymax = std::max(b.ymax, c.y());
      }
    }
    // A NaN corner (a zero-length wall) leaves the box out of the index, where the scan never
    // picked it either (its distance is NaN); the margin covers the rounding of the corners.
    if (!std::isfinite(b.xmin + b.ymin + b.xmax + b.ymax)) {
      boxes.push_back({nan, nan, nan, nan});
      return;
    }
    boxes.push_back(b.grown(1e-9 * (1.0 + std::abs(b.xmin) + std::abs(b.ymin) + std::abs(b.xmax) + std::abs(b.ymax))));
  };
  for (std::size_t k = 0; k < plan.windows.size(); ++k) {
    const Window& w = plan.windows[k];
    const OpeningSpan s = opening_span(plan, ids.find(w.wall_id), w.center_m, w.width_m);
    add(static_cast<int>(k), s.wall_index, s.t0_m, s.t1_m);
  }
  for (std::size_t k = 0; k < plan.walls.size(); ++k) {
    const Wall& w = plan.walls[k];
    if (w.material != WallMaterial::kGlass) continue;
    const double cap = 0.5 * w.thickness_m;
    add(static_cast<int>(windows_ + k), static_cast<int>(k), -cap, w.length_m() + cap);
  }
  index_ = BoxIndex(boxes);
}

int GlassPaneIndex::part_id(const Vec2& p) {
  index_.query({p.x(), p.y(), p.x(), p.y()}, candidates_);
  int best = -1;
  double best_dist = std::numeric_limits<double>::infinity();
  bool windows_done = false;
  for (const std::uint32_t c : candidates_) {  // ascending: window panes first, then glass walls
    const Pane& pane = panes_[c];
    if (!windows_done && static_cast<std::size_t>(pane.id) >= windows_) {
      if (best >= 0) return best;  // a window pane wins over any glass wall
      windows_done = true;
    }
    const Wall& wall = plan_.walls[static_cast<std::size_t>(pane.wall)];
    const Vec2 dir = wall.direction();
    const double t = (p - wall.a_m).dot(dir);
    const double off = std::abs((p - wall.a_m).x() * dir.y() - (p - wall.a_m).y() * dir.x());
    if (t < pane.t0_m - kTol || t > pane.t1_m + kTol || off > 0.5 * wall.thickness_m + kTol) continue;
    if (off < best_dist) {
      best_dist = off;
      best = pane.id;
    }
  }
  return best;
}

const char* mesh_label_name(MeshLabel label) {
  switch (label) {
    case MeshLabel::kWall: return "wall";
    case MeshLabel::kDoorClosed: return "door_closed";
    case MeshLabel::kGlass: return "glass";
    case MeshLabel::kClutter: return "clutter";
    case MeshLabel::kFloor: return "floor";
    case MeshLabel::kCeiling: return "ceiling";
  }
  return "unknown";
}

bool mesh_label_from_name(const std::string& name, MeshLabel& label) {
  for (int i = 0; i < kNumMeshLabels; ++i) {
    if (name == mesh_label_name(static_cast<MeshLabel>(i))) {
      label = static_cast<MeshLabel>(i);
      return true;
    }
  }
  return false;
}

void validate_extrusion(const ExtrusionParams& params) {
  const double H = params.wall_height_m;
  if (!(H > 0.0) || !std::isfinite(H) || H > 100.0) {
    throw InputError("extrusion: wall_height_m must be in (0, 100] m, got " + std::to_string(H));
  }
  if (!(params.door_height_m > 0.0) || !(params.door_height_m < H)) {
    throw InputError("extrusion: door_height_m must be in (0, wall_height_m), got " +
                     std::to_string(params.door_height_m));
  }
  if (!(params.floor_resolution_m >= 0.01) || !(params.floor_resolution_m <= 1.0)) {
    throw InputError("extrusion: floor_resolution_m must be in [0.01, 1] m");
  }
}

std::vector<Vec2> face_in_plane_axes(const ExtrudedFace& face, const Eigen::Matrix3d& basis) {
  std::vector<Vec2> poly;
  poly.reserve(face.polygon_m.size());
  for (const Eigen::Vector3f& p : face.polygon_m) poly.emplace_back(basis.col(0).dot(p.cast<double>()), basis.col(1).dot(p.cast<double>()));
  double area2 = 0.0;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const Vec2& a = poly[k];
    const Vec2& b = poly[(k + 1) % poly.size()];
    area2 += a.x() * b.y() - a.y() * b.x();
  }
  if (area2 < 0.0) std::reverse(poly.begin(), poly.end());
  return poly;
}

std::vector<ExtrudedFace> extrude_faces(const FloorPlan& plan, const ExtrusionParams& params) {
  validate_extrusion(params);
  const double H = params.wall_height_m;

  // Critical heights: the cross-section changes only there.
  std::vector<double> heights{0.0, H};
  auto add_height = [&](double z) {
    if (z > 0.0 && z < H) heights.push_back(z);
  };
  if (!plan.doors.empty()) add_height(params.door_height_m);
  for (const Window& w : plan.windows) {
    add_height(w.sill_m);
    add_height(w.head_m);
  }
  for (const Wall& w : plan.walls) {
    if (w.material != WallMaterial::kGlass) continue;
    add_height(w.glass_sill_m);
    if (w.glass_head_m) add_height(*w.glass_head_m);
  }
  std::sort(heights.begin(), heights.end());
  heights.erase(std::unique(heights.begin(), heights.end(), [](double a, double b) { return b - a < 1e-6; }),
                heights.end());

  FloorPlan no_doors = plan;
  no_doors.doors.clear();
  const WallIdIndex ids(plan);
  GlassPaneIndex glass(plan, ids);

  std::vector<ExtrudedFace> faces;
  // Vertical faces, band by band; a face present with the same 2D segment in consecutive bands
  // is extended instead of split.
  using Key = std::tuple<double, double, double, double, int>;
  struct Open {
    double z0;
    int part;
  };
  std::map<Key, Open> open;
  auto flush = [&](const Key& key, const Open& o, double z1) {
    const Vec2 a(std::get<0>(key), std::get<1>(key)), b(std::get<2>(key), std::get<3>(key));
    const Vec2 d = (b - a).normalized();
    const Eigen::Vector3f outward(static_cast<float>(-d.y()), static_cast<float>(d.x()), 0.0f);
    add_face(faces, {v3(a, o.z0), v3(b, o.z0), v3(b, z1), v3(a, z1)}, outward,
             static_cast<MeshLabel>(std::get<4>(key)), o.part);
  };
  for (std::size_t k = 0; k + 1 < heights.size(); ++k) {
    const double z0 = heights[k], z1 = heights[k + 1];
    const double zm = 0.5 * (z0 + z1);
    BlockingOptions opt;
    opt.closed_doors_block = true;
    opt.open_doors_block = false;
    opt.glass_blocks = true;
    opt.obstacles_block = false;  // obstacles are separate prisms (below)
    opt.cut_height_m = zm;
    const FloorPlan& band_plan = (zm > params.door_height_m) ? no_doors : plan;
    const std::vector<LabeledSegment> outline = blocking_outline(band_plan, opt);
    std::map<Key, Open> next;
    for (const LabeledSegment& s : outline) {
      const MeshLabel label = to_mesh_label(s.label);
      const Key key{s.segment_m.a_m.x(), s.segment_m.a_m.y(), s.segment_m.b_m.x(), s.segment_m.b_m.y(),
                    static_cast<int>(label)};
      auto it = open.find(key);
      if (it != open.end()) {
        next[key] = it->second;
        open.erase(it);
      } else {
        const int part = label == MeshLabel::kGlass
                             ? glass.part_id(0.5 * (s.segment_m.a_m + s.segment_m.b_m))
                             : -1;
        next[key] = {z0, part};
      }
    }
    for (const auto& [key, o] : open) flush(key, o, z0);
    open.swap(next);
  }
  for (const auto& [key, o] : open) flush(key, o, H);

  // Soffits of open door openings (the underside of the lintel).
  for (const Door& d : plan.doors) {
    if (d.closed) continue;
    const OpeningSpan s = opening_span(plan, ids.find(d.wall_id), d.center_m, d.width_m);
    if (s.wall_index < 0) continue;
    const Wall& w = plan.walls[static_cast<std::size_t>(s.wall_index)];
    const Vec2 dir = w.direction();
    const Vec2 n(-dir.y(), dir.x());
    const double h = 0.5 * w.thickness_m;
    const Vec2 a = w.a_m + s.t0_m * dir, b = w.a_m + s.t1_m * dir;
    const double z = params.door_height_m;
    add_face(faces, {v3(a - h * n, z), v3(b - h * n, z), v3(b + h * n, z), v3(a + h * n, z)},
             -Eigen::Vector3f::UnitZ(), MeshLabel::kWall);
  }

  // Obstacles: prisms from the floor to min(height, ceiling), sides and top. (Faces of an
  // obstacle inside a wall or another obstacle are hidden and harmless for ray casting.)
  for (const Obstacle& o : plan.obstacles) {
    const double top = std::min(o.height_m, H);
    std::vector<Vec2> poly;
    if (o.kind == ObstacleKind::kPillar) {
      const double r = 0.5 * o.size_m.x();
      for (int k = 0; k < 16; ++k) {
        const double a = o.yaw_rad + 2.0 * kPi * k / 16.0;
        poly.push_back(o.center_m + r * Vec2(std::cos(a), std::sin(a)));
      }
    } else {
      const double c = std::cos(o.yaw_rad), s = std::sin(o.yaw_rad);
      const Vec2 ex = 0.5 * o.size_m.x() * Vec2(c, s);
      const Vec2 ey = 0.5 * o.size_m.y() * Vec2(-s, c);
      poly = {o.center_m - ex - ey, o.center_m + ex - ey, o.center_m + ex + ey, o.center_m - ex + ey};
    }
    // Counter-clockwise footprint: the outward normal of edge a->b is its right-hand normal.
    for (std::size_t k = 0; k < poly.size(); ++k) {
      const Vec2& a = poly[k];
      const Vec2& b = poly[(k + 1) % poly.size()];
      const Vec2 d = (b - a).normalized();
      const Eigen::Vector3f outward(static_cast<float>(d.y()), static_cast<float>(-d.x()), 0.0f);
      add_face(faces, {v3(a, 0.0), v3(b, 0.0), v3(b, top), v3(a, top)}, outward, MeshLabel::kClutter);
    }
    if (top < H - 1e-6) {
      std::vector<Eigen::Vector3f> lid;
      for (const Vec2& p : poly) lid.push_back(v3(p, top));
      add_face(faces, std::move(lid), Eigen::Vector3f::UnitZ(), MeshLabel::kClutter);
    }
  }

  if (params.floor || params.ceiling) add_floor_and_ceiling(faces, plan, params);
  return faces;
}

}  // namespace floorcast

namespace floorcast {

std::vector<ExtrudedPlane> group_coplanar_faces(const std::vector<ExtrudedFace>& faces, double gap_m) {
  const std::size_t n = faces.size();
  auto label_class = [](MeshLabel l) { return l == MeshLabel::kDoorClosed ? MeshLabel::kWall : l; };
  struct Item {
    int face;
    int cls;
    std::array<long long, 4> key;  // normal and offset quantised to 1e-6
    Eigen::Vector3d normal;
  };
  std::vector<Item> items;
  items.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const ExtrudedFace& f = faces[i];
    if (f.polygon_m.size() < 3) continue;
    const Eigen::Vector3d nrm = f.outward.cast<double>().normalized();
    const double offset = nrm.dot(f.polygon_m[0].cast<double>());
    auto q = [](double x) { return std::llround(x * 1e6); };
    items.push_back({static_cast<int>(i), static_cast<int>(label_class(f.label)),
                     {q(nrm.x()), q(nrm.y()), q(nrm.z()), q(offset)}, nrm});
  }
  // Planes: items with the same class and quantised normal and offset.
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    return std::tie(a.cls, a.key, a.face) < std::tie(b.cls, b.key, b.face);
  });
  std::vector<ExtrudedPlane> planes;
  std::vector<std::pair<int, int>> first_face_and_plane;
  std::size_t start = 0;
  while (start < items.size()) {
    std::size_t end = start + 1;
    while (end < items.size() && items[end].cls == items[start].cls && items[end].key == items[start].key) ++end;
    // Connected components of the faces' in-plane boxes: sweep along u.
    const Eigen::Vector3d nrm = items[start].normal;
    const Eigen::Matrix3d basis = plane_cell_basis(nrm);
    const Eigen::Vector3d u = basis.col(0), v = basis.col(1);
    struct Box {
      double u0, u1, v0, v1;
      int item;
    };
    std::vector<Box> boxes;
    for (std::size_t k = start; k < end; ++k) {
      Box b{1e300, -1e300, 1e300, -1e300, static_cast<int>(k)};
      for (const Eigen::Vector3f& p : faces[static_cast<std::size_t>(items[k].face)].polygon_m) {
        const double pu = u.dot(p.cast<double>()), pv = v.dot(p.cast<double>());
        b.u0 = std::min(b.u0, pu);
        b.u1 = std::max(b.u1, pu);
        b.v0 = std::min(b.v0, pv);
        b.v1 = std::max(b.v1, pv);
      }
      boxes.push_back(b);
    }
    std::sort(boxes.begin(), boxes.end(), [](const Box& a, const Box& b) { return a.u0 < b.u0 || (a.u0 == b.u0 && a.item < b.item); });
    UnionFind uf(boxes.size());
    for (std::size_t a = 0; a < boxes.size(); ++a) {
      for (std::size_t b = a + 1; b < boxes.size() && boxes[b].u0 <= boxes[a].u1 + gap_m; ++b) {
        if (boxes[b].v0 <= boxes[a].v1 + gap_m && boxes[a].v0 <= boxes[b].v1 + gap_m) {
          uf.unite(static_cast<int>(a), static_cast<int>(b));
        }
      }
    }
    std::map<int, std::vector<int>> components;  // root -> faces
    for (std::size_t a = 0; a < boxes.size(); ++a) {
      components[uf.find(static_cast<int>(a))].push_back(items[static_cast<std::size_t>(boxes[a].item)].face);
    }
    for (auto& [root, fs] : components) {
      std::sort(fs.begin(), fs.end());
      ExtrudedPlane p;
      p.normal = nrm;
      double offset = 0.0;
      for (int f : fs) offset += nrm.dot(faces[static_cast<std::size_t>(f)].polygon_m[0].cast<double>());
      p.offset_m = offset / static_cast<double>(fs.size());
      p.label = static_cast<MeshLabel>(items[start].cls);
      p.faces = std::move(fs);
      first_face_and_plane.emplace_back(p.faces.front(), static_cast<int>(planes.size()));
      planes.push_back(std::move(p));
    }
    start = end;
  }
  std::sort(first_face_and_plane.begin(), first_face_and_plane.end());
  std::vector<ExtrudedPlane> ordered;
  ordered.reserve(planes.size());
  for (const auto& [face, idx] : first_face_and_plane) ordered.push_back(std::move(planes[static_cast<std::size_t>(idx)]));
  return ordered;
}

}  // namespace floorcast
