// Orientation candidates of the kernel matcher: which world yaws of the observer to test.
//
// A candidate yaw psi rotates observer-frame segments into world-aligned displacements
// (p_world - p_observer = R(psi) p_observer_frame); psi is the observer's heading in the world.
//
// - palms  (PALMS sec. III-A): principal orientation of the observed segments and of the plan
//   (modulo 90 deg), theta = the smallest rotation aligning them, candidates theta + k * 90 deg.
// - palms+ (PALMS+ sec. 3.3 and supplementary A.1): length-weighted histograms of segment
//   directions over [0, 180) deg (360 bins), circular cross-correlation of plan and observation
//   histograms, greedy non-maximum suppression (radius 10 bins), the best O/2 shifts plus their
//   180 deg complements (O = 10 stationary). Only shifts with a positive correlation count, so
//   clean observations of a plan with few wall directions give fewer than O candidates.
// - dense  (F3Loc-style, and PALMS as run in PALMS+ sec. 4.2): every step (10 deg).
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "floorcast/core/fields.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {

enum class OrientationMode { kPalms, kPalmsPlus, kDense };

/// Names of the modes: "palms", "palms+", "dense".
const std::vector<std::pair<const char*, OrientationMode>>& orientation_mode_names();
std::string orientation_mode_name(OrientationMode mode);

struct OrientationParams {
  OrientationMode mode = OrientationMode::kPalmsPlus;
  /// PALMS+ O: number of candidates (O/2 histogram peaks + their 180 deg complements); O = 10 for
  /// stationary localization (PALMS+ sec. 3.3; configs/pp_custom_config.yaml orn_slice: 10).
  int num_orientations = 10;
  /// Histogram bins over [0, 180) deg (PALMS+ code: 360, i.e. 0.5 deg bins).
  int histogram_bins = 360;
  /// Greedy NMS radius on the circular correlation, bins (PALMS+ code: 10 bins = 5 deg).
  int nms_radius_bins = 10;
  /// Dense mode step (F3Loc: 36 orientations, 10 deg).
  double dense_step_deg = 10.0;
  /// palms / palms+: refine each candidate to the yaw (within one bin) that best aligns the
  /// observed directions with the plan's (refine_orientation). Not in PALMS+ (its 0.5 deg bins
  /// leave up to 0.5 deg of yaw error, 6 cm at the 7 m reach of the CES); off by default: it made
  /// no measurable difference on the shipped buildings.
  bool refine = false;
};

/// An angle in [0, 2 pi) (candidate yaws are given in this range).
double wrap_2pi(double a_rad);

/// Its fields as the kernel matcher's parameters name them ("orientations", "num_orientations",
/// "histogram_bins", "nms_radius_bins", "dense_step_deg", "refine_orientations").
const FieldList<OrientationParams>& orientation_fields();

/// Length-weighted histogram of segment directions folded into [0, 180) deg: bin
/// floor(direction / (180 deg / bins)). Zero-length segments are ignored.
std::vector<double> direction_histogram(const std::vector<Segment2>& segments, int bins);

/// Circular cross-correlation c[s] = sum_k plan[(k + s) mod B] * obs[k]: how well the
/// observation's directions, rotated by s bins, agree with the plan's.
std::vector<double> circular_correlation(const std::vector<double>& plan_hist, const std::vector<double>& obs_hist);

/// Greedy NMS on a circular signal: repeatedly the largest remaining value (ties: lowest index)
/// whose circular distance to every accepted peak exceeds radius; at most max_peaks, only
/// values > 0.
std::vector<int> circular_peaks(const std::vector<double>& signal, int radius, int max_peaks);

/// The plan's main wall directions: peaks of its direction histogram (circular_peaks with
/// nms_radius_bins) holding at least min_share of the largest peak, as directions in [0, 180) deg,
/// largest first. PALMS+ tests O/2 alignments of an observation with them (orientation_candidates):
/// a plan with more main directions than that leaves some observers' headings untested (the
/// angled archetype, 6-8 of them: 22-26% of points; results/realplans_vs_generated.md).
std::vector<double> main_wall_directions_deg(const std::vector<double>& histogram, int nms_radius_bins,
                                             double min_share = 0.1);

/// What a user of these orientation candidates on a plan with this histogram should know: empty,
/// or one sentence when the plan has more main wall directions (main_wall_directions_deg) than the
/// mode tests per observation (palms+: num_orientations / 2 alignments; palms: one, plus quarter
/// turns, i.e. a Manhattan plan); dense tests every heading.
std::vector<std::string> orientation_notes(const OrientationParams& params, const std::vector<double>& plan_histogram);

/// Principal orientation modulo 90 deg, in [0, pi/2): the mode of the length-weighted direction
/// histogram folded to 90 deg (bins of 90/bins90 deg, smoothed circularly with a 3-bin box),
/// refined to the length-weighted circular mean of the directions within 2.5 bins of it.
double principal_orientation_rad(const std::vector<Segment2>& segments, int bins90 = 180);

/// Candidate world yaws of the observer, in [0, 2 pi), in the order they were found (best
/// first for palms+). plan_segments are the plan's wall surfaces (world frame), obs_segments
/// the observation (observer frame). Plans and observations without segments give the dense set.
std::vector<double> orientation_candidates(const OrientationParams& params, const std::vector<Segment2>& plan_segments,
                                           const std::vector<Segment2>& obs_segments);

/// Same, with the plan's histogram (palms+) / principal orientation (palms) precomputed.
struct PlanOrientationCache {
  std::vector<double> histogram;     ///< direction_histogram(plan, params.histogram_bins)
  double principal_rad = 0.0;        ///< principal_orientation_rad(plan)
  bool has_segments = false;
  /// Distinct wall directions in [0, pi) with their total length (for refinement).
  std::vector<std::pair<double, double>> directions;
};

/// The yaw within +-half_window_rad of yaw_rad maximising sum_ij l_i L_j tri((theta_i + yaw -
/// phi_j) mod pi) (tri: triangle of half-width kernel_rad), on a 0.01 deg grid, ties to the
/// closest to yaw_rad; theta_i, l_i: observed directions and lengths, phi_j, L_j: the plan's.
/// Exact data give the exact yaw.
double refine_orientation(const std::vector<std::pair<double, double>>& plan_directions,
                          const std::vector<Segment2>& obs_segments, double yaw_rad, double half_window_rad,
                          double kernel_rad);
PlanOrientationCache make_plan_orientation_cache(const OrientationParams& params,
                                                 const std::vector<Segment2>& plan_segments);

/// PALMS' find_principal_orientations (utils/geometry_utils.py), arithmetic for arithmetic: each
/// segment's direction folded into [-pi/2, pi/2]; bin k of num_bins (theta_k = -pi/2 + k * 180 /
/// num_bins deg) sums the lengths of the segments within +-threshold of theta_k, its window ends
/// wrapped by the code's own formulas (Python // and % on floats); the best k in the first half by
/// bins[k] + bins[k + num_bins / 2]. Returns {best, best + pi/2 wrapped as the code wraps it}.
std::array<double, 2> palms_principal_orientations(const std::vector<Segment2>& segments, int num_bins,
                                                   double threshold_rad);

/// The rotation PALMS applies to a floor plan before rasterising it (rotate_segments_to_landscape:
/// principal orientations with 360 bins and a 0.5 deg threshold; the second one turned onto 0, or
/// onto +-90 deg when the plan would then be taller than wide).
double palms_landscape_rotation_rad(const std::vector<Segment2>& plan_segments);
std::vector<double> orientation_candidates(const OrientationParams& params, const PlanOrientationCache& plan,
                                           const std::vector<Segment2>& obs_segments);

}  // namespace floorcast
