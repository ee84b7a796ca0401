// A faithful F3Loc reference (issue 20 item 3): F3Loc's desdf ray cast and localize() written
// out from its published code (utils/utils.py ray_cast, utils/generate_desdf.py raycast_desdf,
// utils/localization_utils.py localize; facts in ../shared/reference/f3loc.md), slow and obvious:
// a per-pixel march in doubles on a byte occupancy image (255 = free), the whole desdf, and
// localize() with its flip, circular padding, exp(-L1 / lambda), max over orientation and first
// argmax. The ray matcher in its F3Loc mode (raster distances, corner cast point, every cell,
// rays unclipped, F3Loc's ray order) must pick the same pose on >= 95% of seeded observations;
// the rest must be ties at the matcher's millimetre precision. The default mode's disagreement
// with the F3Loc mode is measured and printed (results/paper_4_4.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "floorcast/core/math.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/match/plan_raster.hpp"
#include "floorcast/match/ray_matcher.hpp"
#include "floorcast/sim/perfect_observation.hpp"
#include "match_test_plans.hpp"

namespace floorcast {
namespace {

// --- F3Loc, transcribed -------------------------------------------------------------------------

/// utils.ray_cast(occ, pos, ang, dist_max): occ is the map image (255 = free), pos = [h, w] in
/// pixels, returns pixels. Each of the eight cases as written in F3Loc.
double ref_ray_cast(const cv::Mat& occ_in, double pos0, double pos1, double ang, double dist_max) {
  const int h = occ_in.rows, w = occ_in.cols;
  // occ = 255 - occ; occupied where > 0.
  auto occupied = [&](double r, double c) { return 255 - occ_in.at<std::uint8_t>(static_cast<int>(r), static_cast<int>(c)) > 0; };
  auto norm = [&](double a, double b) { return std::sqrt((a - pos0) * (a - pos0) + (b - pos1) * (b - pos1)); };
  const double c = std::cos(ang), s = std::sin(ang);
  if (c == 1) {  // go right
    double cur0 = pos0, cur1 = pos1;
    for (;;) {
      cur1 += 1;
      if (cur1 >= w) return dist_max;
      if (occupied(cur0, cur1)) return norm(cur0, cur1);
    }
  } else if (s == 1) {  // go up
    double cur0 = pos0, cur1 = pos1;
    for (;;) {
      cur0 += 1;
      if (cur0 >= h) return dist_max;
      if (occupied(cur0, cur1)) return norm(cur0, cur1);
    }
  } else if (c == -1) {  // go left
    double cur0 = pos0, cur1 = pos1;
    for (;;) {
      cur1 -= 1;
      if (cur1 < 0) return dist_max;
      if (occupied(cur0, cur1)) return norm(cur0, cur1);
    }
  } else if (s == -1) {  // go down
    double cur0 = pos0, cur1 = pos1;
    for (;;) {
      cur0 -= 1;
      if (cur0 < 0) return dist_max;
      if (occupied(cur0, cur1)) return norm(cur0, cur1);
    }
  }
  const double t = std::tan(ang);
  if (c > 0 && s > 0) {  // go up and right
    double k0 = std::floor(pos0 + 1), k1 = std::floor(pos1 + 1);
    double cur0 = pos0, cur1 = pos1;
    for (;;) {
      const double dw = k1 - cur1, dh = k0 - cur0, corner_ang = dh / dw;
      if (t > corner_ang) {
        cur1 = cur1 + dh / t;
        cur0 = k0;
        k0 += 1;
      } else if (t < corner_ang) {
        cur0 = cur0 + dw * t;
        cur1 = k1;
        k1 += 1;
      } else {
        cur0 = k0;
        cur1 = k1;
        k0 += 1;
        k1 += 1;
      }
      if (cur0 >= h || cur1 >= w) return dist_max;
      if (occupied(cur0, cur1)) return norm(cur0, cur1);
    }
  } else if (c < 0 && s > 0) {  // go up and left
    double k0 = std::floor(pos0 + 1), k1 = std::ceil(pos1 - 1);
    double cur0 = pos0, cur1 = pos1;
    for (;;) {
      const double dw = k1 - cur1, dh = k0 - cur0, corner_ang = dh / dw;
      if (t < corner_ang) {
        cur1 = cur1 + dh / t;
        cur0 = k0;
        k0 += 1;
      } else if (t > corner_ang) {
        cur0 = cur0 + dw * t;
        cur1 = k1;
        k1 -= 1;
      } else {
        cur0 = k0;
        cur1 = k1;
        k0 += 1;
        k1 -= 1;
      }
      if (cur0 >= h || cur1 < 0) return dist_max;
      if (occupied(cur0, cur1)) return norm(cur0, cur1);
    }
  } else if (c < 0 && s < 0) {  // go down and left
    double k0 = std::ceil(pos0 - 1), k1 = std::ceil(pos1 - 1);
    double cur0 = pos0, cur1 = pos1;
    for (;;) {
      const double dw = k1 - cur1, dh = k0 - cur0, corner_ang = dh / dw;
      if (t > corner_ang) {
        cur1 = cur1 + dh / t;
        cur0 = k0;
        k0 -= 1;
      } else if (t < corner_ang) {
        cur0 = cur0 + dw * t;
        cur1 = k1;
        k1 -= 1;
      } else {
        cur0 = k0;
        cur1 = k1;
        k0 -= 1;
        k1 -= 1;
      }
      if (cur0 < 0 || cur1 < 0) return dist_max;
      if (occupied(cur0, cur1)) return norm(cur0, cur1);
    }
  }
  // c > 0 and s < 0: go down and right
  double k0 = std::ceil(pos0 - 1), k1 = std::floor(pos1 + 1);
  double cur0 = pos0, cur1 = pos1;
  for (;;) {
    const double dw = k1 - cur1, dh = k0 - cur0, corner_ang = dh / dw;
    if (t < corner_ang) {
      cur1 = cur1 + dh / t;
      cur0 = k0;
      k0 -= 1;
    } else if (t > corner_ang) {
      cur0 = cur0 + dw * t;
      cur1 = k1;
      k1 += 1;
    } else {
      cur0 = k0;
      cur1 = k1;
      k0 -= 1;
      k1 += 1;
    }
    if (cur0 < 0 || cur1 >= w) return dist_max;
    if (occupied(cur0, cur1)) return norm(cur0, cur1);
  }
}

/// generate_desdf.raycast_desdf(occ, orn_slice, max_dist, original_resolution, resolution), then
/// the evaluation's truncation on load (desdf[desdf > 10] = 10). [row][col][o], metres.
using Desdf = std::vector<std::vector<std::vector<double>>>;
Desdf ref_raycast_desdf(const cv::Mat& occ, int orn_slice, double max_dist, double original_resolution,
                        double resolution, double truncate_m) {
  const double ratio = resolution / original_resolution;
  const int H = static_cast<int>(occ.rows / ratio), W = static_cast<int>(occ.cols / ratio);
  Desdf desdf(static_cast<std::size_t>(H), std::vector<std::vector<double>>(static_cast<std::size_t>(W), std::vector<double>(static_cast<std::size_t>(orn_slice))));
  for (int o = 0; o < orn_slice; ++o) {
    const double theta = static_cast<double>(o) / orn_slice * kPi * 2;
    for (int row = 0; row < H; ++row)
      for (int col = 0; col < W; ++col) {
        const double d = ref_ray_cast(occ, row * ratio, col * ratio, theta, max_dist / original_resolution) * original_resolution;
        desdf[static_cast<std::size_t>(row)][static_cast<std::size_t>(col)][static_cast<std::size_t>(o)] = std::min(d, truncate_m);
      }
  }
  return desdf;
}

struct RefPose {
  int row = 0, col = 0, orientation = 0;
  double prob = 0.0;
};

/// localization_utils.localize(desdf, rays, orn_slice, lambd): rays are V values from left to
/// right. Returns the first maximum of prob_dist in row-major order (torch.where) and its
/// orientation (the first maximum over the orientation axis). prob(row, col, o) is also returned
/// through *prob when asked.
RefPose ref_localize(const Desdf& desdf, std::vector<double> rays, int orn_slice, double lambd,
                     std::vector<double>* prob = nullptr) {
  std::reverse(rays.begin(), rays.end());  // torch.flip: now counter-clockwise
  const int O = orn_slice, V = static_cast<int>(rays.size());
  const int pad_front = V / 2;
  const int H = static_cast<int>(desdf.size()), W = static_cast<int>(desdf[0].size());
  RefPose best;
  best.prob = -1.0;
  if (prob) prob->assign(static_cast<std::size_t>(H) * W * O, 0.0);
  for (int r = 0; r < H; ++r)
    for (int c = 0; c < W; ++c) {
      double cell_max = -1.0;
      int cell_o = 0;
      for (int i = 0; i < O; ++i) {
        // pad_desdf[i + k] = desdf[(i + k - pad_front) mod O] (circular padding).
        double l1 = 0.0;
        for (int k = 0; k < V; ++k) {
          const int d = ((i + k - pad_front) % O + O) % O;
          l1 += std::abs(desdf[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)][static_cast<std::size_t>(d)] - rays[static_cast<std::size_t>(k)]);
        }
        const double p = std::exp(-l1 / lambd);
        if (prob) (*prob)[(static_cast<std::size_t>(r) * W + c) * O + i] = p;
        if (p > cell_max) {
          cell_max = p;
          cell_o = i;
        }
      }
      if (cell_max > best.prob) {
        best.prob = cell_max;
        best.row = r;
        best.col = c;
        best.orientation = cell_o;
      }
    }
  return best;
}

// --- The comparison -------------------------------------------------------------------------------

/// F3Loc's occupancy image of a plan over the ray matcher's grid at 0.01 m (255 = free, 0 = wall,
/// rows growing with +y as the desdf's), under the matcher's blocking options.
cv::Mat f3loc_map_image(const FloorPlan& plan, const GridSpec& grid, const BlockingOptions& blocking) {
  GridSpec fine = grid;
  fine.resolution_m_per_px = grid.resolution_m_per_px / 10.0;
  fine.width_px = grid.width_px * 10;
  fine.height_px = grid.height_px * 10;
  const cv::Mat occ = rasterize_occupancy(plan, fine, blocking);
  cv::Mat img;
  cv::compare(occ, 0, img, cv::CMP_EQ);  // 255 where free
  return img;
}

struct Agreement {
  int observations = 0;
  int same = 0;
  int ties = 0;  ///< different pose, reference probability within the mm precision of its maximum
  int default_differs = 0;
  int default_differs_far = 0;  ///< more than 1 m or 30 deg apart
  int f3loc_success = 0, default_success = 0;  ///< within 1 m and 30 deg of the truth
  /// The F3Loc mode with one ingredient set back to the default: how often its pose is more than
  /// 1 m or 30 deg from the F3Loc mode's (cells valid, exact distances, centre cast point).
  int far_valid_cells = 0, far_exact = 0, far_centre = 0;
  int f3loc_outside_valid = 0;  ///< F3Loc mode's pose in a cell the default does not score
};

Agreement compare_with_reference(const FloorPlan& plan, int count, std::uint64_t seed) {
  RayMatcherParams f3;
  f3.distances = RayDistances::kRaster;
  f3.cast_point = RayCastPoint::kCorner;
  f3.cells = RayCells::kAll;
  f3.ray_convention = RayConvention::kF3Loc;
  f3.clip_observation = false;
  const RayMatcher matcher(plan, f3);
  const RayMatcher defaults(plan, RayMatcherParams{});
  RayMatcherParams p_valid = f3, p_exact = f3, p_centre = f3;
  p_valid.cells = RayCells::kValid;
  p_exact.distances = RayDistances::kExact;
  p_centre.cast_point = RayCastPoint::kCentre;
  const RayMatcher m_valid(plan, p_valid), m_exact(plan, p_exact), m_centre(plan, p_centre);
  const GridSpec& grid = matcher.grid();
  const Desdf desdf = ref_raycast_desdf(f3loc_map_image(plan, grid, f3.blocking), 36, 15.0, 0.01, 0.1, 10.0);

  PerfectObservationParams op;
  op.num_rays = 36;
  const PerfectObserver observer(plan, op);
  const cv::Mat valid = matcher_valid_mask(plan, grid, f3.blocking);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> ur(0, grid.height_px - 1), uc(0, grid.width_px - 1);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Agreement a;
  while (a.observations < count) {
    const int r = ur(rng), c = uc(rng);
    if (!valid.at<std::uint8_t>(r, c)) continue;
    const Pose2 truth{grid.origin_x_m + (c + u01(rng)) * 0.1, grid.origin_y_m + (r + u01(rng)) * 0.1, 2 * kPi * u01(rng)};
    const Observation2D obs = observer.observe(truth);
    ++a.observations;
    // F3Loc's rays: left to right (clockwise), the heading at the index localize()'s flip maps
    // onto its centre, V - 1 - V//2 = 17 of 36.
    const int V = 36, centre = V - 1 - V / 2;
    std::vector<double> given(V);
    for (int k = 0; k < V; ++k) given[static_cast<std::size_t>(k)] = obs.ray_ranges_m[static_cast<std::size_t>(((centre - k) % V + V) % V)];
    std::vector<double> prob;
    const RefPose ref = ref_localize(desdf, given, 36, 40.0, &prob);
    const MatchResult m = matcher.match(obs, MatchRequest::modes(1));
    EXPECT_FALSE(m.modes.empty());
    if (m.modes.empty()) continue;
    const PoseHypothesis& h = m.modes[0];
    if (h.row == ref.row && h.col == ref.col && h.slice == ref.orientation) {
      ++a.same;
    } else {
      // The matcher stores distances in millimetres: its L1 differs from the reference's by at
      // most 0.5 mm per ray, so its score can only reorder poses within exp(36 * 0.5 mm / 40)
      // of each other.
      const double at_matcher = prob[(static_cast<std::size_t>(h.row) * grid.width_px + h.col) * 36 + static_cast<std::size_t>(h.slice)];
      const bool tie = at_matcher >= ref.prob * std::exp(-2.0 * 36 * 0.0005 / 40.0);
      EXPECT_TRUE(tie) << "observation " << a.observations << ": reference (" << ref.row << ", " << ref.col << ", "
                       << ref.orientation << ") p " << ref.prob << ", matcher (" << h.row << ", " << h.col << ", "
                       << h.slice << ") reference p there " << at_matcher;
      if (tie) ++a.ties;
    }
    auto success = [&](const PoseHypothesis& x) {
      return std::hypot(x.x_m - truth.x_m, x.y_m - truth.y_m) <= 1.0 && angle_distance_rad(x.yaw_rad, truth.yaw_rad) <= kPi / 6;
    };
    auto far_from_f3loc = [&](const RayMatcher& other) {
      const MatchResult o = other.match(obs, MatchRequest::modes(1));
      if (o.modes.empty()) return true;
      return std::hypot(o.modes[0].x_m - h.x_m, o.modes[0].y_m - h.y_m) > 1.0 ||
             angle_distance_rad(o.modes[0].yaw_rad, h.yaw_rad) > kPi / 6;
    };
    a.f3loc_success += success(h);
    a.far_valid_cells += far_from_f3loc(m_valid);
    a.far_exact += far_from_f3loc(m_exact);
    a.far_centre += far_from_f3loc(m_centre);
    a.f3loc_outside_valid += defaults.volume().cell_index[static_cast<std::size_t>(h.row * grid.width_px + h.col)] < 0;
    const MatchResult d = defaults.match(obs, MatchRequest::modes(1));
    if (!d.modes.empty()) {
      a.default_success += success(d.modes[0]);
      const PoseHypothesis& e = d.modes[0];
      if (e.row != h.row || e.col != h.col || e.slice != h.slice) {
        ++a.default_differs;
        if (std::hypot(e.x_m - h.x_m, e.y_m - h.y_m) > 1.0 || angle_distance_rad(e.yaw_rad, h.yaw_rad) > kPi / 6)
          ++a.default_differs_far;
      }
    }
  }
  return a;
}

void report(const char* what, const Agreement& a) {
  std::printf("%s: %d observations, F3Loc mode = reference pose %d (%.1f%%), ties %d; default mode picks another "
              "pose than the F3Loc mode on %d (%d more than 1 m or 30 deg away); success @1 m 30 deg F3Loc mode %d, "
              "default %d; F3Loc mode's pose outside the default's cells %d; far from the F3Loc mode's pose with "
              "valid cells only %d, exact distances %d, centre cast point %d\n",
              what, a.observations, a.same, 100.0 * a.same / a.observations, a.ties, a.default_differs,
              a.default_differs_far, a.f3loc_success, a.default_success, a.f3loc_outside_valid, a.far_valid_cells,
              a.far_exact, a.far_centre);
}

// Ray by ray, the matcher's march (with its empty-space skip) against the transcription, on the
// corners of every cell of a plan: equal to round-off or, where a crossing passes exactly through
// a pixel corner, within a pixel.
TEST(F3LocReference, RayCastEqualsTranscription) {
  const FloorPlan plan = test::asymmetric_floor();
  const RayMatcher m(plan, RayMatcherParams{});
  const GridSpec& grid = m.grid();
  const cv::Mat img = f3loc_map_image(plan, grid, closed_door_map());
  BitRaster bits(img.cols, img.rows);
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c)
      if (img.at<std::uint8_t>(r, c) != 255) bits.set(r, c);
  const RasterSkipMap skip = make_raster_skip_map(bits, 10);
  std::size_t n = 0, exact = 0, within_px = 0;
  for (int o = 0; o < 36; ++o) {
    const double theta = static_cast<double>(o) / 36 * kPi * 2;
    for (int row = 0; row < grid.height_px; row += 3)
      for (int col = 0; col < grid.width_px; col += 3) {
        const double ref = std::min(ref_ray_cast(img, row * 10.0, col * 10.0, theta, 1500.0), 1000.0);
        const double plain = std::min(f3loc_ray_cast(bits, row * 10.0, col * 10.0, theta, 1500.0, 1002.0), 1000.0);
        const double skipped = std::min(f3loc_ray_cast(bits, row * 10.0, col * 10.0, theta, 1500.0, 1002.0, &skip), 1000.0);
        ++n;
        EXPECT_EQ(plain, ref) << "row " << row << " col " << col << " o " << o;
        if (std::abs(skipped - ref) < 1e-9) ++exact;
        if (std::abs(skipped - ref) <= 1.5) ++within_px;
      }
  }
  EXPECT_EQ(within_px, n);
  EXPECT_GT(static_cast<double>(exact) / static_cast<double>(n), 0.999) << exact << " of " << n;
  std::printf("march with skip: %zu of %zu rays equal to round-off, all within 1.5 px\n", exact, n);
}

TEST(F3LocReference, SamePoseAsLocalize) {
  const FloorPlan apartment = load_floor_plan(FLOORCAST_SOURCE_DIR "/floorplans/buildings/apartment.json");
  const Agreement a = compare_with_reference(apartment, 60, 1);
  report("apartment", a);
  const Agreement b = compare_with_reference(test::asymmetric_floor(), 40, 2);
  report("asymmetric floor", b);
  EXPECT_GE(a.same, static_cast<int>(std::ceil(0.95 * a.observations)));
  EXPECT_GE(b.same, static_cast<int>(std::ceil(0.95 * b.observations)));
  EXPECT_EQ(a.same + a.ties, a.observations);
  EXPECT_EQ(b.same + b.ties, b.observations);
}

}  // namespace
}  // namespace floorcast
