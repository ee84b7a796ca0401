// The common output of every matcher: scores over (x, y) x orientation.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "floorcast/floorplans/raster.hpp"

namespace floorcast {

/// One pose hypothesis: world position, world yaw of the observer's heading, its score.
struct PoseHypothesis {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
  double score = 0.0;
};

struct Posterior {
  /// The (x, y) grid; cell (r, c) of every slice is the observer at grid.cell_center_m(r, c).
  GridSpec grid;
  /// World yaw of the observer for each orientation slice.
  std::vector<double> yaw_rad;
  /// One CV_32F grid.height_px x grid.width_px map per slice; finite, >= 0, 0 outside the
  /// valid area. Unnormalised scores (higher is better).
  std::vector<cv::Mat> scores;

  /// Best cell over all slices (ties: lowest slice, then row, then column).
  PoseHypothesis argmax() const;
  /// Up to k modes by greedy non-maximum suppression: a candidate is dropped when an accepted
  /// mode lies within min_separation_m AND within min_separation_rad of it.
  std::vector<PoseHypothesis> top_k(int k, double min_separation_m = 1.0,
                                    double min_separation_rad = 0.5235987755982988) const;
  /// Max over orientation, CV_32F.
  cv::Mat max_over_yaw() const;
  /// Scores divided by their total over all slices (a PDF over cells x slices); all zeros stay
  /// zeros.
  std::vector<cv::Mat> normalised_pdf() const;
};

}  // namespace floorcast
