// On-disk cache of distance volumes (the match library's file-I/O part): callers that build ray
// matchers for the same plans again and again keep the volumes here; the matcher itself never
// touches the disk.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <memory>

#include "floorcast/match/distance_volume.hpp"
#include "floorcast/match/ray_matcher.hpp"

namespace floorcast {

/// Writes a volume with a key (any string identifying what it was computed from) atomically.
/// Throws InputError on failure.
void save_distance_volume(const std::string& path, const DistanceVolume& volume, const std::string& key);

/// Reads a volume written by save_distance_volume. Returns nothing when the file is missing or was
/// written for another key or format version; throws InputError when it is corrupt.
std::optional<DistanceVolume> load_distance_volume(const std::string& path, const std::string& key);

/// A ray matcher whose volume is read from `cache_dir` when one for this plan and these
/// parameters (RayMatcher::volume_key) was saved there, else computed and saved there (the
/// folder is created). `from_cache` receives which happened.
std::unique_ptr<RayMatcher> make_cached_ray_matcher(const std::string& cache_dir, const FloorPlan& plan,
                                                    const RayMatcherParams& params, bool* from_cache = nullptr);

}  // namespace floorcast
