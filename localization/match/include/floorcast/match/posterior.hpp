// The common output of every matcher: scores over (x, y) x orientation.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "floorcast/floorplans/raster.hpp"

namespace floorcast {

/// One pose hypothesis: world position, world yaw of the observer's heading, its score.
struct PoseHypothesis {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
  double score = 0.0;
  /// Where it came from in the posterior (-1 when not from a posterior cell).
  int slice = -1;
  int row = -1;
  int col = -1;
};

struct Posterior {
  /// The (x, y) grid; cell (r, c) of every slice is the observer at grid.cell_center_m(r, c).
  GridSpec grid;
  /// World yaw of the observer for each orientation slice.
  std::vector<double> yaw_rad;
  /// One CV_32F grid.height_px x grid.width_px map per slice; finite, >= 0, 0 outside the
  /// valid area. Unnormalised scores (higher is better).
  std::vector<cv::Mat> scores;

  int num_slices() const { return static_cast<int>(scores.size()); }

  /// Best cell over all slices (ties: lowest slice, then row, then column). A posterior whose
  /// scores are all zero returns score 0 at slice 0, cell (0, 0); an empty one throws.
  PoseHypothesis argmax() const;
  /// Up to k modes by greedy non-maximum suppression in descending score order: a candidate is
  /// dropped when an accepted mode lies within min_separation_m (distance <=) AND within
  /// min_separation_rad (angular distance <=) of it. Only cells with score > 0 are modes; ties are
  /// taken in argmax order.
  std::vector<PoseHypothesis> top_k(int k, double min_separation_m = 1.0,
                                    double min_separation_rad = 0.5235987755982988) const;
  /// Up to k local maxima as the floor-plan localization thesis finds its top-K peaks (seed paper
  /// 004, sec. 5.3: a maximum filter of 5 x 5 x 3 cells, 1 m x 1 m x 30 deg on its 0.2 m grid, over
  /// the whole volume with circular padding in yaw): a cell is a peak when its score is > 0 and no
  /// cell within +-half_cells rows and columns and +-half_slices slices (circular) scores higher;
  /// peaks in descending score order, ties in argmax order.
  std::vector<PoseHypothesis> maximum_filter_peaks(int k, int half_cells, int half_slices) const;
  /// Max over orientation, CV_32F.
  cv::Mat max_over_yaw() const;
  /// Scores divided by their total over all slices (a PDF over cells x slices); all zeros stay
  /// zeros.
  std::vector<cv::Mat> normalised_pdf() const;
  /// Sum of all scores (double accumulation).
  double total() const;
  /// Throws std::invalid_argument when slices, yaws and grid disagree or a score is negative or
  /// not finite.
  void check() const;
};

}  // namespace floorcast
