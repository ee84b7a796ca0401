// Named limits on the size of everything floorcast reads or allocates from its input (docs/limits.md).
//
// Every size that an input file or parameter controls (plan extent, raster cells and memory,
// points, rays, views, image pixels, nesting depth, vertices per element, level ranges, sweep
// cells, work units, file bytes) is checked against one of these limits before anything is
// allocated for it. A refusal is a LimitError (an InputError) whose message names the limit, its
// value and how to raise it:
//
//   plan.json: raster of 100020 x 100020 cells at 0.1 m/px (kernel matcher) exceeds the limit
//   max_raster_cells = 100000000 (raise it with FLOORCAST_LIMITS=max_raster_cells=N; docs/limits.md)
//
// The limits are process-wide: the CLI reads overrides from the environment variable
// FLOORCAST_LIMITS ("name=value,name=value") once at start-up, before any thread runs; a library
// user may call set_input_limits() the same way. Algorithms only read them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "floorcast/core/types.hpp"

namespace floorcast {

struct InputLimits {
  /// Bytes of one input file (JSON, YAML, XML, CSV). Reading /dev/zero stops here.
  double max_file_bytes = 1024.0 * 1024.0 * 1024.0;
  /// Nesting depth of arrays/objects in JSON, of collections in YAML, of elements in XML.
  double max_nesting_depth = 128;
  /// Nodes of a YAML document after alias expansion ("billion laughs" stops here).
  double max_yaml_nodes = 1.0e5;
  /// Side of a plan's bounding box, metres.
  double max_plan_extent_m = 5000.0;
  /// Elements of one plan (walls + doors + windows + obstacles) and of one imported source.
  double max_plan_elements = 2.0e6;
  /// Cells of one raster over a plan (occupancy, distance, posterior slice, belief slice).
  double max_raster_cells = 4.0e8;
  /// Estimated bytes of the rasters one stage builds over a plan (every orientation, every
  /// channel), refused before any is allocated.
  double max_raster_bytes = 8.0 * 1024.0 * 1024.0 * 1024.0;
  /// Points of one point cloud (back-projected scan, imported polygon soup).
  double max_points = 5.0e7;
  /// Segments of one observation.
  double max_segments = 1.0e5;
  /// Rays of one observation or perfect observer (F3Loc uses 40, PALMS+ sec. 4.4 up to 180).
  double max_rays = 3600;
  /// Views of one scan.
  double max_views = 360;
  /// Pixels of one image read or written (depth views, plan images, renders).
  double max_image_pixels = 2.5e8;
  /// Vertices of one element (polygon, way, ring, wall chain) in an imported plan.
  double max_vertices_per_element = 1.0e5;
  /// Levels one element's level range may expand to (OSM `level=0;1e9`, IMDF ordinals).
  double max_level_range = 1000;
  /// Cells of a scenario sweep (product of the axes' lengths).
  double max_sweep_cells = 1.0e5;
  /// Work units of one scenario run (cells x buildings x observation points).
  double max_units = 1.0e7;
};

/// A size over one of the InputLimits.
class LimitError : public InputError {
 public:
  LimitError(const std::string& message, std::string limit) : InputError(message), limit_(std::move(limit)) {}
  const std::string& limit() const { return limit_; }

 private:
  std::string limit_;
};

/// The process-wide limits (defaults unless set_input_limits or FLOORCAST_LIMITS changed them).
const InputLimits& input_limits();
void set_input_limits(const InputLimits& limits);

/// Names of the limits, in declaration order, with their current values.
std::vector<std::pair<std::string, double>> limit_values(const InputLimits& limits);

/// Applies "name=value,name=value" to `limits`; throws InputError naming `source` for an unknown
/// name or a value that is not a positive finite number.
void apply_limit_overrides(InputLimits& limits, const std::string& text, const std::string& source);

/// Reads FLOORCAST_LIMITS (when set) into the process-wide limits. Call once at start-up.
void apply_limits_from_environment();

/// Throws LimitError when `value` exceeds the process-wide limit `name` (a field of
/// InputLimits): "<what>: <value> <unit> exceeds the limit <name> = <limit> (raise it with
/// FLOORCAST_LIMITS=<name>=N; docs/limits.md)". NaN counts as over the limit.
void check_limit(const char* name, double value, const std::string& what, const std::string& unit = "");

/// The current value of the limit `name`.
double input_limit(const char* name);

/// Multiplies sizes without overflowing: the product, saturated at 1e300 (so a 2^64-cell sweep
/// compares as huge rather than wrapping to 0).
double saturating_product(const std::vector<double>& factors);

}  // namespace floorcast
