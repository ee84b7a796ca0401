#include "floorcast/scenarios/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>

#include "floorcast/core/format.hpp"
#include "floorcast/floorplans/raster.hpp"

namespace floorcast {

namespace {

std::string area_text(double m2) { return format_fixed(m2, m2 < 100.0 ? 1 : 0) + " m^2"; }

std::string kinds_text(const std::vector<std::string>& kinds) {
  std::string s;
  for (std::size_t k = 0; k < kinds.size() && k < 12; ++k) s += (k ? ", " : "") + kinds[k];
  if (kinds.size() > 12) s += ", ...";
  return s;
}

}  // namespace

std::vector<Pose2> sample_observation_poses(const FloorPlan& plan, int n, std::uint64_t seed, int plan_index,
                                            double clearance_m, double resolution_m,
                                            const std::vector<Room>& rooms, const std::vector<std::string>& kinds) {
  return sample_observation_points(plan, n, seed, plan_index, clearance_m, resolution_m, rooms, kinds).poses;
}

SampledPoints sample_observation_points(const FloorPlan& plan, int n, std::uint64_t seed, int plan_index,
                                        double clearance_m, double resolution_m, const std::vector<Room>& rooms,
                                        const std::vector<std::string>& kinds) {
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
  int wanted_rooms = 0;
  for (std::size_t k = 0; k < rooms.size(); ++k) {
    room_wanted[k] = std::find(wanted.begin(), wanted.end(), rooms[k].kind) != wanted.end();
    wanted_rooms += room_wanted[k] ? 1 : 0;
  }
  const cv::Mat room_index = wanted.empty() ? cv::Mat() : room_index_raster(rooms, g);
  SampledPoints out;
  for (std::size_t k = 0; k < rooms.size(); ++k) {
    if (room_wanted[k]) out.coverage.kind_area_m2 += room_area_m2(rooms[k]);
  }
  const double cell_area = resolution_m * resolution_m;
  SamplingCoverage& cov = out.coverage;
  std::vector<std::pair<int, int>> cells;
  float widest_kind_m = 0.0f;  // the largest distance to a blocked cell in free cells of the kinds
  for (int r = 0; r < g.height_px; ++r) {
    const std::uint8_t* v = rasters.valid.ptr<std::uint8_t>(r);
    const float* d = distance_m.ptr<float>(r);
    for (int c = 0; c < g.width_px; ++c) {
      if (!wanted.empty()) {
        const int k = room_index.at<int>(r, c);
        if (k < 0 || !room_wanted[static_cast<std::size_t>(k)]) continue;
        if (v[c]) {
          cov.kind_free_area_m2 += cell_area;
          widest_kind_m = std::max(widest_kind_m, d[c]);
        }
      }
      if (!v[c] || d[c] < need) continue;
      cells.emplace_back(r, c);
    }
  }
  cov.candidate_area_m2 = static_cast<double>(cells.size()) * cell_area;
  if (cells.empty()) {
    const std::string what = "plan \"" + plan.name + "\": ";
    if (wanted.empty()) {
      throw SamplingError(SamplingRefusal::kNoClearance, what + "no free cell with " + format_fixed(clearance_m, 2) +
                                                             " m clearance to sample observation points from");
    }
    if (wanted_rooms == 0) {
      std::map<std::string, int> have;
      for (const Room& room : rooms) {
        if (!is_unmapped_kind(room.kind)) ++have[room.kind];
      }
      std::string list;
      for (const auto& [kind, count] : have) list += (list.empty() ? "" : ", ") + kind + " " + std::to_string(count);
      throw SamplingError(SamplingRefusal::kNoRoomOfKinds,
                          what + "no room of the sampled kinds (" + kinds_text(wanted) + "); its rooms: " +
                              (list.empty() ? std::string("none") : list) +
                              " (sampling.region: transitional_or_uniform samples such plans uniformly)");
    }
    if (cov.kind_free_area_m2 < std::max(1.0, 0.05 * cov.kind_area_m2)) {
      throw SamplingError(SamplingRefusal::kKindsOutsideFreeSpace,
                          what + "its " + std::to_string(wanted_rooms) + " room(s) of the sampled kinds (" +
                              kinds_text(wanted) + ") cover " + area_text(cov.kind_area_m2) + ", of which only " +
                              area_text(cov.kind_free_area_m2) +
                              " is free floor: they lie outside the plan's free space (missing corridors: the walls "
                              "leave them out; `floorcast plan import` reports this in its faithfulness check)");
    }
    throw SamplingError(SamplingRefusal::kKindsTooNarrow,
                        what + "its " + std::to_string(wanted_rooms) + " room(s) of the sampled kinds (" + kinds_text(wanted) +
                            ") have " + area_text(cov.kind_free_area_m2) + " of free floor, nowhere more than " +
                            format_fixed(2.0 * widest_kind_m, 2) + " m wide: no cell keeps " + format_fixed(clearance_m, 2) +
                            " m clearance (lower sampling.clearance_m, or sample uniformly)");
  }
  std::vector<Pose2>& poses = out.poses;
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

  // Coverage.
  cov.points = static_cast<int>(poses.size());
  std::map<std::string, int> per_kind;
  std::set<std::pair<long long, long long>> cells_2m;
  for (const Pose2& p : poses) {
    const int k = room_at(rooms, {p.x_m, p.y_m});
    ++per_kind[k < 0 ? std::string("unlabelled") : rooms[static_cast<std::size_t>(k)].kind];
    cells_2m.emplace(static_cast<long long>(std::floor(p.x_m / 2.0)), static_cast<long long>(std::floor(p.y_m / 2.0)));
  }
  cov.points_per_kind.assign(per_kind.begin(), per_kind.end());
  std::stable_sort(cov.points_per_kind.begin(), cov.points_per_kind.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  cov.distinct_cells_2m = static_cast<int>(cells_2m.size());
  if (!wanted.empty() && cov.kind_free_area_m2 < 0.5 * cov.kind_area_m2) {
    cov.warnings.push_back("only " + area_text(cov.kind_free_area_m2) + " of the " + area_text(cov.kind_area_m2) +
                           " of rooms of the sampled kinds is free floor: most of them lie outside the plan's free "
                           "space (missing corridors?)");
  }
  if (cov.points >= 8 && cov.distinct_cells_2m <= std::max(2, cov.points / 8)) {
    cov.warnings.push_back("the " + std::to_string(cov.points) + " points fall into only " +
                           std::to_string(cov.distinct_cells_2m) + " distinct 2 m cells (" +
                           area_text(cov.candidate_area_m2) + " to draw from): the sampled region is tiny");
  }
  return out;
}

std::string sampling_coverage_summary(const SamplingCoverage& c) {
  std::string s;
  for (const auto& [kind, count] : c.points_per_kind) s += (s.empty() ? "" : ", ") + std::to_string(count) + " " + kind;
  s += "; " + std::to_string(c.distinct_cells_2m) + " distinct 2 m cells; " + area_text(c.candidate_area_m2) + " to draw from";
  return s;
}

}  // namespace floorcast
