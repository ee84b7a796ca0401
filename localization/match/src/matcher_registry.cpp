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
#include "floorcast/match/plane_matcher.hpp"
#include "floorcast/match/ray_matcher.hpp"

namespace floorcast {
namespace {

/// Every registered matcher may abstain: with min_score > 0 a match whose best mode scores below
/// it has no pose ("not localized"; the posterior stays). The comparison with methods that reject
/// on their own (the plane matcher) is then fair.
class Abstaining final : public Matcher {
 public:
  Abstaining(std::unique_ptr<Matcher> inner, double min_score, nlohmann::ordered_json parameters)
      : inner_(std::move(inner)), min_score_(min_score), parameters_(std::move(parameters)) {}
  std::string name() const override { return inner_->name(); }
  nlohmann::ordered_json parameters() const override { return parameters_; }
  double precompute_s() const override { return inner_->precompute_s(); }
  std::size_t precompute_bytes() const override { return inner_->precompute_bytes(); }
  BlockingOptions blocking() const override { return inner_->blocking(); }
  using Matcher::match;
  MatchResult match(const Observation2D& observation, const MatchRequest& request) const override {
    MatchResult r = inner_->match(observation, request);
    if (!r.modes.empty() && r.modes.front().score < min_score_) {
      r.modes.clear();
      r.counters["abstained"] = 1.0;
    }
    return r;
  }
  /// The inner matcher's point queries (abstention concerns modes only, never the posterior).
  PosteriorQuery query(const Observation2D& observation) const override { return inner_->query(observation); }
  const Matcher& unwrapped() const override { return inner_->unwrapped(); }
  std::vector<std::string> notes() const override { return inner_->notes(); }

 private:
  std::unique_ptr<Matcher> inner_;
  double min_score_;
  nlohmann::ordered_json parameters_;
};

/// A matcher's own parameters P and the abstention threshold every matcher takes.
template <class P>
struct Abstainable {
  P params;
  double min_score = 0.0;  ///< a best mode scoring below it is "not localized"; 0 = never abstain
};

/// P's fields, then min_score (its errors name the matcher as P's do).
template <class P>
const FieldList<Abstainable<P>>& abstainable_fields() {
  using A = Abstainable<P>;
  static const FieldList<A> f =
      FieldList<A>(P::fields().who())
          .flatten(&A::params, P::fields())
          .number("min_score", &A::min_score, 0.0, 1e300,
                  "abstain (\"not localized\") when the best mode scores below this; 0 = never (every matcher)");
  return f;
}

/// A matcher configuration of parameter type P building matcher type M.
template <class P, class M>
class Config final : public MatcherConfig {
 public:
  Config(const char* name, Abstainable<P> settings) : name_(name), settings_(std::move(settings)) {}
  std::string name() const override { return name_; }
  nlohmann::ordered_json parameters() const override { return abstainable_fields<P>().write(settings_); }
  std::unique_ptr<Matcher> build(const FloorPlan& plan) const override {
    return std::make_unique<Abstaining>(std::make_unique<M>(plan, settings_.params), settings_.min_score, parameters());
  }

 private:
  const char* name_;
  Abstainable<P> settings_;
};

template <class P, class M>
std::shared_ptr<const MatcherConfig> parse(const char* name, const nlohmann::json& overrides, const SharedParams& shared) {
  Abstainable<P> a;
  a.params.apply_shared(shared);
  abstainable_fields<P>().read(a, overrides);
  return std::make_shared<Config<P, M>>(name, std::move(a));
}

/// Every field with its default (the shared quantities applied to the defaults, as a scenario
/// without a `shared` block has them).
template <class P>
std::vector<FieldInfo> describe() {
  Abstainable<P> a;
  a.params.apply_shared(SharedParams{});
  return abstainable_fields<P>().describe(a);
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
    {"planes", &parse<PlaneMatcherParams, PlaneMatcher>, &describe<PlaneMatcherParams>},
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
