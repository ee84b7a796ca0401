// The interface between the sim library (floorcast/sim/gl_renderer.hpp) and the OpenGL back-end
// module floorcast_gl.so (sim/gl/osmesa_backend.cpp), which is loaded with dlopen on first use so
// that processes which never render never map OSMesa and LLVM. Private to floorcast: both sides
// are built from the same tree, so plain C++ types cross the boundary; kApiVersion guards against a
// stale module. Errors inside the module are thrown as std::runtime_error.
#pragma once

#include <cstddef>
#include <cstdint>

namespace floorcast::gl_api {

constexpr int kApiVersion = 1;

/// Surface materials of the colour renderer (MeshLabel 0..5 plus the trims of openings).
enum Material : int {
  kMaterialWall = 0,
  kMaterialDoor = 1,
  kMaterialGlass = 2,
  kMaterialClutter = 3,
  kMaterialFloor = 4,
  kMaterialCeiling = 5,
  kMaterialFrame = 6,  ///< jambs, soffits and sills of door and window openings
};

/// One vertex of the unindexed triangle soup (three per triangle; per-triangle values repeated).
struct Vertex {
  float position_world_m[3];
  float normal_world[3];   ///< the triangle's outward unit normal
  float face_uv_m[2];      ///< coordinates in the face's plane (vertical: along the face, z)
  float face_box_m[4];     ///< the triangle's bounding box in face coordinates: u0, u1, v0, v1
  float material;          ///< Material
  float label;             ///< MeshLabel of the triangle (what the label image reports)
  float instance;          ///< clutter item index (furniture colours), 0 else
};

struct SceneData {
  const Vertex* vertices = nullptr;
  std::size_t vertex_count = 0;
  /// Glass triangles come last: vertices [glass_first, vertex_count).
  std::size_t glass_first = 0;
};

struct ViewRequest {
  double camera_from_world[16];  ///< column-major 4x4, OpenCV camera frame
  double camera_position_world_m[3];
  double fx_px, fy_px, cx_px, cy_px;
  double near_m, far_m;
  bool colour = true;  ///< false: depth and labels only
};

/// Output buffers, row 0 at the top, width x height each; any may be null (not read back).
struct ViewOutput {
  float* depth_z_m = nullptr;         ///< z-depth of the first surface (glass included), 0 = none
  std::uint8_t* bgr = nullptr;        ///< 3 bytes per pixel
  std::uint8_t* label_plus_one = nullptr;  ///< MeshLabel + 1 of the first surface, 0 = none
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual void render(const ViewRequest& view, const ViewOutput& out) = 0;
  virtual const char* renderer_name() = 0;
};

/// The module's one entry point (extern "C", symbol kCreateSymbol): a back-end drawing `scene`
/// into width x height images, or null with a message in `error` (error_size bytes).
using CreateFn = Backend* (*)(int api_version, const SceneData* scene, int width_px, int height_px, char* error,
                              std::size_t error_size);
constexpr const char* kCreateSymbol = "floorcast_gl_create_backend";
constexpr const char* kModuleName = "floorcast_gl";

}  // namespace floorcast::gl_api
