// A matcher in its own shared module (C++), built against an installed floorcast's headers and
// found like floorcast's own PCL and GL modules (core/module.hpp): a scenario or command naming
// matcher NAME that is neither built in nor registered loads floorcast_matcher_NAME.so from
// $FLOORCAST_MODULE_DIR, <prefix>/<libdir>/floorcast beside the binary, or the loader's path.
//
//   // my_matcher.cpp -> floorcast_matcher_mine.so
//   #include "floorcast/match/matcher_module.hpp"
//   class MyConfig : public floorcast::MatcherConfig { ... build(plan) returns a Matcher ... };
//   std::shared_ptr<const floorcast::MatcherConfig> parse(const nlohmann::json& overrides,
//                                                         const floorcast::SharedParams& shared) {...}
//   FLOORCAST_MATCHER_MODULE(parse)
//
// examples/matcher_module/ is a complete one with its CMakeLists.txt. Exceptions never cross the
// module boundary while parsing (the macro turns them into messages); match() may throw: the
// scenario runner reports it for the unit, as for every external method (match/external.hpp).
#pragma once

#include <exception>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "floorcast/core/params.hpp"
#include "floorcast/match/matcher.hpp"

namespace floorcast::matcher_module {

/// Bumped whenever Entry or the Matcher/MatcherConfig interfaces change: a module built against
/// another version is refused with "rebuild it".
constexpr int kApiVersion = 1;
constexpr const char* kEntrySymbol = "floorcast_matcher_module_entry";

struct Entry {
  int api_version;
  /// Parses a configuration; on failure returns null and sets *error (and *error_key for a
  /// parameter's key).
  std::shared_ptr<const MatcherConfig> (*parse)(const nlohmann::json& overrides, const SharedParams& shared,
                                                std::string* error, std::string* error_key);
};
using EntryFn = const Entry* (*)();

/// The module file name (without .so) of matcher `name`.
inline std::string module_name(const std::string& name) { return "floorcast_matcher_" + name; }

}  // namespace floorcast::matcher_module

#define FLOORCAST_MATCHER_MODULE(PARSE_FUNCTION)                                                                    \
  namespace {                                                                                                       \
  std::shared_ptr<const ::floorcast::MatcherConfig> floorcast_matcher_module_parse_(                               \
      const nlohmann::json& overrides, const ::floorcast::SharedParams& shared, std::string* error,                \
      std::string* error_key) {                                                                                     \
    try {                                                                                                           \
      return PARSE_FUNCTION(overrides, shared);                                                                     \
    } catch (const ::floorcast::ParameterError& e) {                                                                \
      *error = e.what();                                                                                            \
      *error_key = e.key();                                                                                         \
    } catch (const std::exception& e) {                                                                             \
      *error = e.what();                                                                                            \
    }                                                                                                               \
    return nullptr;                                                                                                 \
  }                                                                                                                 \
  }                                                                                                                 \
  extern "C" __attribute__((visibility("default"))) const ::floorcast::matcher_module::Entry*                      \
  floorcast_matcher_module_entry() {                                                                                \
    static const ::floorcast::matcher_module::Entry entry{::floorcast::matcher_module::kApiVersion,                \
                                                          &floorcast_matcher_module_parse_};                        \
    return &entry;                                                                                                  \
  }
