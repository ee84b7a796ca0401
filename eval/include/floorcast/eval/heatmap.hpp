// The posterior heatmap: a matcher's posterior drawn over the plan (beside the other plots of eval/).
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "floorcast/match/posterior.hpp"

namespace floorcast {

/// Drawing options of the posterior heatmap.
struct HeatmapStyle {
  /// Output pixels per posterior cell; 0 picks the largest integer keeping the map's long side at
  /// most max_side_px (at least 1).
  int pixels_per_cell = 0;
  int max_side_px = 1600;
  /// Heat is max-over-yaw divided by its maximum, raised to this power (<1 brightens weak modes).
  double gamma = 0.5;
  /// Title in the header band ("" = "Posterior, max over yaw").
  std::string title;
  /// Title band, colour bar, scale bar, legend and inset; false draws the bare map only.
  bool decorations = true;
  /// A zoomed inset (inset_window_m wide, around the truth and the estimate) is added when the
  /// plan's longer side exceeds inset_min_plan_m and the map is drawn at fewer than 12 px/m.
  double inset_min_plan_m = 60.0;
  double inset_window_m = 16.0;
  int inset_side_px = 320;
};

/// The posterior's max over yaw as a colour heatmap (turbo colour map, relative score^gamma) over
/// the plan raster (CV_8U, non-zero = wall), with the ground truth (green ring + heading) and the
/// estimate (red cross + heading) marked when given, markers sized to the picture. Decorations: a
/// title band, a colour bar (relative score), a scale bar, a legend, an "empty posterior" banner
/// when every cell scored 0, and for large plans a zoomed inset around truth and estimate (its
/// area framed on the map). Returns a CV_8UC3 BGR image with +y up. Pure: no file I/O. The plan
/// raster must be on posterior.grid.
cv::Mat render_posterior_heatmap(const Posterior& posterior, const cv::Mat& plan_raster,
                                 const std::optional<PoseHypothesis>& truth,
                                 const std::optional<PoseHypothesis>& estimate,
                                 const HeatmapStyle& style = {});

}  // namespace floorcast
