#include "floorcast/sim/ray_scene.hpp"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <string>

#include "floorcast/core/types.hpp"

namespace floorcast {

struct RayScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

struct PreparedRays::Data {
  std::vector<RTCRayHit> pristine;
  std::vector<RTCRayHit> work;
};
PreparedRays::PreparedRays() : data_(std::make_unique<Data>()) {}
PreparedRays::~PreparedRays() = default;
PreparedRays::PreparedRays(PreparedRays&&) noexcept = default;
PreparedRays& PreparedRays::operator=(PreparedRays&&) noexcept = default;
std::size_t PreparedRays::size() const { return data_ ? data_->pristine.size() : 0; }

namespace {

// StreamRayHit mirrors RTCRayHit exactly.
static_assert(sizeof(StreamRayHit) == sizeof(RTCRayHit), "StreamRayHit size");
static_assert(alignof(StreamRayHit) == alignof(RTCRayHit), "StreamRayHit alignment");
static_assert(RTC_MAX_INSTANCE_LEVEL_COUNT == 1, "StreamRayHit has one instance id");
#define FLOORCAST_SAME_OFFSET(a, b) \
  static_assert(offsetof(StreamRayHit, a) == offsetof(RTCRayHit, b), "StreamRayHit::" #a " offset")
FLOORCAST_SAME_OFFSET(org_x, ray.org_x);
FLOORCAST_SAME_OFFSET(org_y, ray.org_y);
FLOORCAST_SAME_OFFSET(org_z, ray.org_z);
FLOORCAST_SAME_OFFSET(tnear, ray.tnear);
FLOORCAST_SAME_OFFSET(dir_x, ray.dir_x);
FLOORCAST_SAME_OFFSET(dir_y, ray.dir_y);
FLOORCAST_SAME_OFFSET(dir_z, ray.dir_z);
FLOORCAST_SAME_OFFSET(time, ray.time);
FLOORCAST_SAME_OFFSET(tfar, ray.tfar);
FLOORCAST_SAME_OFFSET(mask, ray.mask);
FLOORCAST_SAME_OFFSET(id, ray.id);
FLOORCAST_SAME_OFFSET(flags, ray.flags);
FLOORCAST_SAME_OFFSET(Ng_x, hit.Ng_x);
FLOORCAST_SAME_OFFSET(Ng_y, hit.Ng_y);
FLOORCAST_SAME_OFFSET(Ng_z, hit.Ng_z);
FLOORCAST_SAME_OFFSET(u, hit.u);
FLOORCAST_SAME_OFFSET(v, hit.v);
FLOORCAST_SAME_OFFSET(primID, hit.primID);
FLOORCAST_SAME_OFFSET(geomID, hit.geomID);
FLOORCAST_SAME_OFFSET(instID, hit.instID);
#undef FLOORCAST_SAME_OFFSET
static_assert(StreamRayHit::kInvalid == RTC_INVALID_GEOMETRY_ID, "invalid id");

void embree_error(void*, RTCError code, const char* message) {
  // Errors are checked with rtcGetDeviceError after each call sequence; nothing to do here.
  (void)code;
  (void)message;
}

inline void fill(RTCRayHit& rh, const Ray3& r) {
  rh.ray.org_x = r.origin_m.x();
  rh.ray.org_y = r.origin_m.y();
  rh.ray.org_z = r.origin_m.z();
  rh.ray.tnear = r.t_near;
  rh.ray.dir_x = r.direction.x();
  rh.ray.dir_y = r.direction.y();
  rh.ray.dir_z = r.direction.z();
  rh.ray.time = 0.0f;
  rh.ray.tfar = r.t_far;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

inline RayHit3 result(const RTCRayHit& rh) {
  RayHit3 h;
  if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
    h.t = rh.ray.tfar;
    h.triangle = static_cast<int>(rh.hit.primID);
  }
  return h;
}

}  // namespace

RayScene::RayScene(Mesh mesh) : mesh_(std::move(mesh)), impl_(std::make_unique<Impl>()) {
  if (mesh_.triangles.empty()) throw InputError("ray scene: the mesh has no triangles");
  normals_.reserve(mesh_.triangles.size());
  for (std::size_t i = 0; i < mesh_.triangles.size(); ++i) normals_.push_back(mesh_.normal(i));
  {
    std::vector<std::vector<std::size_t>> by_part;
    for (std::size_t i = 0; i < mesh_.part_ids.size() && i < mesh_.triangles.size(); ++i) {
      const int p = mesh_.part_ids[i];
      if (p < 0) continue;
      if (static_cast<std::size_t>(p) >= by_part.size()) by_part.resize(static_cast<std::size_t>(p) + 1);
      by_part[static_cast<std::size_t>(p)].push_back(i);
    }
    part_thickness_.assign(by_part.size(), 0.0f);
    for (std::size_t p = 0; p < by_part.size(); ++p) {
      float best = std::numeric_limits<float>::infinity();
      for (std::size_t a : by_part[p]) {
        for (std::size_t b : by_part[p]) {
          if (normals_[a].dot(normals_[b]) > -0.999f) continue;
          const Eigen::Vector3f& va = mesh_.vertices_m[static_cast<std::size_t>(mesh_.triangles[a][0])];
          const Eigen::Vector3f& vb = mesh_.vertices_m[static_cast<std::size_t>(mesh_.triangles[b][0])];
          const float dist = std::abs(normals_[a].dot(vb - va));
          if (dist > 1e-6f) best = std::min(best, dist);
        }
      }
      part_thickness_[p] = std::isfinite(best) ? best : 0.0f;
    }
  }

  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) throw InputError("ray scene: Embree device creation failed");
  rtcSetDeviceErrorFunction(impl_->device, embree_error, nullptr);
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_MEDIUM);

  RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), mesh_.vertices_m.size()));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                            3 * sizeof(unsigned), mesh_.triangles.size()));
  if (!vb || !ib) {
    rtcReleaseGeometry(geom);
    throw InputError("ray scene: Embree buffer allocation failed");
  }
  for (std::size_t i = 0; i < mesh_.vertices_m.size(); ++i) {
    vb[3 * i + 0] = mesh_.vertices_m[i].x();
    vb[3 * i + 1] = mesh_.vertices_m[i].y();
    vb[3 * i + 2] = mesh_.vertices_m[i].z();
  }
  for (std::size_t i = 0; i < mesh_.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh_.triangles[i][k];
      if (v < 0 || static_cast<std::size_t>(v) >= mesh_.vertices_m.size()) {
        rtcReleaseGeometry(geom);
        throw InputError("ray scene: triangle " + std::to_string(i) + " has an out-of-range vertex index");
      }
      ib[3 * i + k] = static_cast<unsigned>(v);
    }
  }
  rtcCommitGeometry(geom);
  rtcAttachGeometry(impl_->scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(impl_->scene);
  const RTCError err = rtcGetDeviceError(impl_->device);
  if (err != RTC_ERROR_NONE) {
    throw InputError("ray scene: Embree failed to build the scene (error " + std::to_string(err) + ")");
  }
}

RayScene::~RayScene() = default;

RayHit3 RayScene::intersect(const Ray3& ray) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  fill(rh, ray);
  rtcIntersect1(impl_->scene, &ctx, &rh);
  return result(rh);
}

void RayScene::intersect_stream(const Ray3* rays, RayHit3* hits, std::size_t n, bool coherent) const {
  constexpr std::size_t kChunk = 256;
  RTCRayHit buffer[kChunk];
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  for (std::size_t begin = 0; begin < n; begin += kChunk) {
    const std::size_t m = std::min(kChunk, n - begin);
    for (std::size_t i = 0; i < m; ++i) fill(buffer[i], rays[begin + i]);
    rtcIntersect1M(impl_->scene, &ctx, buffer, static_cast<unsigned>(m), sizeof(RTCRayHit));
    for (std::size_t i = 0; i < m; ++i) hits[begin + i] = result(buffer[i]);
  }
}

void RayScene::intersect_stream(StreamRayHit* rays, std::size_t n, bool coherent) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  rtcIntersect1M(impl_->scene, &ctx, reinterpret_cast<RTCRayHit*>(rays), static_cast<unsigned>(n),
                 sizeof(StreamRayHit));
}

PreparedRays RayScene::prepare(const std::vector<Ray3>& rays) const {
  PreparedRays p;
  p.data_->pristine.resize(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) fill(p.data_->pristine[i], rays[i]);
  p.data_->work = p.data_->pristine;
  return p;
}

std::size_t RayScene::intersect_prepared(PreparedRays& prepared, std::size_t chunk) const {
  PreparedRays::Data& rays = *prepared.data_;
  chunk = std::max<std::size_t>(1, chunk);
  const std::size_t n = rays.pristine.size();
  const std::size_t chunks = (n + chunk - 1) / chunk;
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, chunks), std::size_t{0},
      [&](const tbb::blocked_range<std::size_t>& r, std::size_t acc) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        for (std::size_t c = r.begin(); c != r.end(); ++c) {
          const std::size_t begin = c * chunk;
          const std::size_t m = std::min(chunk, n - begin);
          RTCRayHit* w = rays.work.data() + begin;
          std::memcpy(static_cast<void*>(w), rays.pristine.data() + begin, m * sizeof(RTCRayHit));
          rtcIntersect1M(impl_->scene, &ctx, w, static_cast<unsigned>(m), sizeof(RTCRayHit));
          for (std::size_t i = 0; i < m; ++i) acc += (w[i].hit.geomID != RTC_INVALID_GEOMETRY_ID);
        }
        return acc;
      },
      [](std::size_t a, std::size_t b) { return a + b; });
}

}  // namespace floorcast
