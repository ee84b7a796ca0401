// Stable, platform-independent hashing for cache keys, scenario identities and run checks.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace floorcast {

/// 64-bit FNV-1a of the bytes.
std::uint64_t fnv1a64(std::string_view bytes);

/// 16 lower-case hexadecimal digits.
std::string hex64(std::uint64_t value);

}  // namespace floorcast
