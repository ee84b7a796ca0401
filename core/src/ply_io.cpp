#include "floorcast/core/ply_io.hpp"

#include <cstring>
#include <sstream>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {

std::string ply_bytes(const PlyCloud& cloud, const std::vector<std::string>& comments) {
  const bool colour = !cloud.colours_rgb.empty();
  if (colour && cloud.colours_rgb.size() != cloud.points_m.size()) {
    throw InputError("PLY: " + std::to_string(cloud.colours_rgb.size()) + " colours for " +
                     std::to_string(cloud.points_m.size()) + " points");
  }
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\n";
  for (const std::string& c : comments) {
    std::string line = c;
    for (char& ch : line)
      if (ch == '\n' || ch == '\r') ch = ' ';
    h << "comment " << line << "\n";
  }
  h << "element vertex " << cloud.points_m.size() << "\nproperty float x\nproperty float y\nproperty float z\n";
  if (colour) h << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  h << "end_header\n";
  std::string out = h.str();
  const std::size_t stride = 12 + (colour ? 3 : 0);
  const std::size_t start = out.size();
  out.resize(start + stride * cloud.points_m.size());
  char* p = out.data() + start;
  for (std::size_t i = 0; i < cloud.points_m.size(); ++i, p += stride) {
    const float xyz[3] = {cloud.points_m[i].x(), cloud.points_m[i].y(), cloud.points_m[i].z()};
    std::memcpy(p, xyz, 12);  // x86/ARM hosts are little-endian
    if (colour) std::memcpy(p + 12, cloud.colours_rgb[i].data(), 3);
  }
  return out;
}

void write_ply(const std::string& path, const PlyCloud& cloud, const std::vector<std::string>& comments) {
  std::string bytes;
  try {
    bytes = ply_bytes(cloud, comments);
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
  write_text_file_atomic(path, bytes);
}

PlyCloud read_ply(const std::string& path) {
  const std::string bytes = read_text_file(path);
  const std::size_t end = bytes.find("end_header\n");
  if (bytes.compare(0, 4, "ply\n") != 0 || end == std::string::npos) throw InputError(path + ": not a PLY file");
  std::istringstream header(bytes.substr(0, end));
  std::string line, format;
  std::size_t count = 0;
  bool in_vertex = false;
  struct Property {
    std::string type, name;
  };
  std::vector<Property> props;
  while (std::getline(header, line)) {
    std::istringstream f(line);
    std::string word;
    f >> word;
    if (word == "format") f >> format;
    else if (word == "element") {
      std::string name;
      f >> name;
      in_vertex = name == "vertex";
      if (in_vertex) f >> count;
    } else if (word == "property" && in_vertex) {
      Property p;
      f >> p.type >> p.name;
      if (p.type == "list") throw InputError(path + ": list properties on vertices are not supported");
      props.push_back(p);
    }
  }
  auto size_of = [&](const std::string& t) -> std::size_t {
    if (t == "float" || t == "float32" || t == "int" || t == "int32" || t == "uint" || t == "uint32") return 4;
    if (t == "double" || t == "float64") return 8;
    if (t == "uchar" || t == "uint8" || t == "char" || t == "int8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    throw InputError(path + ": unknown PLY property type " + t);
  };
  PlyCloud cloud;
  int ix = -1, iy = -1, iz = -1, ir = -1, ig = -1, ib = -1;
  for (std::size_t i = 0; i < props.size(); ++i) {
    const std::string& n = props[i].name;
    const int k = static_cast<int>(i);
    if (n == "x") ix = k;
    if (n == "y") iy = k;
    if (n == "z") iz = k;
    if (n == "red") ir = k;
    if (n == "green") ig = k;
    if (n == "blue") ib = k;
  }
  if (ix < 0 || iy < 0 || iz < 0) throw InputError(path + ": PLY vertices have no x, y, z");
  const bool colour = ir >= 0 && ig >= 0 && ib >= 0;
  cloud.points_m.resize(count);
  if (colour) cloud.colours_rgb.resize(count);
  auto value_at = [&](const char* p, const std::string& t) -> double {
    if (t == "float" || t == "float32") { float v; std::memcpy(&v, p, 4); return v; }
    if (t == "double" || t == "float64") { double v; std::memcpy(&v, p, 8); return v; }
    if (t == "uchar" || t == "uint8") return static_cast<unsigned char>(*p);
    if (t == "char" || t == "int8") return static_cast<signed char>(*p);
    if (t == "short" || t == "int16") { std::int16_t v; std::memcpy(&v, p, 2); return v; }
    if (t == "ushort" || t == "uint16") { std::uint16_t v; std::memcpy(&v, p, 2); return v; }
    if (t == "int" || t == "int32") { std::int32_t v; std::memcpy(&v, p, 4); return v; }
    std::uint32_t v; std::memcpy(&v, p, 4); return v;
  };
  if (format == "binary_little_endian") {
    std::vector<std::size_t> offset(props.size());
    std::size_t stride = 0;
    for (std::size_t i = 0; i < props.size(); ++i) {
      offset[i] = stride;
      stride += size_of(props[i].type);
    }
    const std::size_t data = end + 11;
    if (bytes.size() < data + stride * count) throw InputError(path + ": PLY data truncated");
    for (std::size_t v = 0; v < count; ++v) {
      const char* row = bytes.data() + data + v * stride;
      auto get = [&](int i) { return value_at(row + offset[static_cast<std::size_t>(i)], props[static_cast<std::size_t>(i)].type); };
      cloud.points_m[v] = Eigen::Vector3f(static_cast<float>(get(ix)), static_cast<float>(get(iy)), static_cast<float>(get(iz)));
      if (colour) cloud.colours_rgb[v] = {static_cast<std::uint8_t>(get(ir)), static_cast<std::uint8_t>(get(ig)), static_cast<std::uint8_t>(get(ib))};
    }
  } else if (format == "ascii") {
    std::istringstream body(bytes.substr(end + 11));
    for (std::size_t v = 0; v < count; ++v) {
      std::vector<double> vals(props.size());
      for (double& x : vals)
        if (!(body >> x)) throw InputError(path + ": PLY data truncated");
      cloud.points_m[v] = Eigen::Vector3f(static_cast<float>(vals[static_cast<std::size_t>(ix)]), static_cast<float>(vals[static_cast<std::size_t>(iy)]), static_cast<float>(vals[static_cast<std::size_t>(iz)]));
      if (colour) cloud.colours_rgb[v] = {static_cast<std::uint8_t>(vals[static_cast<std::size_t>(ir)]), static_cast<std::uint8_t>(vals[static_cast<std::size_t>(ig)]), static_cast<std::uint8_t>(vals[static_cast<std::size_t>(ib)])};
    }
  } else {
    throw InputError(path + ": unsupported PLY format \"" + format + "\"");
  }
  return cloud;
}

}  // namespace floorcast
