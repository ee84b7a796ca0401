// On-disk cache of distance volumes (the localization library's file-I/O part for them).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "floorcast/match/distance_volume.hpp"

namespace floorcast {

/// Writes a volume with a key (any string identifying what it was computed from) atomically.
/// Throws InputError on failure.
void save_distance_volume(const std::string& path, const DistanceVolume& volume, const std::string& key);

/// Reads a volume written by save_distance_volume. Returns nothing when the file is missing or was
/// written for another key or format version; throws InputError when it is corrupt.
std::optional<DistanceVolume> load_distance_volume(const std::string& path, const std::string& key);

}  // namespace floorcast
