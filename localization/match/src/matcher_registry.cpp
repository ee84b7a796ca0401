// The built-in matcher table. An explicit table, not static self-registration: registrars in a
// static library's object files are dropped by the linker when nothing references them. A new
// matcher is one entry here (its parameter struct P declares its fields once, P::fields() in
// core/fields.hpp, and takes the shared quantities in apply_shared); the contract test
// (tests/match/test_matcher_contract.cpp) then runs it over the same known-answer cases as every
// other matcher.
#include <algorithm>

#include "floorcast/match/bev_matcher.hpp"
#include "floorcast/match/external.hpp"
#include "floorcast/match/kernel_matcher.hpp"
#include "floorcast/match/matcher_module.hpp"
#include "floorcast/match/matcher.hpp"
#include "floorcast/match/ray_matcher.hpp"

namespace floorcast {
namespace {

/// A matcher configuration of parameter type P building matcher type M.
template <class P, class M>
class Config final : public MatcherConfig {
 public:
  Config(const char* name, P params) : name_(name), params_(std::move(params)) {}
  std::string name() const override { return name_; }
  nlohmann::ordered_json parameters() const override { return params_.to_json(); }
  std::unique_ptr<Matcher> build(const FloorPlan& plan) const override { return std::make_unique<M>(plan, params_); }

 private:
  const char* name_;
  P params_;
};

template <class P, class M>
std::shared_ptr<const MatcherConfig> parse(const char* name, const nlohmann::json& overrides, const SharedParams& shared) {
  P p;
  p.apply_shared(shared);
  p.apply_overrides(overrides);
  return std::make_shared<Config<P, M>>(name, std::move(p));
}

/// Every field with its default (the shared quantities applied to the defaults, as a scenario
/// without a `shared` block has them).
template <class P>
std::vector<FieldInfo> describe() {
  P p;
  p.apply_shared(SharedParams{});
  return P::fields().describe(p);
}

using Parser = std::shared_ptr<const MatcherConfig> (*)(const char*, const nlohmann::json&, const SharedParams&);

struct Entry {
  const char* name;
  Parser parse;
  std::vector<FieldInfo> (*describe)();
};

constexpr Entry kMatchers[] = {
    {"kernel", &parse<KernelMatcherParams, KernelMatcher>, &describe<KernelMatcherParams>},
    {"ray", &parse<RayMatcherParams, RayMatcher>, &describe<RayMatcherParams>},
    {"bev", &parse<BevMatcherParams, BevMatcher>, &describe<BevMatcherParams>},
    {"external", &parse<ExternalProgramParams, ExternalProgramMatcher>, &describe<ExternalProgramParams>},
};

const Entry* find_builtin(const std::string& name) {
  for (const Entry& e : kMatchers) {
    if (name == e.name) return &e;
  }
  return nullptr;
}

[[noreturn]] void unknown_matcher(const std::string& name) {
  std::string known;
  for (const std::string& n : matcher_names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown matcher \"" + name + "\" (known: " + known + "; and no module " +
                   matcher_module::module_name(name) + ".so in $FLOORCAST_MODULE_DIR, beside floorcast or on the loader's path)");
}

}  // namespace

std::shared_ptr<const MatcherConfig> make_matcher_config(const std::string& name, const nlohmann::json& overrides,
                                                         const SharedParams& shared) {
  if (const Entry* e = find_builtin(name)) return e->parse(e->name, overrides, shared);
  // Registered at run time (Python, tests), or a module floorcast_matcher_<name>.so.
  if (const MatcherConfigParser p = find_external_matcher(name)) return p(overrides, shared);
  unknown_matcher(name);
}

std::vector<FieldInfo> matcher_parameter_fields(const std::string& name) {
  if (const Entry* e = find_builtin(name)) return e->describe();
  if (find_external_matcher(name))
    throw InputError("matcher \"" + name + "\" comes from outside floorcast: its parameters are its own (see its documentation)");
  unknown_matcher(name);
}

std::unique_ptr<Matcher> make_matcher(const std::string& name, const FloorPlan& plan, const nlohmann::json& overrides) {
  return make_matcher_config(name, overrides)->build(plan);
}

std::vector<std::string> builtin_matcher_names() {
  std::vector<std::string> names;
  for (const Entry& e : kMatchers) names.emplace_back(e.name);
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::string> matcher_names() {
  std::vector<std::string> names = builtin_matcher_names();
  for (const std::string& n : registered_matcher_names()) names.push_back(n);
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace floorcast
