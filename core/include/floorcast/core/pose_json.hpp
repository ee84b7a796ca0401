// 4x4 rigid transforms in JSON (row-major arrays of rows), strict on reading.
#pragma once

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <string>

#include "floorcast/core/json_reader.hpp"

namespace floorcast {

nlohmann::ordered_json pose_matrix_json(const Eigen::Isometry3d& T);

/// Reads parent[key] (already fetched as `j`) as a rigid 4x4 transform; throws InputError naming
/// the file and element when it is not one (shape, non-finite entries, non-rotation, last row).
Eigen::Isometry3d pose_matrix_from_json(const JsonReader& parent, const nlohmann::json& j, const std::string& key);

}  // namespace floorcast
