// The built-in matcher table. An explicit table, not static self-registration: registrars in a
// static library's object files are dropped by the linker when nothing references them.
#include <algorithm>

#include "floorcast/match/kernel_matcher.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/match/ray_matcher.hpp"

namespace floorcast {
namespace {

using Factory = std::unique_ptr<Matcher> (*)(const FloorPlan&, const nlohmann::json&);

struct Entry {
  const char* name;
  Factory make;
};

std::unique_ptr<Matcher> make_kernel(const FloorPlan& plan, const nlohmann::json& overrides) {
  KernelMatcherParams p;
  p.apply_overrides(overrides);
  return std::make_unique<KernelMatcher>(plan, p);
}

std::unique_ptr<Matcher> make_ray(const FloorPlan& plan, const nlohmann::json& overrides) {
  RayMatcherParams p;
  p.apply_overrides(overrides);
  return std::make_unique<RayMatcher>(plan, p);
}

constexpr Entry kMatchers[] = {
    {"kernel", &make_kernel},
    {"ray", &make_ray},
};

}  // namespace

std::unique_ptr<Matcher> make_matcher(const std::string& name, const FloorPlan& plan, const nlohmann::json& overrides) {
  for (const Entry& e : kMatchers) {
    if (name == e.name) return e.make(plan, overrides);
  }
  std::string known;
  for (const std::string& n : matcher_names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown matcher \"" + name + "\" (known: " + known + ")");
}

std::vector<std::string> matcher_names() {
  std::vector<std::string> names;
  for (const Entry& e : kMatchers) names.emplace_back(e.name);
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace floorcast
