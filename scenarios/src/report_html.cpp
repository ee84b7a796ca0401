#include "floorcast/scenarios/report_html.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <vector>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/format.hpp"
#include "floorcast/core/types.hpp"

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

std::string image_tag(const std::string& path, const std::string& alt, const std::string& cls = "") {
  return "<img" + (cls.empty() ? std::string() : " class=\"" + cls + "\"") + " alt=\"" + xml_escape(alt) +
         "\" src=\"data:image/png;base64," + base64_encode(read_text_file(path)) + "\">";
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
figure img{max-width:680px;height:auto;display:block}
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
  const nlohmann::json summary = nlohmann::json::parse(read_text_file(summary_json.string()), nullptr, false);
  if (summary.is_discarded() || !summary.is_object()) throw InputError(summary_json.string() + ": malformed JSON");
  const Scenario scenario = run.stored_scenario();
  const std::vector<UnitResult> units = run.read_units(scenario);

  std::ostringstream h;
  const std::string name = scenario.name;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>floorcast report: " << xml_escape(name)
    << "</title>\n<style>" << kStyle << "</style></head>\n<body>\n";
  h << "<header><h1>" << xml_escape(name) << "</h1><div class=\"meta\">scenario hash <code>" << xml_escape(scenario.hash)
    << "</code> &middot; " << units.size() << " work units &middot; " << scenario.cells.size() << " cells &middot; "
    << scenario.buildings.size() << " buildings</div></header>\n";
  h << "<nav><a href=\"#summary\">Summary</a><a href=\"#plots\">Plots</a><a href=\"#gallery\">Heatmaps</a>"
       "<a href=\"#config\">Configuration</a></nav>\n<main>\n";
  if (!scenario.description.empty()) h << "<p>" << xml_escape(scenario.description) << "</p>\n";

  // Summary tables: summary.md without its own title line (the header shows it).
  std::string md = read_text_file(summary_md.string());
  if (md.rfind("# ", 0) == 0) md = md.substr(md.find('\n') == std::string::npos ? md.size() : md.find('\n') + 1);
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

  // Gallery: heatmaps ranked by the matcher's position error (no pose counts as worst).
  struct Heat {
    fs::path file;
    std::string caption;
    double error_m;
  };
  std::vector<Heat> heats;
  std::map<std::string, const UnitResult*> by_file_prefix;
  for (const UnitResult& u : units) {
    std::string prefix = u.unit.id;
    for (char& c : prefix)
      if (c == '/') c = '_';
    by_file_prefix[prefix] = &u;
  }
  if (fs::is_directory(root / "heatmaps")) {
    for (const auto& e : fs::directory_iterator(root / "heatmaps")) {
      if (e.path().extension() != ".png") continue;
      const std::string stem = e.path().stem().string();
      for (const auto& [prefix, u] : by_file_prefix) {
        if (stem.rfind(prefix + "_", 0) != 0) continue;
        const std::string label = stem.substr(prefix.size() + 1);
        for (const MatcherOutcome& o : u->outcomes) {
          if (o.label != label) continue;
          const double err = o.ok ? o.estimate.position_error_m : INFINITY;
          const std::string cap = u->unit.id + ", " + label + ": " +
                                  (o.ok ? format_fixed(o.estimate.position_error_m, 2) + " m, " +
                                              format_fixed(o.estimate.yaw_error_deg, 1) + " deg"
                                        : std::string("no pose"));
          heats.push_back({e.path(), cap, err});
        }
      }
    }
  }
  std::sort(heats.begin(), heats.end(), [](const Heat& a, const Heat& b) {
    return a.error_m != b.error_m ? a.error_m < b.error_m : a.file < b.file;
  });
  h << "<section id=\"gallery\"><h2>Best and worst heatmaps</h2>\n";
  if (heats.empty()) {
    h << "<p>This run kept no heatmaps (<code>output.heatmaps: 0</code>).</p>\n";
  } else {
    const std::size_t k = static_cast<std::size_t>(std::max(1, options.gallery_each));
    auto show = [&](std::size_t from, std::size_t to, const std::string& title) {
      h << "<h3>" << title << "</h3>\n";
      for (std::size_t i = from; i < to; ++i)
        h << "<figure class=\"heat\">" << image_tag(heats[i].file.string(), heats[i].caption) << "<figcaption>"
          << xml_escape(heats[i].caption) << "</figcaption></figure>\n";
    };
    h << "<p>Of the " << heats.size()
      << " heatmaps kept (the first points of each building), ranked by position error.</p>\n";
    if (heats.size() <= 2 * k) {
      show(0, heats.size(), "All, best first");
    } else {
      show(0, k, "Best " + std::to_string(k));
      show(heats.size() - k, heats.size(), "Worst " + std::to_string(k));
    }
  }
  h << "</section>\n";

  // Configuration.
  const std::string resolved = read_text_file((root / "resolved_config.json").string());
  h << "<section id=\"config\"><h2>Resolved configuration</h2>\n<p>Every parameter of every stage with its value "
       "(resolved_config.json, " << format_fixed(resolved.size() / 1024.0, 1) << " KiB).</p>\n<details><summary>show</summary><pre>"
    << xml_escape(resolved) << "</pre></details>\n</section>\n";
  h << "</main>\n<footer>Generated by " << xml_escape(options.generator) << " from " << xml_escape(root.filename().string())
    << ". Self-contained: images are embedded.</footer>\n</body></html>\n";
  return h.str();
}

}  // namespace floorcast
