// Rasters the layout matchers correlate: wall-surface lines (about 1 px, like PALMS' Bresenham raster) and
// filled triangles, with one pixel convention shared by the plan and the observation kernels.
//
// Pixel convention: an image "anchored" at origin_m with resolution res has its pixel (col c,
// row r) covering world [origin.x + c*res, origin.x + (c+1)*res) x [origin.y + r*res, ...), i.e.
// the GridSpec convention (rows grow with +y). A world point p maps to OpenCV's continuous pixel
// coordinates ((p.x - origin.x)/res - 0.5, (p.y - origin.y)/res - 0.5).
#pragma once

#include <opencv2/core.hpp>
#include <array>
#include <vector>

#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/raster.hpp"

namespace floorcast {

/// Draws segments (value 255) into a CV_8U image: every pixel whose closed square the segment
/// touches (a "supercover" line, ~1 px thick, 2 px where it runs exactly on a pixel boundary).
/// Symmetric under quarter turns and reflections (no tie-breaking), 4-connected like PALMS'
/// "enhanced" Bresenham, and every drawn pixel contains a point of its segment (the property the
/// CES collision test relies on, see kernel_matcher.hpp). Parts outside the image are clipped.
enum class LineRule {
  kClosed,    ///< closed pixel squares: symmetric, 2 px where a line runs on a pixel boundary
  kHalfOpen,  ///< half-open squares [c - 1/2, c + 1/2): 1 px everywhere, ties to the +x / +y side
  /// PALMS' Bresenham (utils/geometry_utils.py Bresenham.seg): both ends floored to their pixel
  /// (negative indices clamped to 0), then integer Bresenham from the first to the second end,
  /// "enhanced": every minor-axis step also marks the pixel at the old major coordinate (so lines
  /// are 4-connected). Not symmetric (the line depends on which end comes first).
  kBresenham,
};
void draw_segment_lines(cv::Mat& image_8u, const std::vector<Segment2>& segments_m, const Vec2& origin_m,
                        double resolution_m_per_px, LineRule rule = LineRule::kClosed);

/// PALMS' Bresenham line (LineRule::kBresenham) between two points given in pixel coordinates
/// (pixel (c, r) covers [c, c + 1) x [r, r + 1)); pixels outside the image are skipped.
void draw_bresenham_line(cv::Mat& image_8u, double x0_px, double y0_px, double x1_px, double y1_px);

/// PALMS' valid-area mask (utils/geometry_utils.py alpha_shape, alphashape package): points
/// sampled along `lines` (every sample_m, ends included: ceil(length / sample_m) steps), their
/// Delaunay triangles with circumradius < 1 / alpha kept, holes of their union filled (shapely's
/// polygonize + unary_union); a cell is valid when its sample point (grid origin + (col +
/// sample_offset, row + sample_offset) * resolution) lies in the union (edges included). CV_8U,
/// 255 = valid. PALMS: alpha 0.15, sample 1 m, points sampled at cell corners (sample_offset 0).
cv::Mat alpha_shape_mask(const std::vector<Segment2>& lines, double alpha, double sample_m, const GridSpec& grid,
                         double sample_offset);

/// Fills triangles (value 255) into a CV_8U image: exactly the pixels whose centre lies strictly
/// inside one of them (symmetric, no tie-breaking; centres exactly on an edge are left out).
void fill_triangles(cv::Mat& image_8u, const std::vector<std::array<Vec2, 3>>& triangles_m, const Vec2& origin_m,
                    double resolution_m_per_px);

/// The plan raster of the layout matchers: the blocking outline (wall surfaces, free space on one
/// side) drawn with draw_segment_lines on `grid`. CV_8U, 255 = wall surface, 0 elsewhere (wall interiors
/// included).
cv::Mat rasterize_outline(const std::vector<LabeledSegment>& outline, const GridSpec& grid,
                          LineRule rule = LineRule::kClosed);

/// Where an observer may stand for a matcher: the plan's valid area (valid_area_mask) minus the
/// cells blocked under the matcher's own blocking options (e.g. inside an open door's leaf when
/// doors count as closed). CV_8U, 255 = valid.
cv::Mat matcher_valid_mask(const FloorPlan& plan, const GridSpec& grid, const BlockingOptions& blocking);

/// Centrelines of blocking footprints (wall pieces, door leaves, glass panes: their axis;
/// obstacles: their polygon's edges), as segments.
std::vector<Segment2> footprint_centrelines(const std::vector<Footprint>& footprints);

}  // namespace floorcast
