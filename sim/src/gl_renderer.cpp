#include "floorcast/sim/gl_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>
#include <vector>

#include "floorcast/core/module.hpp"
#include "floorcast/core/types.hpp"
#include "floorcast/core/union_find.hpp"
#include "floorcast/sim/scan_sim.hpp"
#include "gl_backend_api.hpp"

namespace floorcast {
namespace {

using gl_api::Vertex;

/// Union-find over clutter triangles sharing a vertex position (1 mm grid): one id per item.
std::vector<int> clutter_instances(const Mesh& mesh) {
  const std::size_t n = mesh.triangles.size();
  UnionFind sets(n);
  std::map<std::tuple<long, long, long>, int> first_at;
  for (std::size_t t = 0; t < n; ++t) {
    if (mesh.labels[t] != MeshLabel::kClutter) continue;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3f& v = mesh.vertices_m[static_cast<std::size_t>(mesh.triangles[t][k])];
      const auto key = std::make_tuple(std::lround(v.x() * 1000.0f), std::lround(v.y() * 1000.0f), std::lround(v.z() * 1000.0f));
      auto [it, inserted] = first_at.emplace(key, static_cast<int>(t));
      if (!inserted) {
        sets.unite(static_cast<int>(t), it->second);
      }
    }
  }
  std::vector<int> id(n, 0);
  std::map<int, int> number;
  for (std::size_t t = 0; t < n; ++t) {
    if (mesh.labels[t] != MeshLabel::kClutter) continue;
    const int root = sets.find(static_cast<int>(t));
    id[t] = number.emplace(root, static_cast<int>(number.size()) + 1).first->second;
  }
  return id;
}

/// The triangle soup the module draws: glass last, per-vertex face coordinates, materials.
std::vector<Vertex> scene_vertices(const Mesh& mesh, std::size_t& glass_first) {
  float top_m = 0.0f;
  for (const Eigen::Vector3f& v : mesh.vertices_m) top_m = std::max(top_m, v.z());
  const std::vector<int> instance = clutter_instances(mesh);
  std::vector<Vertex> opaque, glass;
  opaque.reserve(mesh.triangles.size() * 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    Eigen::Vector3f p[3];
    for (int k = 0; k < 3; ++k) p[k] = mesh.vertices_m[static_cast<std::size_t>(mesh.triangles[t][k])];
    Eigen::Vector3f n = (p[1] - p[0]).cross(p[2] - p[0]);
    if (n.norm() <= 0.0f) continue;  // degenerate: nothing to draw
    n.normalize();
    const bool vertical = std::abs(n.z()) < 0.5f;
    // Face coordinates: vertical faces (along the face, height), others (x, y).
    Eigen::Vector2f along(1.0f, 0.0f);
    if (vertical) along = Eigen::Vector2f(-n.y(), n.x()).normalized();
    float uv[3][2];
    float box[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
    float zmin = INFINITY, zmax = -INFINITY;
    for (int k = 0; k < 3; ++k) {
      uv[k][0] = vertical ? along.dot(p[k].head<2>()) : p[k].x();
      uv[k][1] = vertical ? p[k].z() : p[k].y();
      box[0] = std::min(box[0], uv[k][0]);
      box[1] = std::max(box[1], uv[k][0]);
      box[2] = std::min(box[2], uv[k][1]);
      box[3] = std::max(box[3], uv[k][1]);
      zmin = std::min(zmin, p[k].z());
      zmax = std::max(zmax, p[k].z());
    }
    const MeshLabel label = mesh.labels[t];
    int material = static_cast<int>(label);
    if (label == MeshLabel::kWall) {
      // Trims of openings: narrow vertical faces that stop below the ceiling (jambs of doors and
      // windows), and horizontal wall faces between floor and ceiling (soffits, sills).
      const bool below_ceiling = zmax < top_m - 0.05f;
      if (vertical && below_ceiling && box[1] - box[0] <= 0.35f) material = gl_api::kMaterialFrame;
      if (!vertical && below_ceiling && zmin > 0.05f) material = gl_api::kMaterialFrame;
    }
    std::vector<Vertex>& dst = label == MeshLabel::kGlass ? glass : opaque;
    for (int k = 0; k < 3; ++k) {
      Vertex v{};
      for (int i = 0; i < 3; ++i) {
        v.position_world_m[i] = p[k][i];
        v.normal_world[i] = n[i];
      }
      v.face_uv_m[0] = uv[k][0];
      v.face_uv_m[1] = uv[k][1];
      std::copy(box, box + 4, v.face_box_m);
      v.material = static_cast<float>(material);
      v.label = static_cast<float>(static_cast<int>(label));
      v.instance = static_cast<float>(instance[t]);
      dst.push_back(v);
    }
  }
  glass_first = opaque.size();
  opaque.insert(opaque.end(), glass.begin(), glass.end());
  return opaque;
}

gl_api::CreateFn create_function() {
  void* handle = load_module(gl_api::kModuleName);
  return reinterpret_cast<gl_api::CreateFn>(module_symbol(handle, gl_api::kModuleName, gl_api::kCreateSymbol));
}

}  // namespace

struct GlRenderer::Impl {
  std::unique_ptr<gl_api::Backend> backend;
  int width = 0, height = 0;
};

GlRenderer::GlRenderer(const Mesh& mesh, int width_px, int height_px) : impl_(std::make_unique<Impl>()) {
  if (width_px < 1 || height_px < 1 || width_px > 8192 || height_px > 8192) {
    throw InputError("OpenGL renderer: image size must be in [1, 8192]");
  }
  const gl_api::CreateFn create = create_function();
  std::size_t glass_first = 0;
  const std::vector<Vertex> vertices = scene_vertices(mesh, glass_first);
  gl_api::SceneData scene;
  scene.vertices = vertices.data();
  scene.vertex_count = vertices.size();
  scene.glass_first = glass_first;
  char error[1024] = {0};
  gl_api::Backend* b = create(gl_api::kApiVersion, &scene, width_px, height_px, error, sizeof(error));
  if (!b) throw InputError(std::string("OpenGL renderer: ") + error);
  impl_->backend.reset(b);
  impl_->width = width_px;
  impl_->height = height_px;
}

GlRenderer::~GlRenderer() = default;

std::string GlRenderer::renderer_name() const {
  try {
    return impl_->backend->renderer_name();
  } catch (const std::exception& e) {
    throw InputError(e.what());
  }
}

namespace {

gl_api::ViewRequest view_request(const Eigen::Isometry3d& T_world_camera, const CameraIntrinsics& K, double near_m,
                                 double far_m, int width, int height, bool colour) {
  if (K.width_px != width || K.height_px != height) {
    throw InputError("OpenGL renderer: intrinsics size " + std::to_string(K.width_px) + "x" +
                     std::to_string(K.height_px) + " differs from the renderer's " + std::to_string(width) + "x" +
                     std::to_string(height));
  }
  if (!(near_m > 0.0) || !(far_m > near_m)) throw InputError("OpenGL renderer: need 0 < near < far");
  if (!(K.fx_px > 0.0) || !(K.fy_px > 0.0)) throw InputError("OpenGL renderer: focal lengths must be positive");
  gl_api::ViewRequest v{};
  const Eigen::Matrix4d camera_from_world = T_world_camera.inverse().matrix();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) v.camera_from_world[r + 4 * c] = camera_from_world(r, c);
  for (int i = 0; i < 3; ++i) v.camera_position_world_m[i] = T_world_camera.translation()[i];
  v.fx_px = K.fx_px;
  v.fy_px = K.fy_px;
  v.cx_px = K.cx_px;
  v.cy_px = K.cy_px;
  v.near_m = near_m;
  v.far_m = far_m;
  v.colour = colour;
  return v;
}

}  // namespace

GlFrame GlRenderer::render(const Eigen::Isometry3d& T_world_camera, const CameraIntrinsics& K, double near_m,
                           double far_m) {
  const gl_api::ViewRequest v = view_request(T_world_camera, K, near_m, far_m, impl_->width, impl_->height, true);
  GlFrame f;
  f.bgr.create(impl_->height, impl_->width, CV_8UC3);
  f.depth_m.create(impl_->height, impl_->width, CV_32F);
  f.label.create(impl_->height, impl_->width, CV_8U);
  gl_api::ViewOutput out;
  out.bgr = f.bgr.ptr<std::uint8_t>();
  out.depth_z_m = f.depth_m.ptr<float>();
  out.label_plus_one = f.label.ptr<std::uint8_t>();
  try {
    impl_->backend->render(v, out);
  } catch (const std::exception& e) {
    throw InputError(e.what());
  }
  for (int r = 0; r < f.label.rows; ++r) {  // label + 1 (0 = none) -> label (255 = none)
    std::uint8_t* l = f.label.ptr<std::uint8_t>(r);
    for (int c = 0; c < f.label.cols; ++c) l[c] = l[c] == 0 ? 255 : static_cast<std::uint8_t>(l[c] - 1);
  }
  return f;
}

cv::Mat GlRenderer::render_depth(const Eigen::Isometry3d& T_world_camera, const CameraIntrinsics& K, double near_m,
                                 double far_m) {
  const gl_api::ViewRequest v = view_request(T_world_camera, K, near_m, far_m, impl_->width, impl_->height, false);
  cv::Mat depth(impl_->height, impl_->width, CV_32F);
  gl_api::ViewOutput out;
  out.depth_z_m = depth.ptr<float>();
  try {
    impl_->backend->render(v, out);
  } catch (const std::exception& e) {
    throw InputError(e.what());
  }
  return depth;
}

double render_scan_colour(GlRenderer& renderer, SimulatedScan& scan) {
  const auto t0 = std::chrono::steady_clock::now();
  const Eigen::Isometry3d T_world_scan = scan_frame_in_world(scan.truth.T_world_scan, scan.truth.camera_height_m);
  if (scan.truth.T_scan_camera_true.size() != scan.scan.views.size()) {
    throw InputError("render_scan_colour: the scan's truth has " + std::to_string(scan.truth.T_scan_camera_true.size()) +
                     " true view poses for " + std::to_string(scan.scan.views.size()) + " views");
  }
  const double near_m = std::max(1e-3, 0.5 * scan.params.sensor.min_range_m);
  for (std::size_t k = 0; k < scan.scan.views.size(); ++k) {
    DepthView& v = scan.scan.views[k];
    v.rgb = renderer.render(T_world_scan * scan.truth.T_scan_camera_true[k], v.intrinsics, near_m, 1000.0).bgr;
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

bool gl_renderer_available(std::string* why) {
  try {
    (void)create_function();
    return true;
  } catch (const std::exception& e) {
    if (why) *why = e.what();
    return false;
  }
}

std::string gl_module_path() { return module_path(gl_api::kModuleName); }

}  // namespace floorcast
