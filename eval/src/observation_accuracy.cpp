// Observed wall segments against ground truth, by sampling both sets along their length.
#include "floorcast/eval/observation_accuracy.hpp"

#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/core/math.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <unordered_map>

namespace floorcast {
namespace {


struct Sample {
  Vec2 p;
  double weight_m;  ///< length this sample stands for
};

std::vector<Sample> sample_segment(const Segment2& s, double step_m) {
  const double len = s.length_m();
  std::vector<Sample> out;
  if (!(len > 0.0)) return out;
  const int n = std::max(1, static_cast<int>(std::ceil(len / std::max(1e-6, step_m))));
  for (int k = 0; k < n; ++k) {
    const double f = (k + 0.5) / n;
    out.push_back({s.a_m + f * (s.b_m - s.a_m), len / n});
  }
  return out;
}

/// Undirected angle between two segment directions, degrees in [0, 90].
double direction_difference_deg(const Segment2& a, const Segment2& b) {
  return std::abs(std::remainder(a.direction_rad() - b.direction_rad(), kPi)) * 180.0 / kPi;
}

/// Index of the nearest segment of `set` that is compatible in direction with `dir` and within
/// max_distance of p (-1 if none); its distance in *dist.
int nearest_compatible(const Vec2& p, const Segment2& dir, const std::vector<Segment2>& set,
                       const SegmentAccuracyParams& params, double* dist) {
  int best = -1;
  double best_d = params.max_distance_m;
  for (std::size_t k = 0; k < set.size(); ++k) {
    if (!(set[k].length_m() > 0.0)) continue;
    if (direction_difference_deg(dir, set[k]) > params.max_angle_deg) continue;
    const double d = point_segment_distance(p, set[k]);
    if (d <= best_d) {
      best_d = d;
      best = static_cast<int>(k);
    }
  }
  if (dist) *dist = best_d;
  return best;
}

}  // namespace

void SegmentAccuracy::add(const SegmentAccuracy& o) {
  truth_length_m += o.truth_length_m;
  recovered_length_m += o.recovered_length_m;
  observed_length_m += o.observed_length_m;
  on_truth_length_m += o.on_truth_length_m;
  segments += o.segments;
  spurious_segments += o.spurious_segments;
  angle_errors_deg.insert(angle_errors_deg.end(), o.angle_errors_deg.begin(), o.angle_errors_deg.end());
  offset_errors_m.insert(offset_errors_m.end(), o.offset_errors_m.begin(), o.offset_errors_m.end());
}

SegmentAccuracy segment_accuracy(const std::vector<Segment2>& observed, const std::vector<Segment2>& truth,
                                 const SegmentAccuracyParams& params) {
  SegmentAccuracy acc;
  for (const Segment2& t : truth) {
    for (const Sample& s : sample_segment(t, params.sample_step_m)) {
      acc.truth_length_m += s.weight_m;
      if (nearest_compatible(s.p, t, observed, params, nullptr) >= 0) acc.recovered_length_m += s.weight_m;
    }
  }
  for (const Segment2& o : observed) {
    const std::vector<Sample> samples = sample_segment(o, params.sample_step_m);
    if (samples.empty()) continue;
    ++acc.segments;
    double len = 0.0, on = 0.0;
    std::vector<double> dists;
    std::map<int, double> on_truth;  // truth segment -> observed length on it
    for (const Sample& s : samples) {
      len += s.weight_m;
      double d = 0.0;
      const int k = nearest_compatible(s.p, o, truth, params, &d);
      if (k < 0) continue;
      on += s.weight_m;
      dists.push_back(d);
      on_truth[k] += s.weight_m;
    }
    acc.observed_length_m += len;
    acc.on_truth_length_m += on;
    if (on < params.min_on_truth_fraction * len) {
      ++acc.spurious_segments;
      continue;
    }
    int main_truth = on_truth.begin()->first;
    for (const auto& [k, l] : on_truth) {
      if (l > on_truth[main_truth]) main_truth = k;
    }
    acc.angle_errors_deg.push_back(direction_difference_deg(o, truth[static_cast<std::size_t>(main_truth)]));
    acc.offset_errors_m.push_back(median(dists));
  }
  return acc;
}

double point_coverage(const std::vector<Eigen::Vector2d>& points_m, const std::vector<Segment2>& truth,
                      double max_distance_m, double sample_step_m) {
  if (!(max_distance_m > 0.0)) return 0.0;
  // Points hashed into cells of max_distance_m: a sample's neighbours are in its 3x3 cells.
  const double cell = max_distance_m;
  auto key = [](std::int64_t x, std::int64_t y) { return (x << 32) ^ (y & 0xffffffffLL); };
  std::unordered_map<std::int64_t, std::vector<int>> grid;
  for (std::size_t i = 0; i < points_m.size(); ++i) {
    grid[key(static_cast<std::int64_t>(std::floor(points_m[i].x() / cell)),
             static_cast<std::int64_t>(std::floor(points_m[i].y() / cell)))]
        .push_back(static_cast<int>(i));
  }
  double total = 0.0, covered = 0.0;
  for (const Segment2& t : truth) {
    for (const Sample& s : sample_segment(t, sample_step_m)) {
      total += s.weight_m;
      const auto cx = static_cast<std::int64_t>(std::floor(s.p.x() / cell));
      const auto cy = static_cast<std::int64_t>(std::floor(s.p.y() / cell));
      bool hit = false;
      for (std::int64_t dx = -1; dx <= 1 && !hit; ++dx)
        for (std::int64_t dy = -1; dy <= 1 && !hit; ++dy) {
          const auto it = grid.find(key(cx + dx, cy + dy));
          if (it == grid.end()) continue;
          for (int i : it->second) {
            if ((points_m[static_cast<std::size_t>(i)] - s.p).norm() <= max_distance_m) {
              hit = true;
              break;
            }
          }
        }
      if (hit) covered += s.weight_m;
    }
  }
  return total > 0.0 ? covered / total : 0.0;
}

}  // namespace floorcast
