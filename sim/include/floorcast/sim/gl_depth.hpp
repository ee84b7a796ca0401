// Headless OpenGL depth rasteriser of a labelled mesh (OSMesa, llvmpipe): an implementation
// independent of Embree, used to cross-check the ray-cast depth, and the start of an RGB renderer.
// OSMesa headers stay inside gl_depth.cpp.
//
// Conventions as in scan.hpp: OpenCV camera (x right, y down, z forward), pixel (u, v) centred at
// integer coordinates, output CV_32F z-depth in metres, 0 where nothing is drawn. The rasteriser
// samples pixel centres like the ray caster, so both agree away from silhouette edges.
//
// One GlDepthRenderer owns one OSMesa context: use it from one thread at a time (it makes its
// context current on every call).
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <opencv2/core.hpp>

#include "floorcast/sim/mesh.hpp"
#include "floorcast/core/scan.hpp"

namespace floorcast {

class GlDepthRenderer {
 public:
  /// Uploads the mesh and creates a width x height offscreen target. Throws InputError if OSMesa
  /// cannot create a GL 3.3 core context or the framebuffer is incomplete.
  GlDepthRenderer(const Mesh& mesh, int width_px, int height_px);
  ~GlDepthRenderer();
  GlDepthRenderer(const GlDepthRenderer&) = delete;
  GlDepthRenderer& operator=(const GlDepthRenderer&) = delete;

  /// z-depth image of the mesh seen from camera pose T_world_camera with intrinsics K (whose size
  /// must match the renderer's), clipped to [near_m, far_m] along the optical axis.
  cv::Mat render_depth(const Eigen::Isometry3d& T_world_camera, const CameraIntrinsics& K, double near_m = 0.05,
                       double far_m = 100.0);

  /// The GL_RENDERER string (e.g. "llvmpipe (LLVM 15.0.6, 256 bits)").
  std::string renderer_name() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace floorcast
