// The free-space rule at the outlines of mapped spaces (import_common.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "floorcast/core/box_index.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/rooms.hpp"
#include "import_common.hpp"

namespace floorcast::import_detail {

WalledAtUnmapped wall_unmapped_sides(BoundaryPieces& pieces, const std::vector<Room>& spaces, double offset_m) {
  WalledAtUnmapped out;
  if (pieces.open.empty()) return out;
  // The spaces' union on a raster fine enough for the offset (5 cm; coarser for very large levels,
  // never coarser than a third of the offset).
  double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
  for (const Room& r : spaces) {
    for (const Vec2& v : r.polygon_m) {
      xmin = std::min(xmin, v.x());
      xmax = std::max(xmax, v.x());
      ymin = std::min(ymin, v.y());
      ymax = std::max(ymax, v.y());
    }
  }
  if (!(xmax >= xmin && ymax >= ymin)) {
    // No space at all: every open piece borders unmapped space.
    for (const Segment2& s : pieces.open) {
      out.length_m += s.length_m();
      ++out.pieces;
    }
    pieces.walls.insert(pieces.walls.end(), pieces.open.begin(), pieces.open.end());
    pieces.open.clear();
    return out;
  }
  const double margin = offset_m + 1.0;
  double res = 0.05;
  const double area = (xmax - xmin + 2.0 * margin) * (ymax - ymin + 2.0 * margin);
  res = std::max(res, std::sqrt(area / 4.0e7));
  res = std::min(res, offset_m / 3.0);
  GridSpec g;
  g.resolution_m_per_px = res;
  g.origin_x_m = std::floor((xmin - margin) / res) * res;
  g.origin_y_m = std::floor((ymin - margin) / res) * res;
  const double w = std::ceil((xmax + margin - g.origin_x_m) / res), h = std::ceil((ymax + margin - g.origin_y_m) / res);
  check_raster_budget(w, h, res, 1.0, "outline check of the mapped spaces");
  g.width_px = static_cast<int>(w);
  g.height_px = static_cast<int>(h);
  const cv::Mat mapped = rooms_mask(spaces, g);
  auto inside = [&](const Vec2& p) {
    int r = 0, c = 0;
    return g.world_to_cell(p, r, c) && mapped.at<std::uint8_t>(r, c) != 0;
  };

  std::vector<Segment2> still_open;
  constexpr double kStepM = 0.1;
  for (const Segment2& s : pieces.open) {
    const double len = s.length_m();
    if (!(len > 0.0)) continue;
    const Vec2 u = (s.b_m - s.a_m) / len;
    const Vec2 n(-u.y(), u.x());
    const int steps = std::max(1, static_cast<int>(std::ceil(len / kStepM)));
    // Per sample: does one side lie outside every space?
    std::vector<char> unmapped(static_cast<std::size_t>(steps), 0);
    for (int k = 0; k < steps; ++k) {
      const Vec2 p = s.a_m + (len * (k + 0.5) / steps) * u;
      unmapped[static_cast<std::size_t>(k)] = !inside(p + offset_m * n) || !inside(p - offset_m * n);
    }
    // The raster errs toward "mapped" beside a neighbour's corner (its outline's cells count as
    // inside): an open stretch shorter than 0.3 m next to a walled one is walled too, so a wall
    // along unmapped space has no gap where it passes a corner.
    for (int k = 0; k < steps;) {
      int e = k;
      while (e < steps && unmapped[static_cast<std::size_t>(e)] == unmapped[static_cast<std::size_t>(k)]) ++e;
      const bool next_to_wall = (k > 0) || (e < steps);
      if (!unmapped[static_cast<std::size_t>(k)] && next_to_wall && len * (e - k) / steps < 0.3) {
        for (int q = k; q < e; ++q) unmapped[static_cast<std::size_t>(q)] = 1;
      }
      k = e;
    }
    // Runs of equal samples become pieces.
    int run_start = 0;
    bool run_unmapped = false;
    auto flush = [&](int end) {
      const Segment2 piece{s.a_m + (len * run_start / steps) * u, s.a_m + (len * end / steps) * u};
      if (run_unmapped) {
        pieces.walls.push_back(piece);
        out.length_m += piece.length_m();
        ++out.pieces;
      } else {
        still_open.push_back(piece);
      }
    };
    for (int k = 0; k < steps; ++k) {
      const bool here = unmapped[static_cast<std::size_t>(k)] != 0;
      if (k == 0) {
        run_unmapped = here;
      } else if (here != run_unmapped) {
        flush(k);
        run_start = k;
        run_unmapped = here;
      }
    }
    flush(steps);
  }
  pieces.open = std::move(still_open);
  return out;
}

}  // namespace floorcast::import_detail

namespace floorcast::import_detail {
namespace {

struct Box {
  double x0, y0, x1, y1;
  bool near(const Box& o, double d) const { return !(o.x0 > x1 + d || x0 > o.x1 + d || o.y0 > y1 + d || y0 > o.y1 + d); }
};

Box ring_box(const std::vector<Vec2>& ring) {
  Box b{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const Vec2& v : ring) {
    b.x0 = std::min(b.x0, v.x());
    b.y0 = std::min(b.y0, v.y());
    b.x1 = std::max(b.x1, v.x());
    b.y1 = std::max(b.y1, v.y());
  }
  return b;
}

/// Outline edges of a room (outer ring and holes).
std::vector<Segment2> outline_edges(const Room& room) {
  std::vector<Segment2> out;
  auto add = [&](const std::vector<Vec2>& ring) {
    for (std::size_t k = 0; k < ring.size(); ++k) out.push_back({ring[k], ring[(k + 1) % ring.size()]});
  };
  add(room.polygon_m);
  for (const auto& h : room.holes_m) add(h);
  return out;
}

}  // namespace

OpeningsReport check_openings(FloorPlan& plan, const std::vector<Segment2>& walls, bool infer, double width_m,
                              double reach_m, std::vector<std::string>& notes) {
  OpeningsReport rep;
  constexpr double kStepM = 0.1, kSideM = 0.15, kEndMarginM = 0.2, kMinDoorM = 0.6;
  // Samples per outline edge: one per kStepM up to 2 km of edge; longer edges (no building has
  // one: a stray node hundreds of km away, which validation refuses after the import) are
  // sampled more coarsely so that the check costs no more than a 2 km edge (found by fuzzing: a
  // 300 km edge took 0.3 s here and 36 s under the sanitizers).
  constexpr int kMaxEdgeSamples = 20000;
  auto edge_samples = [&](double len) {
    return std::clamp(static_cast<int>(std::ceil(std::min(len, 1e9) / kStepM)), 1, kMaxEdgeSamples);
  };
  std::vector<Box> wall_boxes;
  for (const Segment2& w : walls) wall_boxes.push_back(ring_box({w.a_m, w.b_m}));
  // Whether a wall lies within reach of a sample: the room's nearby walls scanned when they are
  // few, the walls' R-tree asked for those near the sample when they are many (a room whose box
  // spans the plan, e.g. a fuzzed outline edge of 75 km: 20,000 samples x every wall took 5 CPU s
  // under the sanitizers). The same answer either way: a wall within reach of a point has its box
  // within reach of it.
  std::vector<IndexBox> index_boxes;
  index_boxes.reserve(walls.size());
  for (const Box& b : wall_boxes) index_boxes.push_back({b.x0, b.y0, b.x1, b.y1});
  const BoxIndex wall_index(index_boxes);
  constexpr std::size_t kScanAtMost = 64;
  std::vector<std::uint32_t> candidates;
  auto wall_within_reach = [&](const Vec2& p, const std::vector<Segment2>& near_walls) {
    if (near_walls.size() <= kScanAtMost) return distance_to_segments(p, near_walls) <= reach_m;
    wall_index.query(IndexBox{p.x(), p.y(), p.x(), p.y()}.grown(reach_m), candidates);
    for (std::uint32_t w : candidates) {
      if (point_segment_distance(p, walls[w]) <= reach_m) return true;
    }
    return false;
  };
  std::vector<std::string> without, sealed;
  const std::size_t nrooms = plan.rooms.size();
  for (std::size_t i = 0; i < nrooms; ++i) {
    const Room room = plan.rooms[i];  // a copy: plan.rooms is not resized below, but stay safe
    if (room.polygon_m.size() < 3 || is_transitional_kind(room.kind) || room.kind == "area" || is_unmapped_kind(room.kind)) {
      continue;
    }
    ++rep.rooms;
    const Box box = ring_box(room.polygon_m);
    std::vector<Segment2> near_walls;
    for (std::size_t w = 0; w < walls.size(); ++w) {
      if (wall_boxes[w].near(box, reach_m)) near_walls.push_back(walls[w]);
    }
    const std::vector<Segment2> edges = outline_edges(room);
    bool open = false;
    for (const Door& d : plan.doors) {
      if (distance_to_segments(d.center_m, edges) <= reach_m) {
        open = true;
        break;
      }
    }
    // A stretch of outline (>= 0.3 m) with no wall on it is an opening too.
    for (std::size_t e = 0; e < edges.size() && !open; ++e) {
      const double len = edges[e].length_m();
      const int steps = edge_samples(len);
      int run = 0;
      for (int k = 0; k < steps && !open; ++k) {
        const Vec2 p = edges[e].a_m + ((k + 0.5) / steps) * (edges[e].b_m - edges[e].a_m);
        run = wall_within_reach(p, near_walls) ? 0 : run + 1;
        open = run * len / steps >= 0.3;
      }
    }
    if (open) continue;
    ++rep.rooms_without;
    without.push_back(room.id);
    if (!infer) continue;
    // The longest stretch on a wall with a transitional space on its far side.
    double best_len = 0.0;
    Vec2 best_a = Vec2::Zero(), best_b = Vec2::Zero();
    std::string best_neighbour;
    for (const Segment2& e : edges) {
      const double len = e.length_m();
      if (!(len > 0.0)) continue;
      const Vec2 u = (e.b_m - e.a_m) / len;
      const Vec2 n(-u.y(), u.x());
      const int steps = edge_samples(len);
      int start = -1;
      std::string neighbour;
      auto close_run = [&](int end) {
        if (start < 0) return;
        const double run_len = len * (end - start) / steps;
        if (run_len > best_len + 1e-9) {
          best_len = run_len;
          best_a = e.a_m + (len * start / steps) * u;
          best_b = e.a_m + (len * end / steps) * u;
          best_neighbour = neighbour;
        }
        start = -1;
      };
      for (int k = 0; k < steps; ++k) {
        const Vec2 p = e.a_m + (len * (k + 0.5) / steps) * u;
        // The far side: of the two offset points, the one outside the room.
        const Vec2 far = room_contains(room, p + kSideM * n) ? Vec2(p - kSideM * n) : Vec2(p + kSideM * n);
        const int other = room_at(plan.rooms, far);
        const bool ok = wall_within_reach(p, near_walls) && other >= 0 && other != static_cast<int>(i) &&
                        is_transitional_kind(plan.rooms[static_cast<std::size_t>(other)].kind);
        if (ok && start < 0) {
          start = k;
          neighbour = plan.rooms[static_cast<std::size_t>(other)].id;
        } else if (!ok) {
          close_run(k);
        }
      }
      close_run(steps);
    }
    const double width = std::min(width_m, best_len - 2.0 * kEndMarginM);
    if (width < kMinDoorM) {
      ++rep.left_sealed;
      sealed.push_back(room.id);
      continue;
    }
    Door d;
    d.id = "inferred-" + room.id;
    d.center_m = 0.5 * (best_a + best_b);
    d.width_m = width;
    plan.doors.push_back(d);
    ++rep.inferred;
    notes.push_back("room " + room.id + " (" + room.kind + ") has no opening in the source: door inferred on its " +
                    fmt(std::round(best_len * 100.0) / 100.0) + " m boundary with " + best_neighbour + ", " +
                    fmt(std::round(width * 100.0) / 100.0) + " m wide (--infer-openings)");
  }
  if (!infer) rep.left_sealed = rep.rooms_without;
  if (rep.rooms_without > 0) {
    auto list = [](const std::vector<std::string>& ids) {
      std::string s;
      for (std::size_t k = 0; k < ids.size() && k < 8; ++k) s += (k ? ", " : "") + ids[k];
      if (ids.size() > 8) s += ", ... (" + std::to_string(ids.size() - 8) + " more)";
      return s;
    };
    std::string msg = std::to_string(rep.rooms_without) + " of " + std::to_string(rep.rooms) +
                      " rooms have no opening in the source (" + list(without) + ")";
    if (plan.doors.empty() || rep.rooms_without == rep.rooms) msg = "the source has no openings for this level's rooms: " + msg;
    if (!infer) {
      msg += ": sealed; --infer-openings places a door on each one's boundary with a corridor or hall";
    } else {
      msg += ": " + std::to_string(rep.inferred) + " doors inferred (--infer-openings)";
      if (rep.left_sealed > 0) {
        msg += ", " + std::to_string(rep.left_sealed) + " left sealed (no stretch of wall shared with a corridor or hall long enough: " +
               list(sealed) + ")";
      }
    }
    notes.insert(notes.begin(), msg);
  }
  return rep;
}

}  // namespace floorcast::import_detail
