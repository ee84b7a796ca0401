// Importer entry point, shared helpers, OSM level values.
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <set>
#include <sstream>


#include "floorcast/core/image_io.hpp"
#include "floorcast/core/limits.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/import.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/floorplans/rooms.hpp"
#include "import_common.hpp"

namespace floorcast {
namespace import_detail {

std::string fmt(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

std::string quoted(const std::string& s) { return "\"" + s + "\""; }

std::string stem_of(const std::string& path) {
  std::string p = path;
  while (!p.empty() && (p.back() == '/' || p.back() == '\\')) p.pop_back();
  const auto slash = p.find_last_of("/\\");
  std::string base = slash == std::string::npos ? p : p.substr(slash + 1);
  const auto dot = base.find_last_of('.');
  if (dot != std::string::npos && dot > 0) base = base.substr(0, dot);
  return base;
}

double wall_thickness_or(const ImportOptions& options, double fallback_m, const std::string& source) {
  const double t = options.wall_thickness_m.value_or(fallback_m);
  if (!std::isfinite(t) || t <= 0.0 || t > 5.0) {
    throw InputError(source + ": wall thickness " + fmt(t) + " m is outside (0, 5]");
  }
  return t;
}

int plain_level(const ImportOptions& options, const std::string& source) {
  if (!options.level) return 0;
  const std::string& s = *options.level;
  char* end = nullptr;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0' || v < -1000 || v > 1000) {
    throw InputError(source + ": --level " + quoted(s) + " must be an integer storey for this format");
  }
  return static_cast<int>(v);
}

ImportResult finish_import(FloorPlan plan, const std::string& source, const std::string& default_name,
                           const ImportOptions& options, ImportResult partial, const UnitCheck* units,
                           bool mapped_spaces) {
  plan.name = options.name.empty() ? default_name : options.name;
  if (plan.walls.empty()) throw InputError(source + ": no walls found");
  // A level kilometres wide is refused before anything else looks at it; the finer checks (too
  // small, feet) need the cleaned, valid plan.
  if (units) check_plan_units(plan, source, units->unit_m, units->native_unit, units->remedy, true);
  partial.cleanup = cleanup_floor_plan(plan, options.cleanup, source);
  if (plan.walls.empty()) throw InputError(source + ": no walls left after clean-up (all degenerate)");
  validate_floor_plan(plan, source);
  if (units) check_plan_units(plan, source, units->unit_m, units->native_unit, units->remedy, false);
  // Free space = the union of the mapped spaces: enclosed regions no space covers are not floor.
  if (!options.unmapped_is_floor) {
    std::vector<Room> unmapped = unmapped_regions(plan, options.faithfulness);
    if (!unmapped.empty()) {
      double area = 0.0;
      for (const Room& r : unmapped) area += room_area_m2(r);
      partial.notes.push_back(std::to_string(unmapped.size()) + " enclosed region(s) of " + fmt(std::round(area * 10.0) / 10.0) +
                              " m^2 (first: " + unmapped.front().id + ", " + fmt(std::round(room_area_m2(unmapped.front()) * 10.0) / 10.0) +
                              " m^2) lie in no mapped space: labelled \"unmapped\", not floor (--unmapped-as-floor keeps them)");
      count_repair(partial, "unmapped_regions_not_floor", static_cast<int>(unmapped.size()));
      for (Room& r : unmapped) plan.rooms.push_back(std::move(r));
      validate_floor_plan(plan, source);
    }
  }
  std::vector<std::string> levels_without_spaces = std::move(partial.faithfulness.levels_without_spaces);
  partial.faithfulness = check_faithfulness(plan, options.faithfulness);
  partial.faithfulness.levels_without_spaces = std::move(levels_without_spaces);
  partial.warnings.insert(partial.warnings.begin(), partial.faithfulness.warnings.begin(), partial.faithfulness.warnings.end());
  // Somewhere to stand: `plan validate` refuses a plan without a room-sized free region. Sources
  // of mapped spaces (imdf, osm, geojson) are refused too; csv, s3d and png plans (fragments, PALMS
  // plans with doors drawn as gaps) get a warning.
  try {
    require_room_sized_free_region(plan, source);
  } catch (const LimitError&) {
    throw;
  } catch (const InputError& e) {
    if (!mapped_spaces) {
      partial.warnings.push_back(std::string(e.what()) + " (`plan validate` refuses the plan)");
    } else {
      std::string why = e.what();
      for (const std::string& w : partial.warnings) why += "; " + w;
      throw InputError(why);
    }
  }
  if (options.strict && !partial.warnings.empty()) {
    std::string why;
    for (const std::string& w : partial.warnings) why += (why.empty() ? "" : "; ") + w;
    throw InputError(source + ": --strict: the import is not faithful to its source: " + why);
  }
  partial.plan = std::move(plan);
  return partial;
}

void append_walls(FloorPlan& plan, const std::vector<Segment2>& segments, double thickness_m) {
  for (const Segment2& s : segments) {
    Wall w;
    w.id = "w" + std::to_string(plan.walls.size() + 1);
    w.a_m = s.a_m;
    w.b_m = s.b_m;
    w.thickness_m = thickness_m;
    plan.walls.push_back(std::move(w));
  }
}

double source_unit_m(const ImportOptions& options, const std::string& native_unit, const std::string& source) {
  const std::string unit = options.units.value_or(native_unit);
  double factor = 0.0;
  if (unit == "m") factor = 1.0;
  else if (unit == "cm") factor = 0.01;
  else if (unit == "mm") factor = 0.001;
  else if (unit == "ft") factor = 0.3048;
  else if (unit == "in") factor = 0.0254;
  else throw InputError(source + ": --units " + quoted(unit) + " is not a length unit (m, cm, mm, ft or in)");
  if (options.scale) {
    if (!std::isfinite(*options.scale) || !(*options.scale > 0.0)) {
      throw InputError(source + ": --scale " + fmt(*options.scale) + " must be a positive number");
    }
    factor *= *options.scale;
  }
  return factor;
}

namespace {

/// Gaps between collinear wall pieces up to 4 units long (door openings in plans that draw doors
/// as gaps, like PALMS CSVs).
std::vector<double> opening_gaps(const FloorPlan& plan) {
  std::vector<Segment2> segs;
  for (const Wall& w : plan.walls) segs.push_back(w.centerline());
  std::vector<double> gaps;
  const double tol = 1e-3 * std::max(1.0, [&] {
    double len = 0.0;
    for (const Segment2& s : segs) len = std::max(len, s.length_m());
    return len;
  }());
  // Gaps along a line: pieces on one line (collinear within 1 degree and `tol`), sorted along it.
  const std::vector<int> group = collinear_groups(segs, tol, 0.0175);
  std::map<int, std::vector<int>> members;
  for (std::size_t i = 0; i < group.size(); ++i) members[group[i]].push_back(static_cast<int>(i));
  for (const auto& [g, mem] : members) {
    if (mem.size() < 2) continue;
    const GroupLine line = fit_group_line(segs, mem);
    std::vector<std::pair<double, double>> iv;
    for (int m : mem) {
      double t0 = line.param(segs[static_cast<std::size_t>(m)].a_m), t1 = line.param(segs[static_cast<std::size_t>(m)].b_m);
      if (t1 < t0) std::swap(t0, t1);
      iv.emplace_back(t0, t1);
    }
    std::sort(iv.begin(), iv.end());
    double reach = iv.front().second;
    for (std::size_t k = 1; k < iv.size(); ++k) {
      const double gap = iv[k].first - reach;
      if (gap > 0.0 && gap <= 4.0) gaps.push_back(gap);
      reach = std::max(reach, iv[k].second);
    }
  }
  return gaps;
}

double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

void check_plan_units(const FloorPlan& plan, const std::string& source, double unit_m, const std::string& native_unit,
                      const std::string& remedy, bool too_large_only) {
  if (plan.walls.empty()) return;
  double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
  std::vector<double> lengths;
  for (const Wall& w : plan.walls) {
    for (const Vec2& p : {w.a_m, w.b_m}) {
      xmin = std::min(xmin, p.x());
      xmax = std::max(xmax, p.x());
      ymin = std::min(ymin, p.y());
      ymax = std::max(ymax, p.y());
    }
    lengths.push_back(w.length_m());
  }
  const double extent = std::max(xmax - xmin, ymax - ymin);
  const double median_wall = median_of(lengths);
  const std::string read_as = remedy == "--resolution" ? std::string("at the given resolution")
                                                       : "read as " + native_unit + (native_unit == "m" ? "etres" : "");
  const std::string what = source + ": " + read_as + ", the plan is " + fmt(xmax - xmin) + " x " + fmt(ymax - ymin) +
                           " m with a median wall of " + fmt(median_wall) + " m";
  // How to say "multiply by f": a unit when one fits, else a scale.
  auto fix = [&](double f, const std::string& unit_word) {
    if (remedy == "--resolution") return std::string("Check --resolution (metres per pixel)");
    const double target = unit_m * f;
    for (const auto& [name, m] : std::vector<std::pair<std::string, double>>{
             {"m", 1.0}, {"cm", 0.01}, {"mm", 0.001}, {"ft", 0.3048}, {"in", 0.0254}}) {
      if (std::abs(target - m) <= 1e-9 * m) {
        return "Pass --units " + name + " (or --scale " + fmt(f) + "), or --units " + native_unit + " if they really are " +
               unit_word;
      }
    }
    return "Pass --scale " + fmt(f) + ", or --units " + native_unit + " if the coordinates really are " + unit_word;
  };
  const std::string native_word = native_unit == "m" ? "metres" : native_unit == "mm" ? "millimetres" : native_unit;
  // No level of a building is 2 km across; a plan in millimetres or centimetres read as metres is.
  constexpr double kMaxExtentM = 2000.0, kMinExtentM = 1.0;
  if (extent > kMaxExtentM) {
    // Divide by 1,000 or 100: whichever brings the median wall nearer a typical 4 m.
    const bool thousand = std::abs(std::log(median_wall * 0.001 / 4.0)) <= std::abs(std::log(median_wall * 0.01 / 4.0));
    const double f = thousand ? 0.001 : 0.01;
    throw InputError(what + ": no building level is that large (" + fmt(extent * f) + " m across at " + fmt(f) +
                     " of the size). " + fix(f, native_word));
  }
  if (too_large_only) return;
  if (extent < kMinExtentM) {
    throw InputError(what + ": too small for a building level. " +
                     (remedy == "--resolution" ? std::string("Check --resolution (metres per pixel)")
                                               : "Give the source's unit with --units (m, cm, mm, ft, in) or --scale"));
  }
  if (remedy == "--resolution") return;
  // Feet read as metres: doors 2.3-3.6 "m" wide. Evidence from the doors, else from the gaps
  // between collinear wall pieces (plans that draw doors as gaps); at least 3 of them.
  std::vector<double> widths;
  for (const Door& d : plan.doors) widths.push_back(d.width_m);
  const bool from_doors = widths.size() >= 3;
  const std::vector<double> gaps = from_doors ? widths : opening_gaps(plan);
  if (gaps.size() >= 3) {
    const double median_gap = median_of(gaps);
    if (median_gap >= 2.3 && median_gap <= 3.6) {
      throw InputError(what + ", and its " + std::to_string(gaps.size()) +
                       (from_doors ? " doors are" : " door openings (gaps between collinear walls) are") + " a median " +
                       fmt(median_gap) + " m wide: doors are 0.7-1.1 m, i.e. 2.3-3.6 ft, so the coordinates look like feet. " +
                       fix(0.3048, native_word));
    }
  }
}

void count_repair(ImportResult& result, const std::string& name, int n) {
  if (n == 0) return;
  for (auto& [what, count] : result.repairs) {
    if (what == name) {
      count += n;
      return;
    }
  }
  result.repairs.emplace_back(name, n);
}

double distance_to_segments(const Vec2& p, const std::vector<Segment2>& segments) {
  double best = std::numeric_limits<double>::infinity();
  for (const Segment2& s : segments) best = std::min(best, point_segment_distance(p, s));
  return best;
}

BoundaryPieces classify_boundaries(const std::vector<BoundaryEdge>& edges, double tolerance_m,
                                   double angle_tolerance_rad) {
  BoundaryPieces out;
  std::vector<Segment2> segs;
  segs.reserve(edges.size());
  for (const BoundaryEdge& e : edges) segs.push_back(e.segment_m);
  for (std::vector<int> mem : collinear_runs(segs, tolerance_m, angle_tolerance_rad)) {
    mem.erase(std::remove_if(mem.begin(), mem.end(), [&](int m) { return !(segs[static_cast<std::size_t>(m)].length_m() > 0.0); }),
              mem.end());
    if (mem.empty()) continue;
    const GroupLine line = fit_group_line(segs, mem);
    std::vector<std::pair<double, double>> iv;
    std::vector<double> cuts;
    for (int m : mem) {
      double t0 = line.param(segs[static_cast<std::size_t>(m)].a_m), t1 = line.param(segs[static_cast<std::size_t>(m)].b_m);
      if (t1 < t0) std::swap(t0, t1);
      iv.emplace_back(t0, t1);
      cuts.push_back(t0);
      cuts.push_back(t1);
    }
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    // 0 = uncovered, 1 = wall, 2 = open.
    int run_class = 0;
    double run_start = 0.0;
    auto flush = [&](double t_end) {
      if (run_class == 0) return;
      Segment2 s{line.at(run_start), line.at(t_end)};
      (run_class == 1 ? out.walls : out.open).push_back(s);
    };
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      const double mid = 0.5 * (cuts[k] + cuts[k + 1]);
      bool walled = false, all_open = true;
      std::set<int> owners;
      bool covered = false;
      for (std::size_t q = 0; q < mem.size(); ++q) {
        if (iv[q].first <= mid && mid <= iv[q].second) {
          const BoundaryEdge& e = edges[static_cast<std::size_t>(mem[q])];
          covered = true;
          walled = walled || e.walled;
          all_open = all_open && e.open;
          owners.insert(e.owner);
        }
      }
      int cls = 0;
      if (covered) cls = (walled && !(owners.size() >= 2 && all_open)) ? 1 : 2;
      if (cls != run_class) {
        flush(cuts[k]);
        run_class = cls;
        run_start = cuts[k];
      }
    }
    if (!cuts.empty()) flush(cuts.back());
  }
  return out;
}

}  // namespace import_detail

using import_detail::fmt;
using import_detail::quoted;

ImportFormat parse_import_format(const std::string& name) {
  std::string n = name;
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (n == "csv") return ImportFormat::kCsv;
  if (n == "s3d" || n == "structured3d") return ImportFormat::kS3d;
  if (n == "png") return ImportFormat::kPng;
  if (n == "imdf") return ImportFormat::kImdf;
  if (n == "osm") return ImportFormat::kOsm;
  if (n == "geojson") return ImportFormat::kGeojson;
  throw InputError("unknown import format " + quoted(name) + " (expected csv, s3d, png, imdf, osm or geojson)");
}

const char* import_format_name(ImportFormat format) {
  switch (format) {
    case ImportFormat::kCsv: return "csv";
    case ImportFormat::kS3d: return "s3d";
    case ImportFormat::kPng: return "png";
    case ImportFormat::kImdf: return "imdf";
    case ImportFormat::kOsm: return "osm";
    case ImportFormat::kGeojson: return "geojson";
  }
  return "?";
}

namespace {

bool is_directory(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool is_file(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

}  // namespace

ImportResult import_floor_plan(const std::string& path, ImportFormat format, const ImportOptions& options) {
  ImportOptions opts = options;
  switch (format) {
    case ImportFormat::kCsv:
      return import_csv_text(read_text_file(path), path, opts);
    case ImportFormat::kS3d: {
      // A scene folder or its annotation_3d.json; the plan is named after the scene folder.
      std::string file = path;
      if (is_directory(path)) file = path + "/annotation_3d.json";
      if (options.name.empty() && import_detail::stem_of(file) == "annotation_3d") {
        const auto slash = file.find_last_of('/');
        const std::string folder = slash == std::string::npos ? std::string(".") : file.substr(0, slash);
        opts.name = import_detail::stem_of(folder == "." ? "structured3d" : folder);
      }
      return import_s3d_json(read_text_file(file), file, opts);
    }
    case ImportFormat::kPng: {
      if (!is_file(path)) throw InputError(path + ": cannot read image (no such file)");
      const cv::Mat image = read_image(path);
      return import_png_image(image, path, opts);
    }
    case ImportFormat::kImdf: {
      if (!is_directory(path)) {
        throw InputError(path + ": imdf import expects a folder holding level.geojson, unit.geojson and "
                                "opening.geojson (unzip an .imdf archive first)");
      }
      const std::string level = read_text_file(path + "/level.geojson");
      const std::string unit = read_text_file(path + "/unit.geojson");
      std::string opening, building;
      const bool has_openings = is_file(path + "/opening.geojson");
      if (has_openings) opening = read_text_file(path + "/opening.geojson");
      if (is_file(path + "/building.geojson")) building = read_text_file(path + "/building.geojson");
      ImportResult r = import_imdf_texts(level, unit, opening, building, path, opts);
      if (!has_openings) r.notes.insert(r.notes.begin(), path + ": no opening.geojson, so no doors");
      return r;
    }
    case ImportFormat::kOsm:
      return import_osm_xml(read_text_file(path), path, opts);
    case ImportFormat::kGeojson:
      return import_geojson_text(read_text_file(path), path, opts);
  }
  throw InputError(path + ": unknown import format");
}

// ---- OSM level values ---------------------------------------------------------------------------

namespace {

std::string trim(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

bool parse_level_number(const std::string& text, double& out) {
  const std::string s = trim(text);
  if (s.empty()) return false;
  // digits with an optional sign and fraction; no exponents, no hex, no inf/nan.
  std::size_t i = 0;
  if (s[i] == '-' || s[i] == '+') ++i;
  bool digits = false, dot = false;
  for (; i < s.size(); ++i) {
    if (std::isdigit(static_cast<unsigned char>(s[i]))) {
      digits = true;
    } else if (s[i] == '.' && !dot) {
      dot = true;
    } else {
      return false;
    }
  }
  if (!digits) return false;
  out = std::strtod(s.c_str(), nullptr);
  return std::isfinite(out);
}

}  // namespace

bool parse_osm_levels(const std::string& value, std::vector<std::pair<double, double>>& ranges) {
  ranges.clear();
  std::string token;
  std::stringstream ss(value);
  while (std::getline(ss, token, ';')) {
    const std::string t = trim(token);
    if (t.empty()) return false;
    double single = 0.0;
    if (parse_level_number(t, single)) {
      ranges.emplace_back(single, single);
      continue;
    }
    // A range "a~b" (OSM-derived GeoJSON exports).
    const auto tilde = t.find('~');
    if (tilde != std::string::npos) {
      double lo = 0.0, hi = 0.0;
      if (!parse_level_number(t.substr(0, tilde), lo) || !parse_level_number(t.substr(tilde + 1), hi)) return false;
      if (hi < lo) std::swap(lo, hi);
      ranges.emplace_back(lo, hi);
      continue;
    }
    // A range "a-b": the separating dash follows a digit (or a dot) of the first number.
    bool ok = false;
    for (std::size_t k = 1; k < t.size(); ++k) {
      if (t[k] != '-') continue;
      const char prev = t[k - 1];
      if (!(std::isdigit(static_cast<unsigned char>(prev)) || prev == '.' || prev == ' ')) continue;
      double lo = 0.0, hi = 0.0;
      if (parse_level_number(t.substr(0, k), lo) && parse_level_number(t.substr(k + 1), hi)) {
        if (hi < lo) std::swap(lo, hi);
        ranges.emplace_back(lo, hi);
        ok = true;
        break;
      }
    }
    if (!ok) return false;
  }
  if (value.empty() || value.back() == ';') return false;
  return !ranges.empty();
}

}  // namespace floorcast
