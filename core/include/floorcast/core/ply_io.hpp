// Point clouds as PLY (binary little-endian, "vertex" elements with float x, y, z and optional
// uchar red, green, blue), the format Open3D (o3d.io.read_point_cloud), CloudCompare, MeshLab and
// PCL read.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace floorcast {

struct PlyCloud {
  std::vector<Eigen::Vector3f> points_m;
  /// Empty, or one RGB colour per point.
  std::vector<std::array<std::uint8_t, 3>> colours_rgb;
};

/// PLY bytes of a cloud; `comment` lines (no newlines) go into the header (frame, units, source).
std::string ply_bytes(const PlyCloud& cloud, const std::vector<std::string>& comments = {});
/// Writes ply_bytes atomically; throws InputError naming the path on failure or when the colour
/// count differs from the point count.
void write_ply(const std::string& path, const PlyCloud& cloud, const std::vector<std::string>& comments = {});
/// Reads what write_ply writes (binary little-endian or ASCII, float/double x, y, z, optional
/// uchar red, green, blue; other vertex properties are skipped). Throws InputError naming `path`.
PlyCloud read_ply(const std::string& path);

}  // namespace floorcast
