#include "floorcast/floorplans/faithfulness.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <sstream>

#include <opencv2/imgproc.hpp>

#include "floorcast/core/format.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/floorplans/rooms.hpp"

namespace floorcast {
namespace {

bool is_space(const Room& r) { return !is_unmapped_kind(r.kind) && r.polygon_m.size() >= 3; }

/// A grid over the plan's walls and its room labels together (a space outline may reach past the
/// walls' extent), origin snapped to the resolution as grid_for_plan does, at the options'
/// resolution or coarser when the level would exceed max_cells.
GridSpec report_grid(const FloorPlan& plan, const FaithfulnessOptions& options) {
  Eigen::Vector4d box = plan_bbox_m(plan);
  for (const Room& r : plan.rooms) {
    for (const Vec2& v : r.polygon_m) {
      box[0] = std::min(box[0], v.x());
      box[1] = std::min(box[1], v.y());
      box[2] = std::max(box[2], v.x());
      box[3] = std::max(box[3], v.y());
    }
  }
  constexpr double kMargin = 1.0;
  const double area = (box[2] - box[0] + 2.0 * kMargin) * (box[3] - box[1] + 2.0 * kMargin);
  double res = options.resolution_m_per_px;
  if (area / (res * res) > options.max_cells) res = std::sqrt(area / options.max_cells);
  GridSpec g;
  g.resolution_m_per_px = res;
  g.origin_x_m = std::floor((box[0] - kMargin) / res) * res;
  g.origin_y_m = std::floor((box[1] - kMargin) / res) * res;
  const double w = std::max(1.0, std::ceil((box[2] + kMargin - g.origin_x_m) / res));
  const double h = std::max(1.0, std::ceil((box[3] + kMargin - g.origin_y_m) / res));
  check_raster_budget(w, h, res, kPlanRasterBytesPerCell + 8.0, "faithfulness check of plan \"" + plan.name + "\"");
  g.width_px = static_cast<int>(w);
  g.height_px = static_cast<int>(h);
  return g;
}

std::string percent(double share) { return format_fixed(100.0 * share, 1) + "%"; }
std::string area_text(double m2) { return format_fixed(m2, m2 < 100.0 ? 1 : 0) + " m^2"; }

}  // namespace

std::vector<Room> unmapped_regions(const FloorPlan& plan, const FaithfulnessOptions& options) {
  if (std::none_of(plan.rooms.begin(), plan.rooms.end(), is_space)) return {};
  const GridSpec g = report_grid(plan, options);
  const cv::Mat valid = valid_area_mask(plan, g);
  const cv::Mat mapped = rooms_mask(plan.rooms, g, is_space);
  cv::Mat loose;
  cv::bitwise_and(valid, ~mapped, loose);
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(loose, labels, stats, centroids, 4, CV_32S);
  const double cell = g.resolution_m_per_px * g.resolution_m_per_px;
  std::vector<char> keep(static_cast<std::size_t>(n), 0);
  bool any = false;
  for (int k = 1; k < n; ++k) {
    keep[static_cast<std::size_t>(k)] = stats.at<int>(k, cv::CC_STAT_AREA) * cell >= options.min_unmapped_area_m2;
    any = any || keep[static_cast<std::size_t>(k)];
  }
  if (!any) return {};
  cv::Mat coarse(loose.size(), CV_8U, cv::Scalar(0));
  for (int r = 0; r < labels.rows; ++r) {
    const int* l = labels.ptr<int>(r);
    std::uint8_t* o = coarse.ptr<std::uint8_t>(r);
    for (int c = 0; c < labels.cols; ++c) o[c] = keep[static_cast<std::size_t>(l[c])] ? 255 : 0;
  }
  // Traced on a grid twice as fine, grown up to one coarse cell into the walls around it but never
  // into a mapped space: the outline runs along the walls' axes (the spaces' edges), and every cell
  // of the region lies strictly inside it.
  GridSpec fine = g;
  fine.resolution_m_per_px = 0.5 * g.resolution_m_per_px;
  fine.width_px = 2 * g.width_px;
  fine.height_px = 2 * g.height_px;
  cv::Mat region;
  cv::resize(coarse, region, cv::Size(fine.width_px, fine.height_px), 0.0, 0.0, cv::INTER_NEAREST);
  cv::dilate(region, region, cv::getStructuringElement(cv::MORPH_CROSS, cv::Size(5, 5)));
  cv::bitwise_and(region, ~rooms_mask(plan.rooms, fine, is_space), region);
  std::vector<std::vector<cv::Point>> contours;
  std::vector<cv::Vec4i> hierarchy;
  cv::findContours(region, contours, hierarchy, cv::RETR_CCOMP, cv::CHAIN_APPROX_SIMPLE);
  auto to_world = [&](const std::vector<cv::Point>& contour) {
    std::vector<cv::Point> simple;
    cv::approxPolyDP(contour, simple, 0.5, true);
    std::vector<Vec2> ring;
    for (const cv::Point& p : simple) ring.push_back(fine.cell_center_m(p.y, p.x));
    return ring;
  };
  std::vector<Room> out;
  for (std::size_t i = 0; i < contours.size(); ++i) {
    if (hierarchy[i][3] >= 0) continue;  // a hole: added to its outer contour below
    Room room;
    room.kind = kUnmappedRoomKind;
    room.polygon_m = to_world(contours[i]);
    if (room.polygon_m.size() < 3) continue;
    for (int h = hierarchy[i][2]; h >= 0; h = hierarchy[static_cast<std::size_t>(h)][0]) {
      std::vector<Vec2> hole = to_world(contours[static_cast<std::size_t>(h)]);
      if (hole.size() >= 3) room.holes_m.push_back(std::move(hole));
    }
    out.push_back(std::move(room));
  }
  // Stable order (largest first, then position), ids after it.
  std::stable_sort(out.begin(), out.end(), [](const Room& a, const Room& b) { return room_area_m2(a) > room_area_m2(b); });
  for (std::size_t i = 0; i < out.size(); ++i) out[i].id = "unmapped" + std::to_string(i + 1);
  return out;
}

FaithfulnessReport check_faithfulness(const FloorPlan& plan, const FaithfulnessOptions& options) {
  FaithfulnessReport rep;
  if (std::none_of(plan.rooms.begin(), plan.rooms.end(), is_space)) return rep;
  rep.applicable = true;
  const GridSpec g = report_grid(plan, options);
  rep.resolution_m_per_px = g.resolution_m_per_px;
  const double cell = g.resolution_m_per_px * g.resolution_m_per_px;
  const cv::Mat valid = valid_area_mask(plan, g);
  const cv::Mat blocked = rasterize_occupancy(plan, g, BlockingOptions{});
  // Connectivity with every door open.
  FloorPlan open_plan = plan;
  for (Door& d : open_plan.doors) d.closed = false;
  const cv::Mat reach = valid_area_mask(open_plan, g);
  cv::Mat comp;
  const int ncomp = cv::connectedComponents(reach, comp, 4, CV_32S);
  const cv::Mat index = room_index_raster(plan.rooms, g);

  const std::size_t nrooms = plan.rooms.size();
  std::vector<long> mapped(nrooms, 0), wall(nrooms, 0), free_cells(nrooms, 0);
  std::vector<long> comp_size(static_cast<std::size_t>(ncomp), 0);
  // Per component: the one space seen in it (-1 none yet), or -2 for several.
  std::vector<int> comp_space(static_cast<std::size_t>(ncomp), -1);
  long mapped_total = 0, wall_total = 0, free_total = 0, free_in = 0, free_out = 0, unmapped_cells = 0;
  for (int r = 0; r < g.height_px; ++r) {
    const int* ix = index.ptr<int>(r);
    const std::uint8_t* v = valid.ptr<std::uint8_t>(r);
    const std::uint8_t* b = blocked.ptr<std::uint8_t>(r);
    const int* cp = comp.ptr<int>(r);
    for (int c = 0; c < g.width_px; ++c) {
      const int k = ix[c];
      const bool space = k >= 0 && is_space(plan.rooms[static_cast<std::size_t>(k)]);
      if (k >= 0 && !space) ++unmapped_cells;
      if (v[c]) {
        ++free_total;
        (space ? free_in : free_out) += 1;
      }
      if (cp[c] > 0) {
        ++comp_size[static_cast<std::size_t>(cp[c])];
        if (space) {
          int& owner = comp_space[static_cast<std::size_t>(cp[c])];
          owner = owner == -1 ? k : (owner == k ? k : -2);
        }
      }
      if (!space) continue;
      const std::size_t ku = static_cast<std::size_t>(k);
      ++mapped[ku];
      ++mapped_total;
      if (b[c]) {
        ++wall[ku];
        ++wall_total;
      } else if (v[c]) {
        ++free_cells[ku];
      }
    }
  }
  int main_comp = 0;
  for (int k = 1; k < ncomp; ++k) {
    if (main_comp == 0 || comp_size[static_cast<std::size_t>(k)] > comp_size[static_cast<std::size_t>(main_comp)]) main_comp = k;
  }
  // Per space: does it share a component with another space; does it reach the main one.
  std::vector<char> shares(nrooms, 0), in_main(nrooms, 0);
  for (int r = 0; r < g.height_px; ++r) {
    const int* ix = index.ptr<int>(r);
    const int* cp = comp.ptr<int>(r);
    for (int c = 0; c < g.width_px; ++c) {
      if (cp[c] <= 0 || ix[c] < 0) continue;
      const std::size_t ku = static_cast<std::size_t>(ix[c]);
      if (comp_space[static_cast<std::size_t>(cp[c])] == -2) shares[ku] = 1;
      if (cp[c] == main_comp) in_main[ku] = 1;
    }
  }

  std::map<std::string, KindFaithfulness> kinds;
  for (std::size_t i = 0; i < nrooms; ++i) {
    const Room& room = plan.rooms[i];
    if (!is_space(room)) {
      if (is_unmapped_kind(room.kind)) ++rep.unmapped_regions;
      continue;
    }
    ++rep.spaces;
    const double area = room_area_m2(room);
    rep.source_area_m2 += area;
    KindFaithfulness& k = kinds[room.kind];
    k.kind = room.kind;
    ++k.spaces;
    k.source_area_m2 += area;
    k.mapped_area_m2 += mapped[i] * cell;
    k.wall_area_m2 += wall[i] * cell;
    k.free_area_m2 += free_cells[i] * cell;
    const long open_cells = mapped[i] - wall[i];
    if (open_cells > 0 && free_cells[i] < 0.5 * static_cast<double>(open_cells)) rep.spaces_outside_free.push_back(room.id);
    if (free_cells[i] > 0 && !shares[i] && !in_main[i]) {
      ++rep.sealed_spaces;
      rep.sealed_area_m2 += mapped[i] * cell;
      rep.sealed_ids.push_back(room.id);
    }
    if (!in_main[i]) {
      ++rep.unreachable_spaces;
      rep.unreachable_area_m2 += mapped[i] * cell;
    }
  }
  for (auto& [name, k] : kinds) {
    const double open = k.mapped_area_m2 - k.wall_area_m2;
    k.free_share = open > 0.0 ? k.free_area_m2 / open : 1.0;
    rep.kinds.push_back(k);
  }
  rep.mapped_area_m2 = mapped_total * cell;
  rep.wall_area_m2 = wall_total * cell;
  rep.free_area_m2 = free_total * cell;
  rep.free_in_mapped_m2 = free_in * cell;
  rep.free_outside_mapped_m2 = free_out * cell;
  rep.unmapped_area_m2 = unmapped_cells * cell;
  const double open = rep.mapped_area_m2 - rep.wall_area_m2;
  rep.free_share = open > 0.0 ? rep.free_in_mapped_m2 / open : 1.0;

  // Warnings.
  if (rep.free_share < 1.0 - options.max_missing_share) {
    std::string lacking;
    for (const KindFaithfulness& k : rep.kinds) {
      if (k.mapped_area_m2 >= options.min_kind_area_m2 && k.free_share < 1.0 - options.max_missing_share) {
        lacking += (lacking.empty() ? "" : ", ") + k.kind + " " + percent(k.free_share) + " of " + area_text(k.mapped_area_m2);
      }
    }
    rep.warnings.push_back("only " + percent(rep.free_share) + " of the mapped spaces (less wall bodies) is free floor: " +
                           area_text(open - rep.free_in_mapped_m2) + " of mapped space lies outside the walls" +
                           (lacking.empty() ? std::string() : " (free share by kind: " + lacking + ")"));
  } else {
    for (const KindFaithfulness& k : rep.kinds) {
      if (k.mapped_area_m2 >= options.min_kind_area_m2 && k.free_share < 1.0 - options.max_missing_share) {
        rep.warnings.push_back("only " + percent(k.free_share) + " of the " + std::to_string(k.spaces) + " " + k.kind +
                               " space(s) (" + area_text(k.mapped_area_m2) + ", less walls) is free floor");
      }
    }
  }
  if (rep.free_area_m2 > 0.0 && rep.free_outside_mapped_m2 > options.max_unmapped_free_share * rep.free_area_m2) {
    rep.warnings.push_back(area_text(rep.free_outside_mapped_m2) + " (" +
                           percent(rep.free_outside_mapped_m2 / rep.free_area_m2) +
                           ") of the free floor lies in no mapped space");
  }
  if (rep.mapped_area_m2 > 0.0 && rep.sealed_area_m2 > options.max_sealed_area_share * rep.mapped_area_m2) {
    rep.warnings.push_back(std::to_string(rep.sealed_spaces) + " of " + std::to_string(rep.spaces) + " spaces (" +
                           percent(rep.sealed_area_m2 / rep.mapped_area_m2) +
                           " of the mapped area) are sealed: no opening or open boundary connects them to another space");
  }
  return rep;
}

std::string faithfulness_summary(const FaithfulnessReport& r) {
  if (!r.applicable) return "not applicable (the source maps no spaces)";
  std::ostringstream os;
  os << "free " << area_text(r.free_in_mapped_m2) << " = " << percent(r.free_share) << " of the " << r.spaces
     << " mapped spaces' " << area_text(r.mapped_area_m2) << " less " << area_text(r.wall_area_m2)
     << " under walls (source polygons " << area_text(r.source_area_m2) << "); free outside every space "
     << area_text(r.free_outside_mapped_m2) << "; unmapped, not floor " << area_text(r.unmapped_area_m2) << " in "
     << r.unmapped_regions << " region(s); sealed spaces " << r.sealed_spaces << " (" << area_text(r.sealed_area_m2)
     << "); not reachable from the largest free region " << r.unreachable_spaces << " (" << area_text(r.unreachable_area_m2)
     << ")";
  return os.str();
}

}  // namespace floorcast
