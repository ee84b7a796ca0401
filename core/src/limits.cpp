#include "floorcast/core/limits.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace floorcast {
namespace {

InputLimits& mutable_limits() {
  static InputLimits limits;
  return limits;
}

struct LimitField {
  const char* name;
  double InputLimits::*field;
};

const std::vector<LimitField>& limit_fields() {
  static const std::vector<LimitField> fields = {
      {"max_file_bytes", &InputLimits::max_file_bytes},
      {"max_nesting_depth", &InputLimits::max_nesting_depth},
      {"max_yaml_nodes", &InputLimits::max_yaml_nodes},
      {"max_plan_extent_m", &InputLimits::max_plan_extent_m},
      {"max_plan_elements", &InputLimits::max_plan_elements},
      {"max_raster_cells", &InputLimits::max_raster_cells},
      {"max_raster_bytes", &InputLimits::max_raster_bytes},
      {"max_points", &InputLimits::max_points},
      {"max_segments", &InputLimits::max_segments},
      {"max_rays", &InputLimits::max_rays},
      {"max_views", &InputLimits::max_views},
      {"max_image_pixels", &InputLimits::max_image_pixels},
      {"max_vertices_per_element", &InputLimits::max_vertices_per_element},
      {"max_level_range", &InputLimits::max_level_range},
      {"max_sweep_cells", &InputLimits::max_sweep_cells},
      {"max_units", &InputLimits::max_units},
  };
  return fields;
}

const LimitField* find_field(const std::string& name) {
  for (const LimitField& f : limit_fields()) {
    if (name == f.name) return &f;
  }
  return nullptr;
}

std::string known_names() {
  std::string s;
  for (const LimitField& f : limit_fields()) s += (s.empty() ? "" : ", ") + std::string(f.name);
  return s;
}

std::string number_text(double v) {
  std::ostringstream os;
  if (std::isfinite(v) && std::abs(v) < 1e15 && v == std::floor(v)) {
    os << static_cast<long long>(v);
  } else {
    os.precision(6);
    os << v;
  }
  return os.str();
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

}  // namespace

const InputLimits& input_limits() { return mutable_limits(); }
void set_input_limits(const InputLimits& limits) { mutable_limits() = limits; }

std::vector<std::pair<std::string, double>> limit_values(const InputLimits& limits) {
  std::vector<std::pair<std::string, double>> out;
  for (const LimitField& f : limit_fields()) out.emplace_back(f.name, limits.*(f.field));
  return out;
}

void apply_limit_overrides(InputLimits& limits, const std::string& text, const std::string& source) {
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = text.find(',', start);
    const std::string item = trim(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    start = comma == std::string::npos ? text.size() + 1 : comma + 1;
    if (item.empty()) continue;
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos) throw InputError(source + ": \"" + item + "\": expected NAME=VALUE");
    const std::string name = trim(item.substr(0, eq));
    const std::string value = trim(item.substr(eq + 1));
    const LimitField* f = find_field(name);
    if (!f) throw InputError(source + ": unknown limit \"" + name + "\" (known: " + known_names() + ")");
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(v) || v <= 0.0) {
      throw InputError(source + ": limit " + name + ": \"" + value + "\" is not a positive finite number");
    }
    limits.*(f->field) = v;
  }
}

void apply_limits_from_environment() {
  const char* text = std::getenv("FLOORCAST_LIMITS");
  if (!text) return;
  InputLimits limits = input_limits();
  apply_limit_overrides(limits, text, "FLOORCAST_LIMITS");
  set_input_limits(limits);
}

double input_limit(const char* name) {
  const LimitField* f = find_field(name);
  if (!f) throw std::logic_error(std::string("input_limit: no limit named ") + name);
  return input_limits().*(f->field);
}

void check_limit(const char* name, double value, const std::string& what, const std::string& unit) {
  const double limit = input_limit(name);
  if (value <= limit) return;  // NaN fails this test and is refused
  throw LimitError(what + ": " + number_text(value) + (unit.empty() ? "" : " " + unit) + " exceeds the limit " + name +
                       " = " + number_text(limit) + " (raise it with FLOORCAST_LIMITS=" + name +
                       "=N; docs/limits.md)",
                   name);
}

double saturating_product(const std::vector<double>& factors) {
  double p = 1.0;
  for (double f : factors) {
    p *= f;
    if (!(p < 1e300)) return 1e300;
  }
  return p;
}

}  // namespace floorcast
