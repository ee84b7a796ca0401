// Rasters of a floor plan: occupancy, valid-area (interior) mask, distance transform.
//
// Grid convention: cell (row r, col c) covers world x in [origin_x + c*res, origin_x + (c+1)*res)
// and y in [origin_y + r*res, origin_y + (r+1)*res). Rows grow with +y (so an image written as is
// appears upside down; renderers flip it).
#pragma once

#include <opencv2/core.hpp>

#include "floorcast/core/grid.hpp"
#include "floorcast/floorplans/floor_plan.hpp"
#include "floorcast/floorplans/geometry.hpp"

namespace floorcast {

/// Grid covering the plan's bounding box plus a margin, with its origin snapped to a multiple of
/// the resolution (so grids of one plan at one resolution always align). Refused (LimitError)
/// before anything is allocated when its cells exceed max_raster_cells or the plan's own rasters
/// (kPlanRasterBytesPerCell) exceed max_raster_bytes; InputError for a resolution or margin that
/// is not a positive finite number.
GridSpec grid_for_plan(const FloorPlan& plan, double resolution_m_per_px, double margin_m = 1.0);

/// Bytes per cell of make_plan_rasters (occupancy, valid mask, distance, and the envelope,
/// padding and flood-fill temporaries), for the raster memory estimate.
constexpr double kPlanRasterBytesPerCell = 16.0;

struct RasterOptions {
  double resolution_m_per_px = 0.1;
  double margin_m = 1.0;
  BlockingOptions blocking;  ///< closed doors / glass / obstacles as walls or not
};

/// Occupancy: CV_8U, 255 = blocked, 0 = free. A cell is blocked iff its centre lies in a blocking
/// footprint or a footprint's centreline (wall axis, door/window axis, a box obstacle's medial
/// segment) passes through the cell — so every wall and every box (a 5 cm partition) is at least
/// one cell thick and rasters are watertight at any resolution.
cv::Mat rasterize_occupancy(const FloorPlan& plan, const GridSpec& grid, const BlockingOptions& blocking);

/// Interior of the building: CV_8U, 255 = free cell enclosed by the building envelope. The
/// envelope is the occupancy with every door and window closed, morphologically closed to bridge
/// gaps up to gap_close_m; interior = free cells not reachable from the grid border.
cv::Mat valid_area_mask(const FloorPlan& plan, const GridSpec& grid, double gap_close_m = 0.5);

/// Euclidean distance (metres) from each cell centre to the nearest blocked cell, CV_32F.
cv::Mat distance_to_blocked_m(const cv::Mat& occupancy, const GridSpec& grid);

/// All rasters of a plan at one resolution.
struct PlanRasters {
  GridSpec grid;
  cv::Mat occupancy;       ///< CV_8U 255 = blocked
  cv::Mat valid;           ///< CV_8U 255 = interior & free
  cv::Mat distance_m;      ///< CV_32F distance to nearest blocked cell
};
PlanRasters make_plan_rasters(const FloorPlan& plan, const RasterOptions& options = {});

/// Free floor area inside the building (m^2), computed on a fine grid (walls, closed and open
/// doors' leaves, glass and obstacles excluded).
double free_floor_area_m2(const FloorPlan& plan, double resolution_m_per_px = 0.05);

/// Is there somewhere to stand? The plan's free regions: connected components (8-neighbour) of
/// the valid area (doors open; closed doors, glass and walls block; obstacles do not), each with
/// its area and its width (twice the largest distance from a cell to the region's edge, less one
/// cell).
struct FreeRegionOptions {
  double resolution_m_per_px = 0.1;  ///< raster resolution (coarser for plans above max_cells)
  double max_cells = 4.0e6;          ///< cells of the raster at most (a 10 km plan is measured at 5 m/px)
  double min_area_m2 = 4.0;          ///< a room-sized region has at least this area ...
  double min_width_m = 1.0;          ///< ... and is at least this wide somewhere
};
struct FreeRegionSummary {
  double resolution_m_per_px = 0.0;  ///< the resolution used
  double free_area_m2 = 0.0;         ///< all free regions together
  int regions = 0;
  double largest_region_m2 = 0.0;
  double widest_m = 0.0;             ///< the widest region's width
  int room_sized_regions = 0;        ///< regions meeting min_area_m2 and min_width_m
  double largest_room_sized_m2 = 0.0;
};
FreeRegionSummary free_region_summary(const FloorPlan& plan, const FreeRegionOptions& options = {});

/// Refuses (InputError naming `source`, with the largest region's area and width) a plan with no
/// room-sized free region: nowhere an observer could stand (a level of pillar outlines only, a plan
/// whose mapped spaces all lie outside its walls). `floorcast plan validate` and every importer
/// run it.
void require_room_sized_free_region(const FloorPlan& plan, const std::string& source,
                                    const FreeRegionOptions& options = {});

/// Zhang-Suen thinning of a binary CV_8UC1 image (non-zero = foreground) to a one-pixel skeleton,
/// 255 on the skeleton and 0 elsewhere (border pixels are never removed). The same pixels as
/// OpenCV ximgproc's THINNING_ZHANGSUEN for 0/255 input (tested against it), without linking
/// ximgproc (which pulls dnn, calib3d and more into every floorcast process).
cv::Mat thin_zhang_suen(const cv::Mat& binary);

}  // namespace floorcast
