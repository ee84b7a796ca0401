#include "floorcast/core/pose_json.hpp"

#include <cmath>

namespace floorcast {

nlohmann::ordered_json pose_matrix_json(const Eigen::Isometry3d& T) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (int r = 0; r < 4; ++r) {
    nlohmann::ordered_json row = nlohmann::ordered_json::array();
    for (int c = 0; c < 4; ++c) row.push_back(T.matrix()(r, c));
    rows.push_back(row);
  }
  return rows;
}

Eigen::Isometry3d pose_matrix_from_json(const JsonReader& parent, const nlohmann::json& j, const std::string& key) {
  const std::string path = parent.child_path(key);
  auto fail = [&](const std::string& why) { throw InputError(parent.source() + ": " + path + ": " + why); };
  if (!j.is_array() || j.size() != 4) fail("expected a 4x4 matrix (array of 4 rows)");
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r) {
    const nlohmann::json& row = j[static_cast<std::size_t>(r)];
    if (!row.is_array() || row.size() != 4) fail("row " + std::to_string(r) + " must have 4 numbers");
    for (int c = 0; c < 4; ++c) {
      const nlohmann::json& v = row[static_cast<std::size_t>(c)];
      if (!v.is_number() || !std::isfinite(v.get<double>())) fail("entries must be finite numbers");
      M(r, c) = v.get<double>();
    }
  }
  if ((M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9) fail("last row must be [0, 0, 0, 1]");
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-6 || R.determinant() < 0.0) {
    fail("rotation part is not a rotation matrix");
  }
  if (M.topRightCorner<3, 1>().norm() > 1e5) fail("translation absurdly large");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.matrix() = M;
  return T;
}

}  // namespace floorcast
