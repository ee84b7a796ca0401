#include "floorcast/floorplans/rooms.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

namespace floorcast {

bool point_in_polygon(const std::vector<Vec2>& poly, const Vec2& p) {
  bool inside = false;
  const std::size_t n = poly.size();
  if (n < 3) return false;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

bool room_contains(const Room& room, const Vec2& p) {
  if (!point_in_polygon(room.polygon_m, p)) return false;
  for (const auto& hole : room.holes_m) {
    if (point_in_polygon(hole, p)) return false;
  }
  return true;
}

namespace {
double ring_area(const std::vector<Vec2>& ring) {
  double a = 0.0;
  const std::size_t n = ring.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    a += ring[j].x() * ring[i].y() - ring[i].x() * ring[j].y();
  }
  return 0.5 * std::abs(a);
}
}  // namespace

double room_area_m2(const Room& room) {
  if (room.polygon_m.size() < 3) return 0.0;
  double a = ring_area(room.polygon_m);
  for (const auto& hole : room.holes_m) {
    if (hole.size() >= 3) a -= ring_area(hole);
  }
  return std::max(a, 0.0);
}

int room_at(const std::vector<Room>& rooms, const Vec2& p) {
  int best = -1;
  double best_area = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < rooms.size(); ++i) {
    if (!room_contains(rooms[i], p)) continue;
    const double a = room_area_m2(rooms[i]);
    if (a < best_area) {
      best_area = a;
      best = static_cast<int>(i);
    }
  }
  return best;
}

cv::Mat room_index_raster(const std::vector<Room>& rooms, const GridSpec& grid) {
  cv::Mat out(grid.height_px, grid.width_px, CV_32S, cv::Scalar(-1));
  cv::Mat area(grid.height_px, grid.width_px, CV_64F, cv::Scalar(std::numeric_limits<double>::infinity()));
  const double res = grid.resolution_m_per_px;
  for (std::size_t i = 0; i < rooms.size(); ++i) {
    const Room& room = rooms[i];
    if (room.polygon_m.size() < 3) continue;
    const double a = room_area_m2(room);
    double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
    for (const Vec2& v : room.polygon_m) {
      xmin = std::min(xmin, v.x());
      xmax = std::max(xmax, v.x());
      ymin = std::min(ymin, v.y());
      ymax = std::max(ymax, v.y());
    }
    const int c0 = std::max(0, static_cast<int>(std::floor((xmin - grid.origin_x_m) / res)));
    const int c1 = std::min(grid.width_px - 1, static_cast<int>(std::floor((xmax - grid.origin_x_m) / res)));
    const int r0 = std::max(0, static_cast<int>(std::floor((ymin - grid.origin_y_m) / res)));
    const int r1 = std::min(grid.height_px - 1, static_cast<int>(std::floor((ymax - grid.origin_y_m) / res)));
    for (int r = r0; r <= r1; ++r) {
      int* o = out.ptr<int>(r);
      double* ar = area.ptr<double>(r);
      for (int c = c0; c <= c1; ++c) {
        if (!(a < ar[c])) continue;  // a smaller (or earlier equal) room already holds the cell
        if (!room_contains(room, grid.cell_center_m(r, c))) continue;
        o[c] = static_cast<int>(i);
        ar[c] = a;
      }
    }
  }
  return out;
}

cv::Mat rooms_mask(const std::vector<Room>& rooms, const GridSpec& grid, const std::function<bool(const Room&)>& select) {
  cv::Mat mask(grid.height_px, grid.width_px, CV_8U, cv::Scalar(0));
  constexpr int kShift = 4;  // 1/16 cell
  for (const Room& room : rooms) {
    if (room.polygon_m.size() < 3 || (select && !select(room))) continue;
    double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
    for (const Vec2& v : room.polygon_m) {
      const Vec2 g = grid.world_to_grid(v);
      xmin = std::min(xmin, g.x());
      xmax = std::max(xmax, g.x());
      ymin = std::min(ymin, g.y());
      ymax = std::max(ymax, g.y());
    }
    const int c0 = std::max(0, static_cast<int>(std::floor(xmin)) - 1);
    const int r0 = std::max(0, static_cast<int>(std::floor(ymin)) - 1);
    const int c1 = std::min(grid.width_px, static_cast<int>(std::ceil(xmax)) + 1);
    const int r1 = std::min(grid.height_px, static_cast<int>(std::ceil(ymax)) + 1);
    if (c1 <= c0 || r1 <= r0) continue;
    const cv::Rect roi(c0, r0, c1 - c0, r1 - r0);
    // Cell (r, c) is pixel (c, r) with its centre at integer coordinates.
    auto ring_px = [&](const std::vector<Vec2>& ring) {
      std::vector<cv::Point> out;
      out.reserve(ring.size());
      for (const Vec2& v : ring) {
        const Vec2 g = grid.world_to_grid(v) - Vec2(0.5 + c0, 0.5 + r0);
        out.emplace_back(static_cast<int>(std::lround(g.x() * (1 << kShift))),
                         static_cast<int>(std::lround(g.y() * (1 << kShift))));
      }
      return out;
    };
    cv::Mat one(roi.size(), CV_8U, cv::Scalar(0));
    cv::fillPoly(one, std::vector<std::vector<cv::Point>>{ring_px(room.polygon_m)}, cv::Scalar(255), cv::LINE_8, kShift);
    for (const auto& hole : room.holes_m) {
      if (hole.size() >= 3) {
        cv::fillPoly(one, std::vector<std::vector<cv::Point>>{ring_px(hole)}, cv::Scalar(0), cv::LINE_8, kShift);
      }
    }
    cv::Mat target = mask(roi);
    cv::bitwise_or(target, one, target);
  }
  return mask;
}

bool is_unmapped_kind(const std::string& kind) { return kind == kUnmappedRoomKind; }

const std::vector<std::string>& transitional_room_kinds() {
  static const std::vector<std::string> kinds = {"hallway", "corridor", "walkway", "lobby", "foyer", "entrance",
                                                 "atrium", "lounge", "hall", "vestibule", "circulation"};
  return kinds;
}

bool is_transitional_kind(const std::string& kind) {
  const auto& k = transitional_room_kinds();
  return std::find(k.begin(), k.end(), kind) != k.end();
}

std::vector<std::string> expand_room_kinds(const std::vector<std::string>& kinds) {
  std::vector<std::string> out;
  auto add = [&](const std::string& k) {
    if (std::find(out.begin(), out.end(), k) == out.end()) out.push_back(k);
  };
  for (const std::string& k : kinds) {
    if (k == "transitional") {
      for (const std::string& t : transitional_room_kinds()) add(t);
    } else {
      add(k);
    }
  }
  return out;
}

}  // namespace floorcast
