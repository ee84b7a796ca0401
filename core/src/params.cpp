#include "floorcast/core/params.hpp"

#include "floorcast/core/fields.hpp"

#include <climits>
#include <cmath>

namespace floorcast {
namespace {

std::string num(double d) { return nlohmann::json(d).dump(); }

}  // namespace

ParamReader::ParamReader(const nlohmann::json& overrides, std::string who, std::string prefix, ReadMode mode)
    : j_(overrides), who_(std::move(who)), prefix_(std::move(prefix)), mode_(mode) {
  if (!j_.is_object()) {
    if (prefix_.empty()) {
      throw InputError(who_ + (mode_ == ReadMode::kRecord ? ": top level: expected an object" : ": parameter overrides must be a JSON object"));
    }
    fail(prefix_.substr(0, prefix_.size() - 1), "expected an object");
  }
}

bool ParamReader::take(const char* key) {
  seen_.emplace_back(key);
  if (!j_.contains(key)) {
    if (mode_ == ReadMode::kRecord) fail(key, "missing");
    return false;
  }
  read_.insert(key);
  return true;
}

void ParamReader::fail(const std::string& key, const std::string& why) const {
  const std::string full = (key.rfind(prefix_, 0) == 0 && !prefix_.empty()) ? key : prefix_ + key;
  if (mode_ == ReadMode::kRecord) throw ParameterError(who_ + ": " + full + ": " + why, full);
  throw ParameterError(who_ + ": parameter \"" + full + "\": " + why, full);
}

void ParamReader::read(const char* key, nlohmann::json& value) {
  if (!take(key)) return;
  value = j_.at(key);
}

void ParamReader::read(const char* key, nlohmann::ordered_json& value) {
  if (!take(key)) return;
  value = j_.at(key);
}

void ParamReader::read(const char* key, std::vector<std::string>& value) {
  if (!take(key)) return;
  const nlohmann::json& x = j_.at(key);
  if (!x.is_array()) fail(key, "expected an array of strings");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!x[i].is_string()) fail(std::string(key) + "[" + std::to_string(i) + "]", "expected a string");
    out.push_back(x[i].get<std::string>());
  }
  value = std::move(out);
}

void ParamReader::read(const char* key, double& value, double lo, double hi) {
  if (!take(key)) return;
  const nlohmann::json& x = j_.at(key);
  if (!x.is_number()) fail(key, "expected a number");
  const double d = x.get<double>();
  if (!std::isfinite(d)) fail(key, "not a finite number");
  if (!(d >= lo && d <= hi)) fail(key, "value " + x.dump() + " outside [" + num(lo) + ", " + num(hi) + "]");
  value = d;
}

void ParamReader::read(const char* key, int& value, int lo, int hi) {
  if (!take(key)) return;
  const nlohmann::json& x = j_.at(key);
  if (!x.is_number_integer()) fail(key, "expected an integer");
  const long long d = x.get<long long>();
  if (d < lo || d > hi) {
    fail(key, "value " + x.dump() + " outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  value = static_cast<int>(d);
}

void ParamReader::read(const char* key, std::uint64_t& value) {
  if (!take(key)) return;
  const nlohmann::json& x = j_.at(key);
  if (!x.is_number_unsigned() && !(x.is_number_integer() && x.get<long long>() >= 0)) {
    fail(key, "expected a non-negative integer");
  }
  value = x.get<std::uint64_t>();
}

void ParamReader::read(const char* key, bool& value) {
  if (!take(key)) return;
  const nlohmann::json& x = j_.at(key);
  if (!x.is_boolean()) fail(key, "expected true or false");
  value = x.get<bool>();
}

void ParamReader::read(const char* key, std::string& value) {
  if (!take(key)) return;
  const nlohmann::json& x = j_.at(key);
  if (!x.is_string()) fail(key, "expected a string");
  value = x.get<std::string>();
}

void ParamReader::read(const char* key, std::vector<double>& value, double lo, double hi) {
  if (!take(key)) return;
  const nlohmann::json& x = j_.at(key);
  if (!x.is_array() || x.empty()) fail(key, "expected a non-empty array of numbers");
  std::vector<double> out;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const nlohmann::json& e = x[i];
    const std::string at = std::string(key) + "[" + std::to_string(i) + "]";
    if (!e.is_number() || !std::isfinite(e.get<double>())) fail(at, "expected a finite number");
    const double d = e.get<double>();
    if (!(d >= lo && d <= hi)) fail(at, "value " + e.dump() + " outside [" + num(lo) + ", " + num(hi) + "]");
    out.push_back(d);
  }
  value = std::move(out);
}

void ParamReader::read(const char* key, std::vector<int>& value) {
  if (!take(key)) return;
  const nlohmann::json& x = j_.at(key);
  if (!x.is_array()) fail(key, "expected an array of integers");
  std::vector<int> out;
  for (const nlohmann::json& e : x) {
    if (!e.is_number_integer() || e.get<long long>() < INT_MIN || e.get<long long>() > INT_MAX) {
      fail(key, "expected an array of integers");
    }
    out.push_back(static_cast<int>(e.get<long long>()));
  }
  value = std::move(out);
}

void ParamReader::read_series(const char* key, std::vector<double>& value) {
  if (!take(key)) return;
  const nlohmann::json& x = j_.at(key);
  if (!x.is_array()) fail(key, "expected an array of numbers");
  std::vector<double> out;
  out.reserve(x.size());
  for (const nlohmann::json& e : x) {
    if (!e.is_number() || !std::isfinite(e.get<double>())) fail(key, "expected an array of finite numbers");
    out.push_back(e.get<double>());
  }
  value = std::move(out);
}

void ParamReader::finish() const {
  for (auto it = j_.begin(); it != j_.end(); ++it) {
    if (!read_.count(it.key())) {
      std::string known;
      for (const std::string& k : seen_) known += (known.empty() ? "" : ", ") + k;
      const std::string full = prefix_ + it.key();
      if (mode_ == ReadMode::kRecord) throw ParameterError(who_ + ": " + full + ": unknown key (known: " + known + ")", full);
      throw ParameterError(who_ + ": unknown parameter \"" + full + "\" (known: " + known + ")", full);
    }
  }
}

const FieldList<BlockingOptions>& blocking_fields() {
  using B = BlockingOptions;
  static const FieldList<B> f =
      FieldList<B>("blocking")
          .flag("doors_closed", &B::open_doors_block, "open doors drawn closed in the map (PALMS+ sec. 4.4: all doors closed)")
          .flag("glass_blocks", &B::glass_blocks, "glass walls and windows block (drawn in the map)")
          .flag("obstacles_block", &B::obstacles_block, "furniture and clutter block (floor plans do not show them)")
          .number("cut_height_m", &B::cut_height_m, 0.0, 100.0, "plan cut height, m (camera height: 1.5)");
  return f;
}

const FieldList<SharedParams>& shared_fields() {
  static const FieldList<SharedParams> f =
      FieldList<SharedParams>("shared")
          .number("range_m", &SharedParams::range_m, 0.1, 1000.0,
                  "localization range, m: perfect observations see and matchers use geometry within it (PALMS+ "
                  "sec. 4.4, configs max_dist: 10)")
          .flatten(&SharedParams::blocking, blocking_fields());
  return f;
}

nlohmann::ordered_json to_json(const SharedParams& shared) { return shared_fields().write(shared); }

void apply_overrides(SharedParams& shared, const nlohmann::json& overrides, const std::string& who) {
  ParamReader r(overrides, who);
  shared_fields().read_into(r, shared);
  r.finish();
}

}  // namespace floorcast
