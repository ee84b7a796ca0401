#include "floorcast/scenarios/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "floorcast/core/format.hpp"
#include "floorcast/floorplans/raster.hpp"

namespace floorcast {

std::vector<Pose2> sample_observation_poses(const FloorPlan& plan, int n, std::uint64_t seed, int plan_index,
                                            double clearance_m, double resolution_m,
                                            const std::vector<Room>& rooms, const std::vector<std::string>& kinds) {
  RasterOptions ro;
  ro.resolution_m_per_px = resolution_m;
  const PlanRasters rasters = make_plan_rasters(plan, ro);
  const GridSpec& g = rasters.grid;
  // Nobody stands inside furniture: every obstacle footprint blocks, whatever its height (the
  // default rasters cut at 1.5 m, where beds, sofas and desks do not exist). The clearance is
  // kept from walls and obstacles alike.
  BlockingOptions standing = ro.blocking;
  standing.obstacles_block = true;
  standing.cut_height_m = 0.01;
  cv::Mat blocked = rasterize_occupancy(plan, g, standing);
  cv::max(blocked, rasters.occupancy, blocked);
  const cv::Mat distance_m = distance_to_blocked_m(blocked, g);
  // A blocked cell's centre may be up to half a diagonal farther than the surface in it, and the
  // point moves up to half a diagonal inside its cell: keep a full diagonal of slack.
  const float need = static_cast<float>(clearance_m + std::sqrt(2.0) * resolution_m);
  const std::vector<std::string> wanted = expand_room_kinds(kinds);
  std::vector<bool> room_wanted(rooms.size(), false);
  for (std::size_t k = 0; k < rooms.size(); ++k) {
    room_wanted[k] = std::find(wanted.begin(), wanted.end(), rooms[k].kind) != wanted.end();
  }
  const cv::Mat room_index = wanted.empty() ? cv::Mat() : room_index_raster(rooms, g);
  std::vector<std::pair<int, int>> cells;
  for (int r = 0; r < g.height_px; ++r) {
    const std::uint8_t* v = rasters.valid.ptr<std::uint8_t>(r);
    const float* d = distance_m.ptr<float>(r);
    for (int c = 0; c < g.width_px; ++c) {
      if (!v[c] || d[c] < need) continue;
      if (!wanted.empty()) {
        const int k = room_index.at<int>(r, c);
        if (k < 0 || !room_wanted[static_cast<std::size_t>(k)]) continue;
      }
      cells.emplace_back(r, c);
    }
  }
  if (cells.empty()) {
    throw InputError("plan \"" + plan.name + "\": no free cell with " + format_fixed(clearance_m, 2) + " m clearance" +
                     (wanted.empty() ? "" : " inside rooms of the sampled kinds") + " to sample observation points from");
  }
  std::vector<Pose2> poses;
  poses.reserve(static_cast<std::size_t>(std::max(n, 0)));
  for (int i = 0; i < n; ++i) {
    std::seed_seq seq{static_cast<std::uint32_t>(seed & 0xffffffffu), static_cast<std::uint32_t>(seed >> 32),
                      static_cast<std::uint32_t>(plan_index), static_cast<std::uint32_t>(i)};
    std::mt19937_64 rng(seq);
    std::uniform_int_distribution<std::size_t> pick(0, cells.size() - 1);
    std::uniform_real_distribution<double> jitter(-0.5, 0.5);
    std::uniform_real_distribution<double> yaw(0.0, 2.0 * kPi);
    const auto [r, c] = cells[pick(rng)];
    const Vec2 centre = g.cell_center_m(r, c);
    Pose2 p;
    p.x_m = centre.x() + jitter(rng) * resolution_m;
    p.y_m = centre.y() + jitter(rng) * resolution_m;
    p.yaw_rad = yaw(rng);
    poses.push_back(p);
  }
  return poses;
}

}  // namespace floorcast
