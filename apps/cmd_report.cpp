// `floorcast report RUN_DIR -o report.html`: a finished run as one self-contained HTML page.
#include <filesystem>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/core/file_io.hpp"
#include "floorcast/scenarios/report_html.hpp"

namespace floorcast::cli {
namespace {

void register_report(CLI::App& root) {
  struct Options {
    std::string run_dir, out;
    int gallery = HtmlReportOptions{}.gallery_each;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = root.add_subcommand(
      "report", "One self-contained HTML page of a finished run: tables, plots, best/worst heatmaps, configuration");
  cmd->add_option("RUN_DIR", o->run_dir, "Run directory (floorcast run/merge -o DIR)")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--gallery", o->gallery, "Best and worst heatmaps shown (each)")->capture_default_str()->check(in_range(1, 100));
  cmd->add_option("-o,--output", o->out, "HTML file to write (- for standard output)")->required();
  cmd->callback([o] {
    HtmlReportOptions options;
    options.gallery_each = o->gallery;
    options.generator = std::string("floorcast ") + FLOORCAST_VERSION;
    prepare_output_file(o->out);
    const std::string html = render_run_report_html(RunDirectory(o->run_dir), options);
    write_text_file_atomic(o->out, html);
    message_stream(o->out) << "report: " << o->out << " (" << html.size() / 1024 << " KiB, self-contained)\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_report);
}  // namespace floorcast::cli
