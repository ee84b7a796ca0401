// Headless OpenGL rendering of a labelled mesh (OSMesa, llvmpipe; no display): colour views with
// lit, procedurally textured surfaces for depth networks to look at, plus the z-depth and label of
// the first surface of every pixel. The OpenGL code is a separate module (floorcast_gl.so, see
// core/module.hpp) loaded on first use, so a process that never renders never maps OSMesa/LLVM.
//
// Conventions as in core/scan.hpp: OpenCV camera (x right, y down, z forward), pixel (u, v)
// centred at integer coordinates; depth is CV_32F z-depth in metres, 0 where nothing is drawn. The
// rasteriser samples pixel centres like the Embree ray caster, so both depths agree away from
// silhouette edges (an independent cross-check of the ray caster).
//
// Appearance (sim/README.md): plaster walls in soft tints with a skirting board, wooden plank
// floor, tiled ceiling, wooden door leaves with a dark frame and a handle, darker trims on the
// jambs, soffits and sills of openings, furniture in a few colours (one per item), glass tinted
// and blended over what lies behind it. Lighting: ambient + sky direction + head-light, mild
// distance fall-off. Deterministic: the same mesh and view give the same bytes.
//
// One GlRenderer owns one OpenGL context: use it from one thread at a time.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "floorcast/core/scan.hpp"
#include "floorcast/sim/mesh.hpp"
#include "floorcast/sim/simulated_scan.hpp"

namespace floorcast {

/// One rendered view.
struct GlFrame {
  cv::Mat bgr;      ///< CV_8UC3 colour (empty when not requested)
  cv::Mat depth_m;  ///< CV_32F z-depth of the first surface (glass included), 0 = none
  cv::Mat label;    ///< CV_8U MeshLabel of the first surface (glass included), 255 = none
};

class GlRenderer {
 public:
  /// Loads the OpenGL module (first use in the process), uploads the mesh and creates a width x
  /// height offscreen target. Throws InputError when the module cannot be loaded or OSMesa cannot
  /// create a GL 3.3 core context.
  GlRenderer(const Mesh& mesh, int width_px, int height_px);
  ~GlRenderer();
  GlRenderer(const GlRenderer&) = delete;
  GlRenderer& operator=(const GlRenderer&) = delete;

  /// Colour, depth and labels seen from T_world_camera with intrinsics K (whose size must match
  /// the renderer's), clipped to [near_m, far_m] along the optical axis.
  GlFrame render(const Eigen::Isometry3d& T_world_camera, const CameraIntrinsics& K, double near_m = 0.05,
                 double far_m = 100.0);

  /// Depth only (no colour pass): CV_32F z-depth, 0 = none.
  cv::Mat render_depth(const Eigen::Isometry3d& T_world_camera, const CameraIntrinsics& K, double near_m = 0.05,
                       double far_m = 100.0);

  /// The GL_RENDERER string (e.g. "llvmpipe (LLVM 15.0.6, 256 bits)").
  std::string renderer_name() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Renders every view of a simulated scan in colour into scan.scan.views[k].rgb, from the view's
/// true camera pose (what the camera saw; tracker noise stays in the reported poses). The
/// renderer's size must match the views'. Returns the time spent rendering, seconds.
double render_scan_colour(GlRenderer& renderer, SimulatedScan& scan);

/// True when the OpenGL module can be loaded in this process (loads it); `why` gets the reason
/// when not.
bool gl_renderer_available(std::string* why = nullptr);

/// Where the OpenGL module was found ("" before it is first loaded or when absent).
std::string gl_module_path();

}  // namespace floorcast
