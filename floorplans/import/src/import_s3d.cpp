// Structured3D annotation_3d.json. Facts used (the dataset's data_organization.md):
//   junctions[k].coordinate: 3D point in millimetres, z up;
//   planes[p]: type "floor" | "ceiling" | "wall", normal (pointing to the empty space), offset;
//   semantics[s]: type (a room type, "door", "window", "outwall"), planeID: plane indices;
//   planeLineMatrix[p][l] = 1 iff line l lies on plane p; lineJunctionMatrix[l][k] = 1 iff
//   junction k lies on line l.
// Walls: every "wall" plane of a room semantics (and of "outwall" with s3d_include_outwall) becomes
// one wall whose axis is the plane's horizontal trace, spanning its junctions' extent: the walls
// are the room surfaces, as PALMS rebuilds Structured3D plans. Doors and windows: the junctions of
// a door/window semantics' planes, projected to the floor, give the opening's line (principal
// direction), centre, width and (windows) sill and head; the opening is cut into every room wall
// it lies in (door spans cut out of walls, as PALMS does; an opening in a wall between two rooms
// opens both surfaces).
#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include <Eigen/Eigenvalues>

#include "floorcast/floorplans/import.hpp"
#include "import_common.hpp"

namespace floorcast {
namespace {

using Json = nlohmann::json;
using import_detail::fmt;
using import_detail::quoted;


class S3dReader {
 public:
  explicit S3dReader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& reason) const {
    throw InputError(source_ + ": " + where + ": " + reason);
  }

  const Json& array(const Json& root, const char* key) const {
    if (!root.contains(key)) fail("top level", "missing required field " + quoted(key));
    const Json& v = root.at(key);
    if (!v.is_array()) fail(key, std::string("must be an array, got ") + v.type_name());
    return v;
  }

  double number(const Json& v, const std::string& where) const {
    if (!v.is_number()) fail(where, "must be a number, got " + v.dump());
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(where, "is not a finite number");
    return x;
  }

  Eigen::Vector3d vec3(const Json& obj, const char* key, const std::string& where) const {
    if (!obj.is_object()) fail(where, std::string("must be an object, got ") + obj.type_name());
    if (!obj.contains(key)) fail(where, "missing required field " + quoted(key));
    const Json& v = obj.at(key);
    if (!v.is_array() || v.size() != 3) fail(where + "." + key, "must be an array of 3 numbers, got " + v.dump());
    return {number(v[0], where + "." + key + "[0]"), number(v[1], where + "." + key + "[1]"),
            number(v[2], where + "." + key + "[2]")};
  }

  /// Indices of the non-zero entries of each row of a 0/1 matrix with `rows` x `cols` entries.
  std::vector<std::vector<int>> sparse_rows(const Json& root, const char* key, std::size_t rows, std::size_t cols,
                                            const char* row_name, const char* col_name) const {
    const Json& m = array(root, key);
    if (m.size() != rows) {
      fail(key, "has " + std::to_string(m.size()) + " rows, expected one per " + row_name + " (" +
                    std::to_string(rows) + ")");
    }
    std::vector<std::vector<int>> out(rows);
    for (std::size_t r = 0; r < rows; ++r) {
      const Json& row = m[r];
      const std::string where = std::string(key) + "[" + std::to_string(r) + "]";
      if (!row.is_array() || row.size() != cols) {
        fail(where, "must be an array of " + std::to_string(cols) + " entries (one per " + col_name + ")");
      }
      for (std::size_t c = 0; c < cols; ++c) {
        const Json& v = row[c];
        if (!v.is_number()) fail(where + "[" + std::to_string(c) + "]", "must be 0 or 1, got " + v.dump());
        if (v.get<double>() != 0.0) out[r].push_back(static_cast<int>(c));
      }
    }
    return out;
  }

 private:
  std::string source_;
};

struct Face {
  std::string wall_id;
  Vec2 a, b;        // metres
  Vec2 u;           // unit direction a->b
  Vec2 n;           // unit normal, pointing to the room (empty space)
  double t0 = 0.0;  // extent along u (a = t0, b = t1 in the plane's own frame)
  double t1 = 0.0;
};

}  // namespace

ImportResult import_s3d_json(const std::string& json_text, const std::string& source, const ImportOptions& options) {
  const double thickness = import_detail::wall_thickness_or(options, 0.02, source);
  S3dReader rd(source);
  Json root;
  try {
    root = Json::parse(json_text);
  } catch (const Json::exception& e) {
    throw InputError(source + ": malformed JSON: " + e.what());
  }
  if (!root.is_object()) throw InputError(source + ": top level must be a JSON object");

  const Json& junctions_json = rd.array(root, "junctions");
  const Json& lines_json = rd.array(root, "lines");
  const Json& planes_json = rd.array(root, "planes");
  const Json& semantics_json = rd.array(root, "semantics");

  const double unit_m = import_detail::source_unit_m(options, "mm", source);
  std::vector<Eigen::Vector3d> junctions;
  for (std::size_t k = 0; k < junctions_json.size(); ++k) {
    junctions.push_back(rd.vec3(junctions_json[k], "coordinate", "junctions[" + std::to_string(k) + "]") * unit_m);
  }
  struct Plane {
    std::string type;
    Eigen::Vector3d normal;
    long long id = 0;
  };
  std::vector<Plane> planes;
  for (std::size_t p = 0; p < planes_json.size(); ++p) {
    const std::string where = "planes[" + std::to_string(p) + "]";
    const Json& pj = planes_json[p];
    Plane plane;
    plane.normal = rd.vec3(pj, "normal", where);
    if (!pj.contains("type") || !pj["type"].is_string()) rd.fail(where, "missing string field \"type\"");
    plane.type = pj["type"].get<std::string>();
    plane.id = pj.contains("ID") && pj["ID"].is_number_integer() ? pj["ID"].get<long long>() : static_cast<long long>(p);
    if (plane.normal.norm() < 1e-9) rd.fail(where, "normal has zero length");
    plane.normal.normalize();
    planes.push_back(plane);
  }
  const auto plane_lines = rd.sparse_rows(root, "planeLineMatrix", planes.size(), lines_json.size(), "plane", "line");
  const auto line_junctions =
      rd.sparse_rows(root, "lineJunctionMatrix", lines_json.size(), junctions.size(), "line", "junction");

  auto plane_junctions = [&](int p) {
    std::set<int> js;
    for (int l : plane_lines[static_cast<std::size_t>(p)]) {
      for (int j : line_junctions[static_cast<std::size_t>(l)]) js.insert(j);
    }
    return std::vector<int>(js.begin(), js.end());
  };

  struct Semantic {
    std::string type;
    long long id = 0;
    std::vector<int> planes;
  };
  std::vector<Semantic> semantics;
  for (std::size_t s = 0; s < semantics_json.size(); ++s) {
    const std::string where = "semantics[" + std::to_string(s) + "]";
    const Json& sj = semantics_json[s];
    if (!sj.is_object()) rd.fail(where, "must be an object");
    if (!sj.contains("type") || !sj["type"].is_string()) rd.fail(where, "missing string field \"type\"");
    if (!sj.contains("planeID") || !sj["planeID"].is_array()) rd.fail(where, "missing array field \"planeID\"");
    Semantic sem;
    sem.type = sj["type"].get<std::string>();
    sem.id = sj.contains("ID") && sj["ID"].is_number_integer() ? sj["ID"].get<long long>() : static_cast<long long>(s);
    for (std::size_t k = 0; k < sj["planeID"].size(); ++k) {
      const Json& v = sj["planeID"][k];
      if (!v.is_number_integer() || v.get<long long>() < 0 || v.get<long long>() >= static_cast<long long>(planes.size())) {
        rd.fail(where + ".planeID[" + std::to_string(k) + "]", "is not a plane index in [0, " +
                                                               std::to_string(planes.size()) + "): " + v.dump());
      }
      sem.planes.push_back(v.get<int>());
    }
    semantics.push_back(std::move(sem));
  }

  ImportResult result;
  FloorPlan plan;
  plan.level = import_detail::plain_level(options, source);

  // Floor height: lowest junction of the floor planes (Structured3D floors are at z = 0).
  double floor_z = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < planes.size(); ++p) {
    if (planes[p].type != "floor") continue;
    for (int j : plane_junctions(static_cast<int>(p))) floor_z = std::min(floor_z, junctions[static_cast<std::size_t>(j)].z());
  }
  if (!std::isfinite(floor_z)) {
    floor_z = 0.0;
    for (const auto& j : junctions) floor_z = std::min(floor_z, j.z());
  }

  // Walls: room (and optionally outwall) wall planes.
  std::vector<Face> faces;
  std::set<int> used_planes;
  int rooms = 0, doors_read = 0, windows_read = 0;
  for (const Semantic& sem : semantics) {
    const bool opening = sem.type == "door" || sem.type == "window";
    if (opening) continue;
    if (sem.type == "outwall" && !options.s3d_include_outwall) continue;
    if (sem.type != "outwall") ++rooms;
    for (int p : sem.planes) {
      const Plane& plane = planes[static_cast<std::size_t>(p)];
      if (plane.type != "wall" || !used_planes.insert(p).second) continue;
      const Vec2 n2(plane.normal.x(), plane.normal.y());
      if (n2.norm() < 0.9) {
        result.notes.push_back("planes[" + std::to_string(p) + "] (ID " + std::to_string(plane.id) +
                               "): wall plane is not vertical (normal z " + fmt(plane.normal.z()) + "), skipped");
        continue;
      }
      const Vec2 nrm = n2.normalized();
      const Vec2 u(-nrm.y(), nrm.x());
      const std::vector<int> js = plane_junctions(p);
      if (js.size() < 2) {
        result.notes.push_back("planes[" + std::to_string(p) + "] (ID " + std::to_string(plane.id) +
                               "): wall plane has fewer than 2 junctions, skipped");
        continue;
      }
      double t0 = std::numeric_limits<double>::infinity(), t1 = -t0, s_sum = 0.0;
      for (int j : js) {
        const Vec2 q = junctions[static_cast<std::size_t>(j)].head<2>();
        t0 = std::min(t0, q.dot(u));
        t1 = std::max(t1, q.dot(u));
        s_sum += q.dot(nrm);
      }
      const double s = s_sum / static_cast<double>(js.size());
      Face f;
      f.wall_id = "plane" + std::to_string(plane.id);
      f.u = u;
      f.n = nrm;
      f.t0 = t0;
      f.t1 = t1;
      f.a = t0 * u + s * nrm;
      f.b = t1 * u + s * nrm;
      faces.push_back(f);
      Wall w;
      w.id = f.wall_id;
      w.a_m = f.a;
      w.b_m = f.b;
      w.thickness_m = thickness;
      plan.walls.push_back(std::move(w));
    }
  }

  // Doors and windows.
  constexpr double kParallelCos = 0.996;  // 5 degrees
  for (std::size_t si = 0; si < semantics.size(); ++si) {
    const Semantic& sem = semantics[si];
    const bool is_door = sem.type == "door";
    if (!is_door && sem.type != "window") continue;
    (is_door ? doors_read : windows_read) += 1;
    const std::string name = "semantics[" + std::to_string(si) + "] (" + sem.type + ", ID " + std::to_string(sem.id) + ")";
    std::set<int> js;
    for (int p : sem.planes) {
      for (int j : plane_junctions(p)) js.insert(j);
    }
    std::vector<Eigen::Vector3d> pts;
    for (int j : js) pts.push_back(junctions[static_cast<std::size_t>(j)]);
    if (pts.size() < 2) {
      result.notes.push_back(name + ": fewer than 2 junctions, skipped");
      continue;
    }
    Vec2 mean = Vec2::Zero();
    double zmin = std::numeric_limits<double>::infinity(), zmax = -zmin;
    for (const auto& q : pts) {
      mean += q.head<2>();
      zmin = std::min(zmin, q.z());
      zmax = std::max(zmax, q.z());
    }
    mean /= static_cast<double>(pts.size());
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& q : pts) {
      const Vec2 d = q.head<2>() - mean;
      cov += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
    const Vec2 e = eig.eigenvectors().col(1).normalized();  // largest eigenvalue
    double a0 = std::numeric_limits<double>::infinity(), a1 = -a0, c0 = a0, c1 = -a0;
    const Vec2 en(-e.y(), e.x());
    for (const auto& q : pts) {
      const Vec2 d = q.head<2>() - mean;
      a0 = std::min(a0, d.dot(e));
      a1 = std::max(a1, d.dot(e));
      c0 = std::min(c0, d.dot(en));
      c1 = std::max(c1, d.dot(en));
    }
    const double width = a1 - a0;
    const Vec2 center = mean + 0.5 * (a0 + a1) * e + 0.5 * (c0 + c1) * en;
    const double depth = c1 - c0;
    if (width < 0.05) {
      result.notes.push_back(name + ": opening narrower than 5 cm (" + fmt(width) + " m), skipped");
      continue;
    }
    // The surfaces the opening passes through: faces it touches, each with the opposite surface
    // of the same wall (the nearest face behind it with an opposite normal, within
    // kMaxWallThicknessM); with no touching face, the nearest face on each side.
    constexpr double kMaxWallThicknessM = 0.35;
    auto candidate = [&](const Face& f, double& signed_across) {
      if (std::abs(f.u.dot(e)) < kParallelCos) return false;
      const Vec2 r = center - f.a;
      const double along = r.dot(f.u);
      if (along < 0.0 || along > (f.b - f.a).norm()) return false;
      signed_across = r.dot(f.n);  // > 0: the opening centre is on the room side of f
      return true;
    };
    std::vector<std::size_t> chosen;
    auto choose = [&](std::size_t k) {
      if (std::find(chosen.begin(), chosen.end(), k) == chosen.end()) chosen.push_back(k);
    };
    for (std::size_t k = 0; k < faces.size(); ++k) {
      double sa = 0.0;
      if (!candidate(faces[k], sa) || std::abs(sa) > 0.5 * depth + 0.05) continue;
      choose(k);
      // Partner surface: behind faces[k] (against its normal), facing the other way.
      double best = std::numeric_limits<double>::infinity();
      std::size_t partner = faces.size();
      for (std::size_t g = 0; g < faces.size(); ++g) {
        double sg = 0.0;
        if (g == k || faces[g].n.dot(faces[k].n) > -0.99 || !candidate(faces[g], sg)) continue;
        const double behind = (faces[k].a - faces[g].a).dot(faces[k].n);  // distance of g behind k
        if (behind >= 0.0 && behind <= kMaxWallThicknessM && behind < best) {
          best = behind;
          partner = g;
        }
      }
      if (partner < faces.size()) choose(partner);
    }
    if (chosen.empty()) {
      for (int side : {-1, 1}) {
        double best = std::numeric_limits<double>::infinity();
        std::size_t pick = faces.size();
        for (std::size_t k = 0; k < faces.size(); ++k) {
          double sa = 0.0;
          if (!candidate(faces[k], sa)) continue;
          const Vec2 r = center - faces[k].a;
          const double side_offset = r.dot(en);  // which side of the opening's line
          if ((side_offset >= 0.0 ? 1 : -1) != side) continue;
          if (std::abs(sa) <= 0.5 * depth + kMaxWallThicknessM && std::abs(sa) < best) {
            best = std::abs(sa);
            pick = k;
          }
        }
        if (pick < faces.size()) choose(pick);
      }
    }
    std::sort(chosen.begin(), chosen.end());
    int placed = 0;
    for (std::size_t k : chosen) {
      const Face& f = faces[k];
      const double along = (center - f.a).dot(f.u);
      const Vec2 c_on = f.a + along * f.u;
      const std::string id = std::string(is_door ? "door" : "window") + std::to_string(sem.id) +
                             (placed == 0 ? std::string() : "-" + std::to_string(placed + 1));
      if (is_door) {
        Door d;
        d.id = id;
        d.wall_id = f.wall_id;
        d.center_m = c_on;
        d.width_m = width;
        d.closed = options.doors_closed;
        plan.doors.push_back(std::move(d));
      } else {
        Window w;
        w.id = id;
        w.wall_id = f.wall_id;
        w.center_m = c_on;
        w.width_m = width;
        double sill = zmin - floor_z, head = zmax - floor_z;
        if (sill < 0.0 && sill > -0.05) sill = 0.0;  // junction noise just below the floor
        w.sill_m = sill;
        w.head_m = head;
        plan.windows.push_back(std::move(w));
      }
      ++placed;
    }
    if (placed == 0) result.notes.push_back(name + ": lies in no imported wall, skipped");
  }

  result.source_counts = {{"junctions", static_cast<int>(junctions.size())},
                          {"planes", static_cast<int>(planes.size())},
                          {"rooms", rooms},
                          {"wall_planes", static_cast<int>(faces.size())},
                          {"door_semantics", doors_read},
                          {"window_semantics", windows_read}};
  const import_detail::UnitCheck check{unit_m, "mm", "--units"};
  return import_detail::finish_import(std::move(plan), source, import_detail::stem_of(source), options, std::move(result),
                                      options.units || options.scale ? nullptr : &check);
}

}  // namespace floorcast
