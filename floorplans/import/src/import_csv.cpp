// PALMS wall-segment CSV: one `x1,y1,x2,y2` per line, metres. Blank lines and `#` comments (whole
// line or trailing) are allowed; anything else that is not four finite numbers is an error naming
// the line.
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "floorcast/floorplans/import.hpp"
#include "import_common.hpp"
#include "floorcast/core/json_text.hpp"

namespace floorcast {
namespace {

using import_detail::fmt;
using import_detail::quoted;

std::string trim(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

bool parse_number(const std::string& field, double& out) {
  const std::string t = trim(field);
  if (t.empty()) return false;
  errno = 0;
  char* end = nullptr;
  out = std::strtod(t.c_str(), &end);
  return end == t.c_str() + t.size() && errno != ERANGE && std::isfinite(out);
}

}  // namespace

ImportResult import_csv_text(const std::string& text, const std::string& source, const ImportOptions& options) {
  const double thickness = import_detail::wall_thickness_or(options, 0.10, source);
  const double unit_m = import_detail::source_unit_m(options, "m", source);
  FloorPlan plan;
  plan.level = import_detail::plain_level(options, source);
  std::string body = text;
  const bool had_bom = strip_utf8_bom(body);  // Excel's "CSV UTF-8" starts with one
  std::istringstream in(body);
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    std::string content = line;
    const auto hash = content.find('#');
    if (hash != std::string::npos) content = content.substr(0, hash);
    content = trim(content);
    if (content.empty()) continue;
    std::vector<std::string> fields;
    std::stringstream fs(content);
    std::string field;
    while (std::getline(fs, field, ',')) fields.push_back(field);
    if (!content.empty() && content.back() == ',') fields.emplace_back();
    const std::string where = source + ":" + std::to_string(line_number) + ": ";
    if (fields.size() != 4) {
      throw InputError(where + "expected 4 comma-separated numbers x1,y1,x2,y2 (metres), got " +
                       std::to_string(fields.size()) + " field(s): " + quoted(trim(line)));
    }
    double v[4];
    for (int k = 0; k < 4; ++k) {
      if (!parse_number(fields[static_cast<std::size_t>(k)], v[k])) {
        static const char* kNames[4] = {"x1", "y1", "x2", "y2"};
        throw InputError(where + kNames[k] + " is not a finite number: " + quoted(trim(fields[static_cast<std::size_t>(k)])));
      }
    }
    Wall w;
    w.id = "l" + std::to_string(line_number);
    w.a_m = unit_m * Vec2(v[0], v[1]);
    w.b_m = unit_m * Vec2(v[2], v[3]);
    w.thickness_m = thickness;
    plan.walls.push_back(std::move(w));
  }
  if (plan.walls.empty()) throw InputError(source + ": no wall segments (expected lines x1,y1,x2,y2)");
  ImportResult result;
  result.source_counts.emplace_back("segments", static_cast<int>(plan.walls.size()));
  if (had_bom) result.notes.push_back("ignored the UTF-8 byte-order mark at the start of the file");
  const import_detail::UnitCheck check{unit_m, "m", "--units"};
  return import_detail::finish_import(std::move(plan), source, import_detail::stem_of(source), options, std::move(result),
                                      options.units || options.scale ? nullptr : &check);
}

}  // namespace floorcast
