#include "floorcast/scenarios/report_html.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/format.hpp"
#include "floorcast/core/image_io.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/core/types.hpp"
#include "floorcast/eval/plot.hpp"
#include "floorcast/eval/trajectory_plot.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/scenarios/runner.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;

/// Inline Markdown of one line: `code` and *em* (after escaping).
std::string inline_md(const std::string& text) {
  const std::string s = xml_escape(text);
  std::string out;
  bool code = false, em = false;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c == '`') {
      out += code ? "</code>" : "<code>";
      code = !code;
    } else if (c == '*' && !code) {
      out += em ? "</em>" : "<em>";
      em = !em;
    } else {
      out += c;
    }
  }
  if (code) out += "</code>";
  if (em) out += "</em>";
  return out;
}

std::vector<std::string> table_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::string t = line;
  if (!t.empty() && t.front() == '|') t.erase(0, 1);
  if (!t.empty() && t.back() == '|') t.pop_back();
  std::stringstream ss(t);
  std::string cell;
  while (std::getline(ss, cell, '|')) {
    const auto a = cell.find_first_not_of(' '), b = cell.find_last_not_of(' ');
    cells.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
  }
  return cells;
}

/// An embedded PNG; clicking it shows it full size (the page's one overlay, no copy of the data).
std::string png_tag(const std::string& png_bytes, const std::string& alt, const std::string& cls = "") {
  return "<img" + (cls.empty() ? std::string() : " class=\"" + cls + "\"") + " alt=\"" + xml_escape(alt) +
         "\" title=\"click: full size\" onclick=\"fullSize(this)\" src=\"data:image/png;base64," + base64_encode(png_bytes) + "\">";
}

std::string image_tag(const std::string& path, const std::string& alt, const std::string& cls = "") {
  return png_tag(read_text_file(path), alt, cls);
}

/// Sinks the heatmaps of units drawn on demand (best and worst of all units) into memory.
class MemorySink : public UnitSink {
 public:
  bool has_unit(const WorkUnit&) const override { return false; }
  void write_unit(const UnitResult&) override {}
  void write_image(const std::string& relative_path, const cv::Mat& image) override { images[relative_path] = image; }
  std::map<std::string, cv::Mat> images;
};

/// The estimate's trajectory split where it jumps (a histogram filter's argmax moves across the
/// plan between steps; drawing a line there would cross walls): pieces of consecutive points at
/// most max_step_m apart, each at least two points long.
std::vector<std::vector<Vec2>> pieces_between_jumps(const std::vector<Vec2>& xy, double max_step_m, int* jumps) {
  std::vector<std::vector<Vec2>> out(1);
  *jumps = 0;
  for (std::size_t k = 0; k < xy.size(); ++k) {
    if (k > 0 && (xy[k] - xy[k - 1]).norm() > max_step_m) {
      out.emplace_back();
      ++*jumps;
    }
    out.back().push_back(xy[k]);
  }
  return out;
}

const char* kStyle = R"(
body{font-family:system-ui,-apple-system,"Segoe UI",Helvetica,Arial,sans-serif;margin:0;color:#1d1d1f;background:#fafafa}
header{background:#1f3b57;color:#fff;padding:18px 28px}
header h1{margin:0 0 6px 0;font-size:26px}
header .meta{opacity:.85;font-size:14px}
nav{background:#e8eef4;padding:8px 28px;font-size:14px}
nav a{margin-right:18px;color:#1f3b57}
main{padding:8px 28px 40px 28px;max-width:1500px}
h2{border-bottom:2px solid #1f3b57;padding-bottom:4px;margin-top:34px}
h3{margin-top:26px}
table{border-collapse:collapse;margin:10px 0 16px 0;font-size:14px;background:#fff}
th,td{border:1px solid #b9c3cc;padding:5px 9px;text-align:right}
th{background:#dfe7ee}
td:first-child,th:first-child{text-align:left}
tr:nth-child(even) td{background:#f3f6f8}
figure{display:inline-block;margin:8px 14px 14px 0;vertical-align:top;background:#fff;border:1px solid #d5dbe0;padding:6px}
figure img{max-width:680px;height:auto;display:block;cursor:zoom-in}
#overlay{display:none;position:fixed;inset:0;background:rgba(0,0,0,.85);z-index:10;overflow:auto;cursor:zoom-out}
#overlay img{display:block;margin:20px auto;max-width:none}
header .desc{font-size:15px;margin:4px 0 8px 0;max-width:1100px}
figure.heat img{max-width:460px}
figcaption{font-size:13px;color:#444;margin-top:4px;max-width:680px}
pre{background:#fff;border:1px solid #d5dbe0;padding:10px;overflow:auto;max-height:600px;font-size:12px}
code{background:#eef1f4;padding:0 3px}
footer{color:#666;font-size:12px;padding:10px 28px}
)";

}  // namespace

std::string base64_encode(const std::string& bytes) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = static_cast<unsigned char>(bytes[i]) << 16 | static_cast<unsigned char>(bytes[i + 1]) << 8 |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += k[v >> 18 & 63];
    out += k[v >> 12 & 63];
    out += k[v >> 6 & 63];
    out += k[v & 63];
  }
  if (i < bytes.size()) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += k[v >> 18 & 63];
    out += k[v >> 12 & 63];
    out += i + 1 < bytes.size() ? k[v >> 6 & 63] : '=';
    out += '=';
  }
  return out;
}

std::string markdown_to_html(const std::string& md) {
  std::istringstream in(md);
  std::string line, out, para;
  std::vector<std::string> table;
  auto flush_para = [&] {
    if (!para.empty()) out += "<p>" + inline_md(para) + "</p>\n";
    para.clear();
  };
  auto flush_table = [&] {
    if (table.empty()) return;
    out += "<table>\n";
    for (std::size_t r = 0; r < table.size(); ++r) {
      const std::vector<std::string> cells = table_cells(table[r]);
      const bool separator = std::all_of(cells.begin(), cells.end(), [](const std::string& c) {
        return !c.empty() && c.find_first_not_of("-: ") == std::string::npos;
      });
      if (separator) continue;
      const char* tag = r == 0 ? "th" : "td";
      out += "<tr>";
      for (const std::string& c : cells) out += std::string("<") + tag + ">" + inline_md(c) + "</" + tag + ">";
      out += "</tr>\n";
    }
    out += "</table>\n";
    table.clear();
  };
  while (std::getline(in, line)) {
    if (!line.empty() && line.front() == '|') {
      flush_para();
      table.push_back(line);
      continue;
    }
    flush_table();
    if (line.empty()) {
      flush_para();
    } else if (line.front() == '#') {
      flush_para();
      std::size_t level = line.find_first_not_of('#');
      if (level == std::string::npos) level = line.size();
      const std::string text = level < line.size() ? line.substr(line.find_first_not_of(' ', level)) : "";
      // The page's own title is h1; summary headings start at h2.
      const std::size_t h = std::min<std::size_t>(level + 1, 6);
      out += "<h" + std::to_string(h) + ">" + inline_md(text) + "</h" + std::to_string(h) + ">\n";
    } else {
      para += (para.empty() ? "" : " ") + line;
    }
  }
  flush_table();
  flush_para();
  return out;
}

std::string render_run_report_html(const RunDirectory& run, const HtmlReportOptions& options) {
  const fs::path root(run.root());
  const fs::path summary_md = root / "summary.md", summary_json = root / "summary.json";
  if (!fs::is_regular_file(summary_md) || !fs::is_regular_file(summary_json)) {
    throw InputError(run.root() + ": no summary.md/summary.json: not a finished run (run it to completion, or merge its "
                                  "shards with `floorcast merge`)");
  }
  const nlohmann::json summary = read_json_file(summary_json.string());
  if (!summary.is_object()) throw InputError(summary_json.string() + ": expected a JSON object");
  const Scenario scenario = run.stored_scenario();
  const std::vector<UnitResult> units = run.read_units(scenario);

  std::ostringstream h;
  const std::string name = scenario.name;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>floorcast report: " << xml_escape(name)
    << "</title>\n<style>" << kStyle << "</style></head>\n<body>\n";
  // A header people read: the name, the description (once), what was run; the configuration's
  // identity (its hash) stays short here and in full under Configuration.
  std::string buildings;
  for (const BuildingSpec& b : scenario.buildings) buildings += (buildings.empty() ? "" : ", ") + b.label;
  std::string methods;
  for (const MatcherSpec& m : scenario.cells.front().matchers) methods += (methods.empty() ? "" : ", ") + m.label;
  if (scenario.cells.front().sequential)
    for (const TrackerSpec& t : scenario.cells.front().sequential->trackers) methods += ", " + t.label;
  h << "<header><h1>" << xml_escape(name) << "</h1>";
  if (!scenario.description.empty()) h << "<div class=\"desc\">" << xml_escape(scenario.description) << "</div>";
  h << "<div class=\"meta\">" << units.size() << (scenario.cells.front().sequential ? " walks" : " observations") << " in "
    << scenario.buildings.size() << (scenario.buildings.size() == 1 ? " building" : " buildings") << " (" << xml_escape(buildings)
    << ")";
  if (scenario.cells.size() > 1) h << " &middot; " << scenario.cells.size() << " sweep cells";
  h << " &middot; methods: " << xml_escape(methods) << " &middot; configuration <code>"
    << xml_escape(scenario.hash.substr(0, 8)) << "</code></div></header>\n";
  h << "<div id=\"overlay\" onclick=\"this.style.display='none'\"><img alt=\"full size\"></div>\n"
       "<script>function fullSize(img){var o=document.getElementById('overlay');o.firstChild.src=img.src;"
       "o.style.display='block';}</script>\n";
  h << "<nav><a href=\"#summary\">Summary</a><a href=\"#plots\">Plots</a><a href=\"#gallery\">Heatmaps</a>"
    << (scenario.cells.front().sequential ? "<a href=\"#walks\">Walks</a>" : "") << "<a href=\"#config\">Configuration</a></nav>\n<main>\n";

  // Summary tables: summary.md without its title line and its description (the header shows both).
  std::string md = read_text_file(summary_md.string());
  if (md.rfind("# ", 0) == 0) md = md.substr(md.find('\n') == std::string::npos ? md.size() : md.find('\n') + 1);
  while (!md.empty() && md.front() == '\n') md.erase(0, 1);
  if (!scenario.description.empty() && md.rfind(scenario.description, 0) == 0) md.erase(0, scenario.description.size());
  h << "<section id=\"summary\"><h2>Summary</h2>\n" << markdown_to_html(md) << "</section>\n";

  // Plots.
  h << "<section id=\"plots\"><h2>Plots</h2>\n";
  std::vector<fs::path> plots;
  if (fs::is_directory(root / "plots"))
    for (const auto& e : fs::directory_iterator(root / "plots"))
      if (e.path().extension() == ".png") plots.push_back(e.path());
  std::sort(plots.begin(), plots.end());
  if (plots.empty()) h << "<p>No plots in this run.</p>\n";
  for (const fs::path& p : plots) {
    h << "<figure>" << image_tag(p.string(), p.filename().string()) << "<figcaption>" << xml_escape(p.filename().string())
      << "</figcaption></figure>\n";
  }
  h << "</section>\n";

  // Gallery: the best and the worst of all units per method, ranked by position error (no pose
  // counts as worst). Heatmaps kept by the run are used; the others are drawn now (the unit run
  // again, the same result: units are deterministic).
  h << "<section id=\"gallery\"><h2>Best and worst heatmaps</h2>\n";
  {
    struct Ranked {
      const UnitResult* unit;
      std::string label;
      double error_m;
    };
    std::vector<Ranked> ranked;
    for (const UnitResult& u : units)
      for (const MatcherOutcome& o : u.outcomes)
        ranked.push_back({&u, o.label, o.ok && u.observation_ok ? o.estimate.position_error_m : INFINITY});
    std::stable_sort(ranked.begin(), ranked.end(), [](const Ranked& a, const Ranked& b) {
      return a.error_m != b.error_m ? a.error_m < b.error_m : a.unit->unit.id < b.unit->unit.id;
    });
    const std::size_t k = static_cast<std::size_t>(std::max(1, options.gallery_each));
    std::vector<std::string> labels;
    for (const MatcherSpec& m : scenario.cells.front().matchers) labels.push_back(m.label);
    // Per method: the k best and the k worst (all of them when there are at most 2k).
    std::vector<std::pair<std::string, std::vector<const Ranked*>>> shown;
    std::set<std::string> wanted;  // unit ids whose heatmaps are needed
    for (const std::string& label : labels) {
      std::vector<const Ranked*> mine;
      for (const Ranked& r : ranked)
        if (r.label == label) mine.push_back(&r);
      std::vector<const Ranked*> best(mine.begin(), mine.begin() + std::min(k, mine.size()));
      std::vector<const Ranked*> worst;
      if (mine.size() > 2 * k) worst.assign(mine.end() - k, mine.end());
      else if (mine.size() > k) worst.assign(mine.begin() + k, mine.end());
      shown.push_back({"Best " + std::to_string(best.size()) + ", " + label, best});
      if (!worst.empty()) shown.push_back({"Worst " + std::to_string(worst.size()) + ", " + label, worst});
      for (const Ranked* r : best) wanted.insert(r->unit->unit.id);
      for (const Ranked* r : worst) wanted.insert(r->unit->unit.id);
    }
    auto stem_of = [](const std::string& id, const std::string& label) {
      std::string stem = id + "_" + label;
      for (char& c : stem)
        if (c == '/') c = '_';
      return stem;
    };
    // Draw the missing ones.
    MemorySink drawn;
    std::vector<const UnitResult*> missing;
    for (const UnitResult& u : units) {
      if (!wanted.count(u.unit.id)) continue;
      bool all_kept = true;
      for (const MatcherOutcome& o : u.outcomes)
        all_kept = all_kept && fs::is_regular_file(root / "heatmaps" / (stem_of(u.unit.id, o.label) + ".png"));
      if (!all_kept) missing.push_back(&u);
    }
    std::string drawing_note;
    if (!missing.empty() && options.draw_missing) {
      Scenario again = scenario;
      again.output.heatmaps = std::numeric_limits<int>::max();  // every unit may draw
      try {
        const ScenarioRunner runner(again);
        for (const UnitResult* u : missing) runner.run_unit(u->unit, &drawn);
      } catch (const InputError& e) {
        drawing_note = std::string("Some heatmaps could not be drawn: ") + e.what();
      }
    }
    h << "<p>Of all " << units.size() << " units, per method, ranked by position error (no pose last); click a picture "
      << "for its full size." << (missing.empty() ? "" : " Heatmaps the run did not keep were drawn for this page.") << "</p>\n";
    if (!drawing_note.empty()) h << "<p>" << xml_escape(drawing_note) << "</p>\n";
    for (const auto& [title, list] : shown) {
      h << "<h3>" << xml_escape(title) << "</h3>\n";
      for (const Ranked* r : list) {
        const std::string stem = stem_of(r->unit->unit.id, r->label);
        const fs::path kept = root / "heatmaps" / (stem + ".png");
        std::string bytes;
        if (fs::is_regular_file(kept)) {
          bytes = read_text_file(kept.string());
        } else if (auto it = drawn.images.find("heatmaps/" + stem + ".png"); it != drawn.images.end()) {
          bytes = encode_png(it->second);
        }
        const std::string cap = r->unit->unit.id + ", " + r->label + ": " +
                                (std::isfinite(r->error_m) ? format_fixed(r->error_m, 2) + " m" : std::string("no pose"));
        if (bytes.empty()) {
          h << "<figure class=\"heat\"><figcaption>" << xml_escape(cap) << " (no heatmap)</figcaption></figure>\n";
        } else {
          h << "<figure class=\"heat\">" << png_tag(bytes, cap) << "<figcaption>" << xml_escape(cap) << "</figcaption></figure>\n";
        }
      }
    }
  }
  h << "</section>\n";

  // Sequential runs: one trajectory figure per walk and tracker (the first walks of each
  // building), estimate split where it jumps.
  if (scenario.cells.front().sequential) {
    h << "<section id=\"walks\"><h2>Walks</h2>\n<p>True path (grey), the tracker's estimate (blue; a jump of the "
         "estimate, more than " << format_fixed(options.jump_m, 1) << " m between steps, is a gap, not a line through "
         "walls), start (green), true end (black), estimated end (red).</p>\n";
    std::map<std::pair<int, std::string>, int> per;
    for (const UnitResult& u : units) {
      const nlohmann::json& walk = u.walk;
      if (!walk.contains("truth_xy") || !walk["truth_xy"].is_array()) continue;
      const fs::path plan_file = root / "plans" / (scenario.buildings[static_cast<std::size_t>(u.unit.building)].label + ".json");
      if (!fs::is_regular_file(plan_file)) continue;
      const FloorPlan plan = load_floor_plan(plan_file.string());
      std::vector<Vec2> truth;
      for (const auto& p : walk["truth_xy"]) truth.emplace_back(p.at(0).get<double>(), p.at(1).get<double>());
      for (const TrackOutcome& t : u.tracks) {
        int& n = per[{u.unit.building, t.label}];
        if (t.estimate_xy_m.empty() || n >= options.walks_each) continue;
        ++n;
        std::vector<TrajectoryLayer> lines = {{"true path", truth, cv::Scalar(120, 120, 120), 3}};
        int jumps = 0;
        bool first = true;
        for (const std::vector<Vec2>& piece : pieces_between_jumps(t.estimate_xy_m, options.jump_m, &jumps)) {
          lines.push_back({first ? "estimate" : "", piece, series_colour(0), 2});
          first = false;
        }
        std::vector<MarkerLayer> markers = {{"start", {truth.front()}, cv::Scalar(0, 160, 0), 7, true},
                                            {"true end", {truth.back()}, cv::Scalar(0, 0, 0), 6, true},
                                            {"estimated end", {t.estimate_xy_m.back()}, cv::Scalar(0, 0, 220), 6, true}};
        const double end = t.record.position_error_m.empty() ? INFINITY : t.record.position_error_m.back();
        const std::string title = u.unit.id + ", " + t.label + ": end error " +
                                  (std::isfinite(end) ? format_fixed(end, 2) + " m" : std::string("no track")) +
                                  (jumps ? ", " + std::to_string(jumps) + " jump" + (jumps > 1 ? "s" : "") : "");
        const cv::Mat img = draw_plan_with_trajectories(plan, lines, markers, title, 900);
        h << "<figure class=\"heat\">" << png_tag(encode_png(img), title) << "<figcaption>" << xml_escape(title)
          << "</figcaption></figure>\n";
      }
    }
    if (per.empty()) h << "<p>This run kept no trajectories (made before they were kept).</p>\n";
    h << "</section>\n";
  }

  // Configuration.
  const std::string resolved = read_text_file((root / "resolved_config.json").string());
  h << "<section id=\"config\"><h2>Resolved configuration</h2>\n<p>Scenario hash <code>" << xml_escape(scenario.hash)
    << "</code>. Every parameter of every stage with its value (resolved_config.json, " << format_fixed(resolved.size() / 1024.0, 1) << " KiB).</p>\n<details><summary>show</summary><pre>"
    << xml_escape(resolved) << "</pre></details>\n</section>\n";
  h << "</main>\n<footer>Generated by " << xml_escape(options.generator) << " from " << xml_escape(root.filename().string())
    << ". Self-contained: images are embedded.</footer>\n</body></html>\n";
  return h.str();
}

}  // namespace floorcast
