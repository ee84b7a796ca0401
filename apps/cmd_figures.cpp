// `floorcast figures RUN_DIR [--format pdf|svg|png] [--style paper|screen] [-o DIR]`: every figure
// of a finished run through matplotlib (python/floorcast/figures.py, run by Debian's Python).
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli_common.hpp"

namespace floorcast::cli {
namespace {

/// The figures script: FLOORCAST_FIGURES_SCRIPT, else python/floorcast/figures.py in the data
/// folder (the source tree, or <prefix>/share/floorcast when installed).
std::string figures_script() {
  if (const char* env = std::getenv("FLOORCAST_FIGURES_SCRIPT"); env && *env) return env;
  return (std::filesystem::path(data_dir()) / "python" / "floorcast" / "figures.py").string();
}

/// FLOORCAST_PYTHON, else Debian's /usr/bin/python3 (where python3-matplotlib installs), else
/// python3 on PATH.
std::string python_interpreter() {
  if (const char* env = std::getenv("FLOORCAST_PYTHON"); env && *env) return env;
  if (::access("/usr/bin/python3", X_OK) == 0) return "/usr/bin/python3";
  return "python3";
}

void register_figures(CLI::App& root) {
  struct Options {
    std::string run_dir, out, format = "pdf", style = "paper";
    int walks = 4;
  };
  auto o = std::make_shared<Options>();
  CLI::App* cmd = root.add_subcommand(
      "figures", "Every figure of a finished run for a paper (matplotlib): error CDFs, recalls with intervals, sweeps, "
                 "tracking, trajectories, heatmaps with the plan as vectors");
  cmd->add_option("RUN_DIR", o->run_dir, "Run directory (floorcast run/merge -o DIR)")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--format", o->format, "pdf, svg (vector, text as text) or png (300 dpi)")
      ->capture_default_str()
      ->check(CLI::IsMember({"pdf", "svg", "png"}));
  cmd->add_option("--style", o->style, "paper: one 85 mm column, 8 pt text; screen: twice the size")
      ->capture_default_str()
      ->check(CLI::IsMember({"paper", "screen"}));
  cmd->add_option("--walks", o->walks, "Trajectory figures per building and tracker (sequential runs)")
      ->capture_default_str()
      ->check(in_range(0, 1000));
  cmd->add_option("-o,--output", o->out, "Output folder (default RUN_DIR/figures)");
  cmd->callback([o] {
    const std::string script = figures_script();
    if (!std::filesystem::is_regular_file(script)) {
      throw InputError(script + ": the figures script is missing (set FLOORCAST_FIGURES_SCRIPT or FLOORCAST_DATA_DIR)");
    }
    std::vector<std::string> args = {python_interpreter(), script, o->run_dir, "--format", o->format, "--style", o->style,
                                     "--walks", std::to_string(o->walks)};
    if (!o->out.empty()) {
      args.push_back("-o");
      args.push_back(o->out);
    }
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    const int err = posix_spawnp(&pid, args[0].c_str(), nullptr, nullptr, argv.data(), ::environ);
    if (err != 0) throw InputError("figures: cannot run " + args[0] + ": " + std::strerror(err) + " (install python3-matplotlib)");
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      // The script printed its own message (a bad run folder: 2; matplotlib missing: Python's).
      throw CommandExit{WIFEXITED(status) && WEXITSTATUS(status) == kExitUsage ? kExitUsage : kExitInternal};
    }
  });
}

}  // namespace
FLOORCAST_REGISTER_COMMANDS(register_figures);
}  // namespace floorcast::cli
