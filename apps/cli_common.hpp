// Shared pieces of the `floorcast` CLI: command registration, output helpers.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "floorcast/core/types.hpp"
#include "floorcast/scenarios/scenario.hpp"

namespace floorcast::cli {

/// A function that adds commands to the root app. Each cmd_*.cpp registers one with
/// FLOORCAST_REGISTER_COMMANDS; main() calls them in name order.
using Registrar = void (*)(CLI::App& root);
bool add_registrar(const char* name, Registrar registrar);
void register_all(CLI::App& root);

/// The subcommand `name` of `parent`, created with `description` the first time. Lets several
/// files add sub-commands to one group (`plan`, `sim`, `bench`, ...).
CLI::App& group(CLI::App& parent, const std::string& name, const std::string& description);

/// Where the shipped data lives (floorplans/buildings, scenarios, results/baselines): the
/// FLOORCAST_DATA_DIR environment variable when set; else <prefix>/share/floorcast next to an
/// installed binary; else the source tree the binary was built in (found by walking up from the
/// executable); else the working directory. Nothing of the build machine is compiled in.
std::string source_dir();

/// Parses "X,Y,YAW_DEG" (metres, metres, degrees); errors name `option`.
Pose2 parse_pose(const std::string& text, const std::string& option = "--pose");
/// "X,Y,YAW_DEG" with 10 significant digits.
std::string format_pose(const Pose2& pose);

/// Adds "KEY=VALUE" to a JSON object of parameter overrides: the value parsed as JSON when it is
/// valid JSON, else taken as a string.
void add_override(nlohmann::json& overrides, const std::string& text);

/// Creates a directory (and parents); throws InputError naming it on failure.
void ensure_directory(const std::string& path);

/// Thrown by a command to end with a specific exit status after printing its own message (e.g.
/// a failed gate: 1). main() returns `code`.
struct CommandExit {
  int code = 1;
};

/// Runs a scenario (or shard "I/N" of it) into the run directory `out` (resuming what is there),
/// with progress on stderr unless quiet, and writes and prints the report when every unit is
/// done: the one experiment engine behind `run` and `compare-matchers`.
void run_scenario(const Scenario& scenario, const std::string& out, int jobs, const std::string& shard, bool quiet);

/// Writes pretty JSON (2-space indent, trailing newline) atomically.
void write_json(const std::string& path, const nlohmann::ordered_json& json);

}  // namespace floorcast::cli

#define FLOORCAST_CLI_CONCAT_INNER(a, b) a##b
#define FLOORCAST_CLI_CONCAT(a, b) FLOORCAST_CLI_CONCAT_INNER(a, b)
#define FLOORCAST_REGISTER_COMMANDS(fn)                                                  \
  static const bool FLOORCAST_CLI_CONCAT(floorcast_registered_, __LINE__) [[maybe_unused]] = \
      ::floorcast::cli::add_registrar(#fn, &fn)
