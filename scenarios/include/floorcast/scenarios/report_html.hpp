// `floorcast report RUN_DIR -o report.html`: one self-contained HTML page per finished run, for
// people and for sharing (one file, no external resources): the summary tables, every plot, a
// gallery of the best and worst posterior heatmaps over all units (drawn when the run did not keep
// them), one trajectory figure per walk in sequential runs, the run's identity and its resolved
// configuration. Images are inlined as data: URIs; a click shows one full size.
#pragma once

#include <string>

#include "floorcast/scenarios/run_directory.hpp"

namespace floorcast {

struct HtmlReportOptions {
  int gallery_each = 6;  ///< best and worst heatmaps shown per method (each), over all units
  /// Draw the heatmaps of the shown units that the run did not keep (their units run again:
  /// deterministic, the same results).
  bool draw_missing = true;
  int walks_each = 3;     ///< sequential runs: trajectory figures per building and tracker
  double jump_m = 1.5;    ///< an estimate moving farther than this between steps jumps
  
  std::string generator = "floorcast";  ///< "floorcast 0.1.0": named in the footer
};

/// The HTML page of a finished run (summary.json, summary.md present). Throws InputError naming
/// the folder when the run is not complete (no report written by `run`/`merge` yet).
std::string render_run_report_html(const RunDirectory& run, const HtmlReportOptions& options = {});

/// Standard base64 (RFC 4648, with padding).
std::string base64_encode(const std::string& bytes);

/// Minimal Markdown -> HTML of what floorcast's summary.md uses: # headings, | tables |, *em*,
/// `code`, paragraphs. Text is HTML-escaped.
std::string markdown_to_html(const std::string& markdown);

}  // namespace floorcast
