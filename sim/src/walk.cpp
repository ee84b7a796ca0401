#include "floorcast/sim/walk.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "floorcast/core/format.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/fields.hpp"
#include "floorcast/core/params.hpp"
#include "floorcast/core/random.hpp"
#include "floorcast/floorplans/raster.hpp"

namespace floorcast {
namespace {

/// Random-number streams of a walk (distinct from the scan simulator's).
enum WalkStream : std::uint64_t {
  kStreamStart = 101,
  kStreamGait = 102,
  kStreamGoal = 103,
  kStreamStep = 104,
  kStreamPause = 105,
};

/// The navigation grid: free cells (interior, with clearance) and each cell's clearance.
struct NavGrid {
  GridSpec grid;
  cv::Mat free;        ///< CV_8U, 255 = walkable
  cv::Mat clearance;   ///< CV_32F metres to the nearest obstacle cell

  bool is_free(int r, int c) const { return grid.contains(r, c) && free.at<std::uint8_t>(r, c) != 0; }
  bool is_free(const Vec2& p) const {
    int r = 0, c = 0;
    return grid.world_to_cell(p, r, c) && free.at<std::uint8_t>(r, c) != 0;
  }
  /// Every point of the segment, sampled at a quarter cell, lies in a free cell.
  bool segment_free(const Vec2& a, const Vec2& b) const {
    const double len = (b - a).norm();
    const int n = std::max(1, static_cast<int>(std::ceil(len / (0.25 * grid.resolution_m_per_px))));
    for (int k = 0; k <= n; ++k) {
      if (!is_free(a + (b - a) * (static_cast<double>(k) / n))) return false;
    }
    return true;
  }
};

NavGrid make_nav_grid(const FloorPlan& plan, const WalkParams& p) {
  NavGrid nav;
  nav.grid = grid_for_plan(plan, p.resolution_m, 0.5);
  const cv::Mat blocked = rasterize_occupancy(plan, nav.grid, walker_blocking());
  const cv::Mat interior = valid_area_mask(plan, nav.grid);
  nav.clearance = distance_to_blocked_m(blocked, nav.grid);
  nav.free = cv::Mat::zeros(nav.grid.height_px, nav.grid.width_px, CV_8U);
  for (int r = 0; r < nav.grid.height_px; ++r) {
    const std::uint8_t* in = interior.ptr<std::uint8_t>(r);
    const std::uint8_t* bl = blocked.ptr<std::uint8_t>(r);
    const float* d = nav.clearance.ptr<float>(r);
    std::uint8_t* f = nav.free.ptr<std::uint8_t>(r);
    for (int c = 0; c < nav.grid.width_px; ++c) {
      f[c] = (in[c] && !bl[c] && d[c] >= p.clearance_m) ? 255 : 0;
    }
  }
  return nav;
}

/// Dijkstra over the 8-connected free cells (diagonals only where both orthogonal neighbours are
/// free: no squeezing past a corner), cost = step length x the centre-preference factor.
struct CostField {
  std::vector<double> cost;  ///< per cell, +inf where unreachable
  std::vector<int> parent;   ///< per cell, -1 at the source and where unreachable
};

CostField dijkstra(const NavGrid& nav, int source, const WalkParams& p) {
  const int W = nav.grid.width_px, H = nav.grid.height_px;
  const std::size_t n = static_cast<std::size_t>(W) * H;
  CostField f;
  f.cost.assign(n, std::numeric_limits<double>::infinity());
  f.parent.assign(n, -1);
  std::vector<double> factor(n, 1.0);
  for (int r = 0; r < H; ++r)
    for (int c = 0; c < W; ++c) {
      const double d = nav.clearance.at<float>(r, c);
      factor[static_cast<std::size_t>(r) * W + c] = 1.0 + p.centre_weight * std::exp(-(d - p.clearance_m) / 0.5);
    }
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  f.cost[static_cast<std::size_t>(source)] = 0.0;
  queue.push({0.0, source});
  const double res = nav.grid.resolution_m_per_px;
  static const int dr[8] = {-1, 1, 0, 0, -1, -1, 1, 1};
  static const int dc[8] = {0, 0, -1, 1, -1, 1, -1, 1};
  while (!queue.empty()) {
    const auto [cost, cell] = queue.top();
    queue.pop();
    if (cost > f.cost[static_cast<std::size_t>(cell)]) continue;
    const int r = cell / W, c = cell % W;
    for (int k = 0; k < 8; ++k) {
      const int rr = r + dr[k], cc = c + dc[k];
      if (!nav.is_free(rr, cc)) continue;
      if (k >= 4 && (!nav.is_free(r + dr[k], c) || !nav.is_free(r, c + dc[k]))) continue;
      const int next = rr * W + cc;
      const double step = (k >= 4 ? std::sqrt(2.0) : 1.0) * res;
      const double w = 0.5 * (factor[static_cast<std::size_t>(cell)] + factor[static_cast<std::size_t>(next)]);
      const double nc = cost + step * w;
      if (nc < f.cost[static_cast<std::size_t>(next)]) {
        f.cost[static_cast<std::size_t>(next)] = nc;
        f.parent[static_cast<std::size_t>(next)] = cell;
        queue.push({nc, next});
      }
    }
  }
  return f;
}

/// Shortens a grid path by line-of-sight string pulling: from each kept point, the farthest later
/// point reachable by a straight free segment.
std::vector<Vec2> string_pull(const NavGrid& nav, const std::vector<Vec2>& path) {
  std::vector<Vec2> out;
  if (path.empty()) return out;
  out.push_back(path.front());
  std::size_t i = 0;
  while (i + 1 < path.size()) {
    std::size_t j = path.size() - 1;
    while (j > i + 1 && !nav.segment_free(path[i], path[j])) --j;
    out.push_back(path[j]);
    i = j;
  }
  return out;
}

/// Replaces each corner by a quadratic Bezier arc (up to corner_radius from the corner along both
/// legs) where the arc stays in free space; returns a dense polyline (points every ~5 cm).
std::vector<Vec2> round_corners(const NavGrid& nav, const std::vector<Vec2>& poly, double radius_m) {
  if (poly.size() < 3) return poly;
  std::vector<Vec2> out{poly.front()};
  auto add_line = [&](const Vec2& to) {
    const Vec2 from = out.back();
    const int n = std::max(1, static_cast<int>(std::ceil((to - from).norm() / 0.05)));
    for (int k = 1; k <= n; ++k) out.push_back(from + (to - from) * (static_cast<double>(k) / n));
  };
  for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
    const Vec2 a = out.back(), b = poly[i], c = poly[i + 1];
    const double r = std::min({radius_m, 0.5 * (b - a).norm(), 0.5 * (c - b).norm()});
    const Vec2 p0 = b + (a - b).normalized() * r, p2 = b + (c - b).normalized() * r;
    std::vector<Vec2> arc;
    for (int k = 0; k <= 12; ++k) {
      const double t = k / 12.0;
      arc.push_back((1 - t) * (1 - t) * p0 + 2 * (1 - t) * t * b + t * t * p2);
    }
    bool ok = r > 1e-6 && nav.segment_free(a, p0);
    for (std::size_t k = 1; ok && k < arc.size(); ++k) ok = nav.segment_free(arc[k - 1], arc[k]);
    if (ok) {
      add_line(p0);
      for (std::size_t k = 1; k < arc.size(); ++k) out.push_back(arc[k]);
    } else {
      add_line(b);
    }
  }
  add_line(poly.back());
  return out;
}

/// Arc-length parametrised polyline.
class Route {
 public:
  explicit Route(std::vector<Vec2> pts) : pts_(std::move(pts)) {
    s_.assign(pts_.size(), 0.0);
    for (std::size_t i = 1; i < pts_.size(); ++i) s_[i] = s_[i - 1] + (pts_[i] - pts_[i - 1]).norm();
  }
  double length() const { return s_.empty() ? 0.0 : s_.back(); }
  Vec2 at(double s) const {
    if (pts_.size() == 1 || s <= 0.0) return pts_.front();
    if (s >= length()) return pts_.back();
    const auto it = std::upper_bound(s_.begin(), s_.end(), s);
    const std::size_t i = static_cast<std::size_t>(it - s_.begin());
    const double seg = s_[i] - s_[i - 1];
    const double t = seg > 0.0 ? (s - s_[i - 1]) / seg : 0.0;
    return pts_[i - 1] + (pts_[i] - pts_[i - 1]) * t;
  }
  /// Direction of travel around s (a chord of +-0.3 m), or nullopt on a degenerate route.
  std::optional<double> heading_at(double s) const {
    const Vec2 d = at(std::min(s + 0.3, length())) - at(std::max(s - 0.3, 0.0));
    if (d.norm() < 1e-6) return std::nullopt;
    return std::atan2(d.y(), d.x());
  }
  const std::vector<Vec2>& points() const { return pts_; }

 private:
  std::vector<Vec2> pts_;
  std::vector<double> s_;
};

int cell_index(const NavGrid& nav, const Vec2& p) {
  int r = 0, c = 0;
  if (!nav.grid.world_to_cell(p, r, c)) return -1;
  return r * nav.grid.width_px + c;
}

}  // namespace

const FieldList<WalkParams>& WalkParams::fields() {
  using P = WalkParams;
  static const FieldList<P> f =
      FieldList<P>("walk")
          .integer("steps", &P::steps, 2, 1000000, "step samples of the walk, pauses included (PALMS walks: 100-200)")
          .number("clearance_m", &P::clearance_m, 0.0, 5.0, "minimum distance of the path from walls, doors, glass, furniture, m")
          .number("speed_min_mps", &P::speed_min_mps, 0.1, 5.0, "walking speed, drawn once per walk: lowest, m/s")
          .number("speed_max_mps", &P::speed_max_mps, 0.1, 5.0, "walking speed: highest, m/s")
          .number("cadence_min_hz", &P::cadence_min_hz, 0.2, 5.0, "step frequency, drawn once per walk: lowest, Hz")
          .number("cadence_max_hz", &P::cadence_max_hz, 0.2, 5.0, "step frequency: highest, Hz")
          .number("step_variation_rel", &P::step_variation_rel, 0.0, 0.5, "per-step variation of length and duration (relative sigma)")
          .number("max_turn_rate_dps", &P::max_turn_rate_dps, 1.0, 3600.0, "largest heading change rate, deg/s")
          .number("pause_probability", &P::pause_probability, 0.0, 1.0, "probability of a pause after a step")
          .number("pause_min_s", &P::pause_min_s, 0.0, 600.0, "shortest pause, s")
          .number("pause_max_s", &P::pause_max_s, 0.0, 600.0, "longest pause, s")
          .number("min_goal_distance_m", &P::min_goal_distance_m, 0.0, 1e4, "goals at least this far along the free space, m")
          .number("transitional_clearance_m", &P::transitional_clearance_m, 0.0, 20.0,
                  "cells with this much clearance are transitional space (corridors, lobbies), m")
          .number("transitional_goal_share", &P::transitional_goal_share, 0.0, 1.0, "share of goals in transitional space")
          .number("centre_weight", &P::centre_weight, 0.0, 100.0, "walkers keep to the middle of corridors by this weight")
          .number("resolution_m", &P::resolution_m, 0.02, 1.0, "navigation grid resolution, m")
          .number("corner_radius_m", &P::corner_radius_m, 0.0, 10.0, "radius of the arcs replacing route corners, m")
          .unsigned_integer("seed", &P::seed, "random seed")
          .check([](const P& p, const ParamReader& r) {
            if (p.speed_min_mps > p.speed_max_mps) r.fail("speed_min_mps", "larger than speed_max_mps");
            if (p.cadence_min_hz > p.cadence_max_hz) r.fail("cadence_min_hz", "larger than cadence_max_hz");
            if (p.pause_min_s > p.pause_max_s) r.fail("pause_min_s", "larger than pause_max_s");
          });
  return f;
}

nlohmann::ordered_json WalkParams::to_json() const { return fields().write(*this); }

const FieldList<ObservationSchedule>& schedule_fields() {
  using S = ObservationSchedule;
  static const FieldList<S> f =
      FieldList<S>("schedule")
          .flag("initial", &S::initial, "an observation at the start (PALMS: scan, then walk)")
          .integer("every_steps", &S::every_steps, 0, 1000000, "then one every N steps (0 = never)")
          .number("every_m", &S::every_m, 0.0, 1e6, "then one every N metres walked (0 = never)");
  return f;
}

void WalkParams::apply_overrides(const nlohmann::json& overrides) { fields().read(*this, overrides); }

BlockingOptions walker_blocking() {
  BlockingOptions b;
  b.closed_doors_block = true;
  b.open_doors_block = false;
  b.glass_blocks = true;
  b.obstacles_block = true;
  b.cut_height_m = 0.01;
  return b;
}

Pose2 random_start_pose(const FloorPlan& plan, const WalkParams& params) {
  const NavGrid nav = make_nav_grid(plan, params);
  // Start in the largest connected free region (a walk that starts in a room behind a closed
  // door could never leave it).
  cv::Mat labels;
  const int n = cv::connectedComponents(nav.free, labels, 8, CV_32S);
  std::vector<int> size(static_cast<std::size_t>(std::max(n, 1)), 0);
  for (int r = 0; r < labels.rows; ++r)
    for (int c = 0; c < labels.cols; ++c) ++size[static_cast<std::size_t>(labels.at<int>(r, c))];
  int largest = 0;
  for (int l = 1; l < n; ++l)
    if (largest == 0 || size[static_cast<std::size_t>(l)] > size[static_cast<std::size_t>(largest)]) largest = l;
  std::vector<int> cells;
  for (int r = 0; r < nav.grid.height_px; ++r)
    for (int c = 0; c < nav.grid.width_px; ++c)
      if (largest > 0 && labels.at<int>(r, c) == largest) cells.push_back(r * nav.grid.width_px + c);
  if (cells.empty()) {
    throw InputError("plan \"" + plan.name + "\": no free space with " + format_fixed(params.clearance_m, 2) + " m" +
                     " clearance to start a walk in");
  }
  const CounterRng rng(params.seed, kStreamStart);
  const int cell = cells[static_cast<std::size_t>(rng.uniform(0) * static_cast<double>(cells.size()))];
  const Vec2 p = nav.grid.cell_center_m(cell / nav.grid.width_px, cell % nav.grid.width_px);
  return {p.x(), p.y(), wrap_angle_rad(kTwoPi * rng.uniform(1))};
}

Walk simulate_walk(const FloorPlan& plan, const Pose2& start, const WalkParams& p) {
  Walk walk;
  walk.params = p;
  const NavGrid nav = make_nav_grid(plan, p);
  const int W = nav.grid.width_px;
  const int start_cell = cell_index(nav, start.position_m());
  if (start_cell < 0 || !nav.free.at<std::uint8_t>(start_cell / W, start_cell % W)) {
    throw InputError("plan \"" + plan.name + "\": walk start (" + format_fixed(start.x_m, 2) + ", " +
                     format_fixed(start.y_m, 2) + ") is not in free space with " + format_fixed(p.clearance_m, 2) + " m" +
                     " clearance from walls, closed doors, glass and furniture");
  }
  // Gait of this walk.
  const CounterRng gait(p.seed, kStreamGait);
  const double speed = p.speed_min_mps + (p.speed_max_mps - p.speed_min_mps) * gait.uniform(0);
  const double cadence = p.cadence_min_hz + (p.cadence_max_hz - p.cadence_min_hz) * gait.uniform(1);
  const double step_len = speed / cadence;
  const double need_m = step_len * p.steps * 1.1 + 1.0;

  // Route: goal after goal until it is long enough.
  std::vector<Vec2> route{start.position_m()};
  double route_len = 0.0;
  int cell = start_cell;
  for (int g = 0; route_len < need_m && g < 64; ++g) {
    const CostField field = dijkstra(nav, cell, p);
    std::vector<int> far, far_transitional, reachable;
    for (std::size_t i = 0; i < field.cost.size(); ++i) {
      if (!std::isfinite(field.cost[i]) || static_cast<int>(i) == cell) continue;
      reachable.push_back(static_cast<int>(i));
      if (field.cost[i] < p.min_goal_distance_m) continue;
      far.push_back(static_cast<int>(i));
      if (nav.clearance.at<float>(static_cast<int>(i) / W, static_cast<int>(i) % W) >= p.transitional_clearance_m) {
        far_transitional.push_back(static_cast<int>(i));
      }
    }
    if (reachable.empty()) {
      if (g == 0) throw InputError("plan \"" + plan.name + "\": nothing reachable from the walk start");
      break;
    }
    const CounterRng rng(p.seed, kStreamGoal, static_cast<std::uint64_t>(g));
    if (far.empty()) {  // a small building: the farthest fifth of what is reachable
      std::sort(reachable.begin(), reachable.end(), [&](int a, int b) {
        return field.cost[static_cast<std::size_t>(a)] > field.cost[static_cast<std::size_t>(b)];
      });
      far.assign(reachable.begin(), reachable.begin() + static_cast<std::ptrdiff_t>(std::max<std::size_t>(1, reachable.size() / 5)));
    }
    const std::vector<int>& pool =
        (!far_transitional.empty() && rng.uniform(0) < p.transitional_goal_share) ? far_transitional : far;
    const int goal = pool[static_cast<std::size_t>(rng.uniform(1) * static_cast<double>(pool.size()))];
    std::vector<Vec2> leg;
    for (int c = goal; c != -1; c = field.parent[static_cast<std::size_t>(c)]) leg.push_back(nav.grid.cell_center_m(c / W, c % W));
    std::reverse(leg.begin(), leg.end());
    leg.front() = route.back();  // continue exactly where the last leg ended
    const std::vector<Vec2> pulled = string_pull(nav, leg);
    for (std::size_t i = 1; i < pulled.size(); ++i) {
      route_len += (pulled[i] - route.back()).norm();
      route.push_back(pulled[i]);
    }
    cell = goal;
    walk.summary.goals = g + 1;
  }
  const Route path(round_corners(nav, route, p.corner_radius_m));
  walk.route_m = path.points();

  // The walker: steps along the route, heading following the direction of travel at a human turn
  // rate, occasional pauses.
  WalkStep first;
  first.T_world_body = start;
  first.moving = false;
  walk.steps.push_back(first);
  double s = 0.0, t = 0.0, heading = start.yaw_rad;
  double turned = 0.0;
  int k = 0;
  while (static_cast<int>(walk.steps.size()) < p.steps) {
    const CounterRng rng(p.seed, kStreamStep, static_cast<std::uint64_t>(k++));
    const double dt = (1.0 / cadence) * (1.0 + p.step_variation_rel * rng.normal(0));
    const double len = std::max(0.05, step_len * (1.0 + p.step_variation_rel * rng.normal(1)));
    const double s_next = std::min(s + len, path.length());
    const double before = heading;
    if (const std::optional<double> want = path.heading_at(s_next)) {
      const double max_turn = deg_to_rad(p.max_turn_rate_dps) * dt;
      heading = wrap_angle_rad(heading + std::clamp(wrap_angle_rad(*want - heading), -max_turn, max_turn));
    }
    turned += std::abs(wrap_angle_rad(heading - before));
    t += dt;
    WalkStep step;
    step.t_s = t;
    const Vec2 pos = path.at(s_next);
    step.T_world_body = {pos.x(), pos.y(), heading};
    step.step_length_m = (pos - path.at(s)).norm();
    step.moving = step.step_length_m > 0.0;
    s = s_next;
    walk.steps.push_back(step);
    // A pause: the walker stands for a while (samples at the step rate, no motion).
    const CounterRng pause(p.seed, kStreamPause, static_cast<std::uint64_t>(k));
    if (pause.uniform(0) < p.pause_probability) {
      const double duration = p.pause_min_s + (p.pause_max_s - p.pause_min_s) * pause.uniform(1);
      const int n = std::max(1, static_cast<int>(std::lround(duration * cadence)));
      ++walk.summary.pauses;
      for (int i = 0; i < n && static_cast<int>(walk.steps.size()) < p.steps; ++i) {
        t += 1.0 / cadence;
        WalkStep still = walk.steps.back();
        still.t_s = t;
        still.moving = false;
        still.step_length_m = 0.0;
        walk.steps.push_back(still);
      }
    }
  }

  // Summary.
  WalkSummary& sm = walk.summary;
  sm.speed_mps = speed;
  sm.cadence_hz = cadence;
  sm.duration_s = walk.steps.back().t_s;
  sm.total_turn_deg = rad_to_deg(turned);
  int transitional = 0;
  double straight = 0.0;
  double straight_heading = walk.steps.front().T_world_body.yaw_rad;
  for (std::size_t i = 0; i < walk.steps.size(); ++i) {
    const WalkStep& w = walk.steps[i];
    sm.length_m += w.step_length_m;
    int r = 0, c = 0;
    if (nav.grid.world_to_cell(w.T_world_body.position_m(), r, c) && nav.clearance.at<float>(r, c) >= p.transitional_clearance_m) {
      ++transitional;
    }
    if (w.step_length_m <= 0.0) continue;
    if (angle_distance_rad(w.T_world_body.yaw_rad, straight_heading) > deg_to_rad(20.0)) {
      straight = 0.0;
      straight_heading = w.T_world_body.yaw_rad;
    }
    straight += w.step_length_m;
    sm.longest_straight_m = std::max(sm.longest_straight_m, straight);
  }
  sm.transitional_share = static_cast<double>(transitional) / static_cast<double>(walk.steps.size());
  return walk;
}

std::vector<int> schedule_observations(const Walk& walk, const ObservationSchedule& schedule) {
  std::vector<int> out;
  if (walk.steps.empty()) return out;
  if (schedule.initial) out.push_back(0);
  double since = 0.0;
  for (std::size_t i = 1; i < walk.steps.size(); ++i) {
    since += walk.steps[i].step_length_m;
    bool take = schedule.every_steps > 0 && static_cast<int>(i) % schedule.every_steps == 0;
    if (schedule.every_m > 0.0 && since >= schedule.every_m) {
      take = true;
    }
    if (take) {
      out.push_back(static_cast<int>(i));
      since = 0.0;
    }
  }
  return out;
}

}  // namespace floorcast
