// `floorcast params`: every parameter set with its defaults (JSON), or docs/parameters.md (Markdown),
// listed from the field lists the code reads and writes parameters with.
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "floorcast/scenarios/parameters.hpp"

namespace floorcast::cli {
namespace {

void register_params(CLI::App& root) {
  struct Options {
    bool markdown = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = root.add_subcommand(
      "params", "Every parameter of the shared block, the matchers and the trackers with its default (JSON), or the "
                "docs table (--markdown: docs/parameters.md)");
  cmd->add_flag("--markdown", o->markdown, "Print docs/parameters.md (key, default, type, range, meaning)");
  cmd->callback([o] {
    const std::vector<ParameterSet> sets = parameter_sets();
    if (o->markdown) std::cout << parameters_markdown(sets);
    else std::cout << parameter_defaults_json(sets).dump(2) << "\n";
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_params);
}  // namespace floorcast::cli
