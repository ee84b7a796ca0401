// Observation files: the JSON form of an Observation2D that the simulator's perfect observer and
// the observation module write and every matcher reads (`floorcast sim perfect ... -o DIR` writes DIR/observation.json).
//
// Schema (format "floorcast-observation", format_version 1; keys in this order, unknown keys are
// refused):
//   {
//     "format": "floorcast-observation",
//     "format_version": 1,
//     "frame": "observer",            // x along the heading, y to its left, metres
//     "source": "perfect",            // free text: who made it (perfect, observation module, ...)
//     "max_range_m": 10.0,            // > 0
//     "segments_m": [[ax, ay, bx, by], ...],   // observer frame; free space on each one's left
//     "segment_labels": ["wall", ...],         // optional; same length: wall, door_closed, glass, obstacle
//     "ray_ranges_m": [r0, r1, ...],           // optional (at least 4; left out when none); ray i at angle i*2*pi/N CCW
//                                              // from +x; no return = max_range_m
//     "bev": [{"classes": "semantic",          // optional BEV predictions (core/bev.hpp), at most
//              "class_names": [...],           //   one per class set ("semantic", "occupancy")
//              "depth_bins": 32, "min_depth_m": 0.3, "max_depth_m": 10.0,
//              "column_azimuth_rad": [...],    //   W columns, observer frame
//              "probabilities": [...]}],       //   W x D x C, (w * D + d) * C + c, rounded to 1e-6
//     "ground_truth": {"x_m": 1.0, "y_m": 2.0, "yaw_rad": 0.3},   // optional: T_world_observer
//     "metadata": {"key": "value", ...}        // optional free strings (plan file, parameters)
//   }
// Ranges must lie in [0, max_range_m]; all numbers finite.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "floorcast/core/observation.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {

struct ObservationRecord {
  Observation2D observation;
  /// Empty, or one label per segment.
  std::vector<SurfaceLabel> segment_labels;
  std::string source;
  std::optional<Pose2> T_world_observer;  ///< ground truth, when known
  std::map<std::string, std::string> metadata;
};

const char* surface_label_name(SurfaceLabel label);
bool surface_label_from_name(const std::string& name, SurfaceLabel& label);

/// Canonical JSON text (2-space indent, trailing newline).
std::string observation_to_json_text(const ObservationRecord& record);
/// Parses and validates; `source_name` names the file in errors. Throws InputError.
ObservationRecord parse_observation_json(const std::string& text, const std::string& source_name);

void save_observation(const std::string& path, const ObservationRecord& record);
ObservationRecord load_observation(const std::string& path);

}  // namespace floorcast
