// Ray casting against a labelled mesh with Embree 3 (robust, watertight intersection). Embree
// headers stay inside ray_scene.cpp.
//
// Rays are o + t d with d not necessarily unit length: t is measured in units of |d| (the scan
// renderer uses camera rays with unit z component, so t is z-depth directly).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <memory>
#include <vector>

#include "floorcast/sim/mesh.hpp"

namespace floorcast {

struct Ray3 {
  Eigen::Vector3f origin_m = Eigen::Vector3f::Zero();
  Eigen::Vector3f direction = Eigen::Vector3f::UnitX();
  float t_near = 0.0f;
  float t_far = std::numeric_limits<float>::infinity();
};

struct RayHit3 {
  float t = std::numeric_limits<float>::infinity();  ///< infinity: no hit within [t_near, t_far]
  int triangle = -1;                                  ///< index into the mesh's triangles
  bool hit() const { return triangle >= 0; }
};

/// A ray and its hit in the memory layout of Embree's RTCRayHit (checked field by field with
/// static_asserts in ray_scene.cpp), so a renderer can build a stream in place and read the
/// hits back without copying. Fill with set(); after intersection tfar is the hit distance.
struct alignas(16) StreamRayHit {
  static constexpr unsigned kInvalid = 0xFFFFFFFFu;
  float org_x, org_y, org_z, tnear;
  float dir_x, dir_y, dir_z, time;
  float tfar;
  unsigned mask, id, flags;
  float Ng_x, Ng_y, Ng_z, u, v;
  unsigned primID, geomID, instID;

  void set(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near, float t_far) {
    org_x = origin.x();
    org_y = origin.y();
    org_z = origin.z();
    tnear = t_near;
    dir_x = direction.x();
    dir_y = direction.y();
    dir_z = direction.z();
    time = 0.0f;
    tfar = t_far;
    mask = 0xFFFFFFFFu;
    id = 0;
    flags = 0;
    primID = geomID = instID = kInvalid;
  }
  bool hit() const { return geomID != kInvalid; }
  int triangle() const { return hit() ? static_cast<int>(primID) : -1; }
  Eigen::Vector3f origin() const { return {org_x, org_y, org_z}; }
  Eigen::Vector3f direction() const { return {dir_x, dir_y, dir_z}; }
};

/// Rays prepared once in Embree's own layout, for measuring raw stream throughput.
class PreparedRays {
 public:
  PreparedRays();
  ~PreparedRays();
  PreparedRays(PreparedRays&&) noexcept;
  PreparedRays& operator=(PreparedRays&&) noexcept;
  std::size_t size() const;

 private:
  friend class RayScene;
  struct Data;
  std::unique_ptr<Data> data_;
};

class RayScene {
 public:
  /// Builds the acceleration structure (copies the mesh). Throws InputError on an empty mesh or
  /// if Embree fails.
  explicit RayScene(Mesh mesh);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  const Mesh& mesh() const { return mesh_; }
  /// Unit outward normal of each triangle (precomputed).
  const std::vector<Eigen::Vector3f>& normals() const { return normals_; }

  /// Slab thickness of a mesh part (Mesh::part_ids, e.g. a glass pane): the smallest distance
  /// between two of its faces with opposite normals; 0 for unknown parts.
  float part_thickness(int part) const {
    return part >= 0 && static_cast<std::size_t>(part) < part_thickness_.size()
               ? part_thickness_[static_cast<std::size_t>(part)]
               : 0.0f;
  }

  /// Closest hit of one ray.
  RayHit3 intersect(const Ray3& ray) const;

  /// Closest hits of n rays through Embree's stream interface (rtcIntersect1M) in chunks;
  /// `coherent` tells Embree the rays are camera-coherent. Safe to call from many threads.
  void intersect_stream(const Ray3* rays, RayHit3* hits, std::size_t n, bool coherent = true) const;

  /// Same, in place on rays already in Embree's layout (no copies).
  void intersect_stream(StreamRayHit* rays, std::size_t n, bool coherent = true) const;

  /// Converts rays into Embree's layout (done outside any timing).
  PreparedRays prepare(const std::vector<Ray3>& rays) const;
  /// Intersects prepared rays with rtcIntersect1M in chunks of `chunk` rays, in parallel (TBB);
  /// nothing else. Returns the number of hits (so the work cannot be optimised away).
  std::size_t intersect_prepared(PreparedRays& rays, std::size_t chunk = 256) const;

 private:
  struct Impl;
  Mesh mesh_;
  std::vector<Eigen::Vector3f> normals_;
  std::vector<float> part_thickness_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace floorcast
