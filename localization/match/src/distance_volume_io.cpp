#include "floorcast/match/distance_volume_io.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <vector>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/hash.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {
namespace {

constexpr char kMagic[8] = {'F', 'C', 'D', 'V', 'O', 'L', '0', '3'};  // 02: bits and step; 03: cast point

template <typename T>
void put(std::ofstream& out, const T& v) {
  out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <typename T>
bool get(std::ifstream& in, T& v) {
  return static_cast<bool>(in.read(reinterpret_cast<char*>(&v), sizeof(T)));
}

}  // namespace

void save_distance_volume(const std::string& path, const DistanceVolume& v, const std::string& key) {
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot open for writing: " + std::strerror(errno));
    out.write(kMagic, sizeof(kMagic));
    put<std::uint64_t>(out, key.size());
    out.write(key.data(), static_cast<std::streamsize>(key.size()));
    put(out, v.grid.origin_x_m);
    put(out, v.grid.origin_y_m);
    put(out, v.grid.resolution_m_per_px);
    put<std::int32_t>(out, v.grid.width_px);
    put<std::int32_t>(out, v.grid.height_px);
    put<std::int32_t>(out, v.num_directions);
    put(out, v.max_range_m);
    put<std::int32_t>(out, v.bits);
    put<std::int32_t>(out, v.step_mm);
    put(out, v.sample_offset);
    put<std::uint64_t>(out, v.cells.size());
    out.write(reinterpret_cast<const char*>(v.cells.data()),
              static_cast<std::streamsize>(v.cells.size() * sizeof(std::int32_t)));
    out.write(reinterpret_cast<const char*>(v.mm.data()), static_cast<std::streamsize>(v.mm.size() * sizeof(std::uint16_t)));
    out.write(reinterpret_cast<const char*>(v.q8.data()), static_cast<std::streamsize>(v.q8.size()));
    out.flush();
    if (!out) {
      std::remove(tmp.c_str());
      throw InputError(path + ": write error");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(tmp.c_str());
    throw InputError(path + ": cannot move the written file into place: " + reason);
  }
}

std::optional<DistanceVolume> load_distance_volume(const std::string& path, const std::string& key) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  auto corrupt = [&](const std::string& why) { return InputError(path + ": corrupt distance-volume cache: " + why); };
  char magic[sizeof(kMagic)];
  if (!in.read(magic, sizeof(magic))) throw corrupt("truncated header");
  if (std::memcmp(magic, kMagic, sizeof(kMagic)) != 0) return std::nullopt;  // other format version
  std::uint64_t key_len = 0;
  if (!get(in, key_len) || key_len > 4096) throw corrupt("bad key length");
  std::string stored(key_len, '\0');
  if (!in.read(stored.data(), static_cast<std::streamsize>(key_len))) throw corrupt("truncated key");
  if (stored != key) return std::nullopt;
  DistanceVolume v;
  std::int32_t w = 0, h = 0, d = 0;
  std::uint64_t n = 0;
  if (!get(in, v.grid.origin_x_m) || !get(in, v.grid.origin_y_m) || !get(in, v.grid.resolution_m_per_px) ||
      !get(in, w) || !get(in, h) || !get(in, d) || !get(in, v.max_range_m) || !get(in, v.bits) || !get(in, v.step_mm) ||
      !get(in, v.sample_offset) || !get(in, n)) {
    throw corrupt("truncated header");
  }
  if ((v.bits != 8 && v.bits != 16) || v.step_mm < 1 || v.step_mm > 65535 || (v.bits == 16 && v.step_mm != 1)) {
    throw corrupt("bad bits or step");
  }
  if (!(v.sample_offset >= 0.0 && v.sample_offset < 1.0)) throw corrupt("bad cast point");
  const std::uint64_t hw = static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h);
  if (w <= 0 || h <= 0 || d <= 0 || d > 100000 || n > hw) throw corrupt("bad sizes");
  v.grid.width_px = w;
  v.grid.height_px = h;
  v.num_directions = d;
  v.cells.resize(n);
  (v.bits == 8 ? v.q8.resize(n * static_cast<std::uint64_t>(d)) : v.mm.resize(n * static_cast<std::uint64_t>(d)));
  if (!in.read(reinterpret_cast<char*>(v.cells.data()), static_cast<std::streamsize>(n * sizeof(std::int32_t))) ||
      !in.read(reinterpret_cast<char*>(v.mm.data()), static_cast<std::streamsize>(v.mm.size() * sizeof(std::uint16_t))) ||
      !in.read(reinterpret_cast<char*>(v.q8.data()), static_cast<std::streamsize>(v.q8.size()))) {
    throw corrupt("truncated data");
  }
  char extra;
  if (in.read(&extra, 1)) throw corrupt("trailing bytes");
  v.cell_index.assign(hw, -1);
  for (std::size_t i = 0; i < v.cells.size(); ++i) {
    const std::int32_t c = v.cells[i];
    if (c < 0 || static_cast<std::uint64_t>(c) >= hw || (i > 0 && c <= v.cells[i - 1])) throw corrupt("bad cell list");
    v.cell_index[static_cast<std::size_t>(c)] = static_cast<std::int32_t>(i);
  }
  return v;
}

std::unique_ptr<RayMatcher> make_cached_ray_matcher(const std::string& cache_dir, const FloorPlan& plan,
                                                    const RayMatcherParams& params, bool* from_cache) {
  const std::string key = RayMatcher::volume_key(plan, params);
  const std::string path =
      (std::filesystem::path(cache_dir) / ("distance_volume_" + hex64(fnv1a64(key)) + ".bin")).string();
  const GridSpec grid = grid_for_plan(plan, params.resolution_m, params.grid_margin_m);
  if (std::optional<DistanceVolume> v = load_distance_volume(path, key); v && v->grid == grid) {
    if (from_cache) *from_cache = true;
    return std::make_unique<RayMatcher>(plan, params, std::move(*v));
  }
  auto matcher = std::make_unique<RayMatcher>(plan, params);
  create_directories_or_throw(cache_dir);
  save_distance_volume(path, matcher->volume(), key);
  if (from_cache) *from_cache = false;
  return matcher;
}

}  // namespace floorcast
