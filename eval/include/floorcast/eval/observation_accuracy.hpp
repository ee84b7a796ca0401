// Accuracy of observed 2D wall segments against ground truth (e.g. the perfect observation of the
// same pose at the sensor's range): how much of the visible wall length is recovered, how much of
// the observed length lies on true walls, and the angle and offset errors of the segments that
// do. Used by `floorcast bench walls` and the observation-module tests.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "floorcast/core/types.hpp"

namespace floorcast {

struct SegmentAccuracyParams {
  /// A point sampled on one segment lies on a segment of the other set when it is within
  /// max_distance_m of it and their directions differ by at most max_angle_deg (so a segment
  /// also "recovers" up to max_distance_m of wall beyond each of its ends).
  double max_distance_m = 0.2;
  double max_angle_deg = 10.0;
  double sample_step_m = 0.05;  ///< segments are sampled at (at most) this spacing
  /// An observed segment with less than this fraction of its length on true walls is spurious.
  double min_on_truth_fraction = 0.5;
};

struct SegmentAccuracy {
  double truth_length_m = 0.0;
  double recovered_length_m = 0.0;  ///< truth length with an observed segment on it
  double observed_length_m = 0.0;
  double on_truth_length_m = 0.0;   ///< observed length lying on true walls
  int segments = 0;
  int spurious_segments = 0;
  /// Per non-spurious observed segment: direction error against the true segment most of its
  /// samples lie on, and the median distance of its samples to the true walls.
  std::vector<double> angle_errors_deg;
  std::vector<double> offset_errors_m;

  double recall() const { return truth_length_m > 0.0 ? recovered_length_m / truth_length_m : 0.0; }
  double precision() const { return observed_length_m > 0.0 ? on_truth_length_m / observed_length_m : 0.0; }
  /// Sums lengths and counts, concatenates the error lists.
  void add(const SegmentAccuracy& other);
};

SegmentAccuracy segment_accuracy(const std::vector<Segment2>& observed, const std::vector<Segment2>& truth,
                                 const SegmentAccuracyParams& params = {});

/// Fraction of the truth length that has at least one of `points_m` within max_distance_m: what
/// any segment extractor working on these points could recover at best.
double point_coverage(const std::vector<Eigen::Vector2d>& points_m, const std::vector<Segment2>& truth,
                      double max_distance_m, double sample_step_m = 0.05);

}  // namespace floorcast
