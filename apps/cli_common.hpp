// Shared pieces of the `floorcast` CLI: command registration, output helpers.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <memory>
#include <ostream>
#include <string>

#include "floorcast/core/types.hpp"
#include "floorcast/scenarios/driver.hpp"
#include "floorcast/scenarios/scenario.hpp"

namespace floorcast::cli {

/// The whole CLI: limits from FLOORCAST_LIMITS, every command registered, argv parsed and run.
/// Returns the exit status: 0, 1 (a check failed, e.g. a gate), 2 (bad input: "floorcast: error:
/// ..." on stderr), a CLI11 usage status, or a command's own status (CommandExit). A message
/// "floorcast: internal error" (status 1) means a bug: no input may reach it.
int run_cli(int argc, char** argv);

/// A function that adds commands to the root app. Each cmd_*.cpp registers one with
/// FLOORCAST_REGISTER_COMMANDS; main() calls them in name order.
using Registrar = void (*)(CLI::App& root);
bool add_registrar(const char* name, Registrar registrar);
void register_all(CLI::App& root);

/// The subcommand `name` of `parent`, created with `description` the first time. Lets several
/// files add sub-commands to one group (`plan`, `sim`, `bench`, ...).
CLI::App& group(CLI::App& parent, const std::string& name, const std::string& description);


/// Parses "X,Y,YAW_DEG" (metres, metres, degrees); errors name `option`.
Pose2 parse_pose(const std::string& text, const std::string& option = "--pose");
/// "X,Y,YAW_DEG" with 10 significant digits.
std::string format_pose(const Pose2& pose);

/// Adds "KEY=VALUE" to a JSON object of parameter overrides: the value parsed as JSON when it is
/// valid JSON, else taken as a string. Errors name `option` (the flag the text came with).
void add_override(nlohmann::json& overrides, const std::string& text, const std::string& option = "--matcher-param");

/// One CLI grammar (docs/cli.md): an old spelling of an option stays accepted, hidden from
/// --help, with a note on stderr naming the current spelling. Adds `old_name` storing into
/// `target` and excluding `current` (both given is a usage error). Returns the old option.
template <typename T>
CLI::Option* add_deprecated_option(CLI::App& cmd, const std::string& old_name, CLI::Option* current, T& target);
/// Prints "floorcast: note: OLD is deprecated, use NEW (docs/cli.md)" on stderr.
void deprecation_note(const std::string& old_spelling, const std::string& current_spelling);

/// Warns on stderr when `source` (an observation file, a walk folder) was recorded on a plan
/// whose hash (`recorded_hash`, hex) differs from `plan`'s: another building or another version
/// of the plan, so the estimate may be meaningless. Not refused: a plan may have been repaired
/// since. Silent when the hash was not recorded.
void warn_plan_mismatch(const std::string& source, const std::string& recorded_hash, const std::string& plan_path,
                        const FloorPlan& plan);

/// "random" or "X,Y,YAW_DEG": what --pose takes in every command that places an observer.
bool is_random_pose(const std::string& text);

/// Creates a directory (and parents); throws InputError naming it on failure.
void ensure_directory(const std::string& path);

/// Checks of numeric options with the messages of scenario keys (CLI11 adds the option name):
/// "--scale: must be in (0, 1e+06], got 0". in_range: LO <= x <= HI; above: LO < x <= HI. Integers
/// and NaN/inf are refused by every command's number validators before these run.
CLI::Validator in_range(double lo, double hi);
CLI::Validator above(double lo, double hi);
/// Refuses an empty text ("--units ''"): "must not be empty".
CLI::Validator non_empty();

/// The one output file of a command that writes one (`-o FILE`): "-" is standard output;
/// otherwise the parent folder is created and the target checked now (not a device, FIFO,
/// symbolic link or folder; not an input already read), so a wrong -o fails before the work.
void prepare_output_file(const std::string& path);
/// Where a command's own messages go: standard error when its result goes to standard output
/// (`-o -`), standard output otherwise.
std::ostream& message_stream(const std::string& output);

/// Exit codes of every command (documented in the README, "Exit codes"):
constexpr int kExitOk = 0;
constexpr int kExitCheckFailed = 1;  ///< a verdict was negative: gate regression, compare-runs differ
constexpr int kExitUsage = 2;        ///< bad command line or bad input (message names option/file/element)
constexpr int kExitNoPose = 3;       ///< the method ran but produced no pose (empty posterior, no track)
constexpr int kExitInternal = 4;     ///< a bug in floorcast (please report it)

/// Thrown by a command to end with a specific exit status after printing its own message (e.g.
/// a failed gate: 1). main() returns `code`.
struct CommandExit {
  int code = 1;
};

/// floorcast::run_scenario (scenarios/driver.hpp) with progress and notes on stderr unless quiet,
/// and the summary tables on stdout when print_summary and every unit is done: the front of `run`
/// and `compare-matchers`.
void run_scenario(const Scenario& scenario, const std::string& out, int jobs, const std::string& shard, bool quiet,
                  bool print_summary = true);

/// Writes DIR/report.html (the self-contained page `floorcast report` writes) of a finished run.
void write_html_report(const std::string& run_dir);

/// "12s", "3m05s", "1h02m"; "--" when unknown.
std::string duration_text(double seconds);

/// Progress of work with a known amount (units, observations, steps) on stderr: a bar with elapsed
/// time and ETA on a terminal; plain lines every 10% or 15 s otherwise. Silent when quiet.
class ProgressMeter {
 public:
  ProgressMeter(std::string what, bool quiet);
  /// `done` of `total` finished after `elapsed_s`; `note` is appended (e.g. "(3 resumed)").
  void update(std::size_t done, std::size_t total, double elapsed_s, const std::string& note = "");

 private:
  std::string what_;
  bool quiet_;
  bool tty_;
  int last_decile_ = -1;
  double last_print_s_ = -1.0;
};

/// For a stage whose length is not known in advance (building a matcher's distance volume,
/// matching a large plan): while alive, prints "<what>... 5s" on stderr every 5 s (every 15 s when
/// stderr is not a terminal) after the first 3 s, and "<what>: done in 12s" at the end if it
/// printed anything. Silent when quiet.
class Heartbeat {
 public:
  Heartbeat(std::string what, bool quiet);
  ~Heartbeat();
  Heartbeat(const Heartbeat&) = delete;
  Heartbeat& operator=(const Heartbeat&) = delete;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// Writes pretty JSON (2-space indent, trailing newline) atomically.
void write_json(const std::string& path, const nlohmann::ordered_json& json);

/// Cost of one child process, from wait4: CPU (user + system, all threads), wall, peak resident
/// memory.
struct ChildCost {
  double cpu_s = 0.0;
  double wall_s = 0.0;
  double max_rss_mb = 0.0;
};
/// Runs `exe args...` as a child process (stdout to stdout_path, or /dev/null when empty; stderr
/// to /dev/null) and waits for it; throws InputError naming `what` when it cannot start or does
/// not exit with status 0.
ChildCost run_child(const std::string& exe, const std::vector<std::string>& args, const std::string& stdout_path,
                    const std::string& what);

template <typename T>
CLI::Option* add_deprecated_option(CLI::App& cmd, const std::string& old_name, CLI::Option* current, T& target) {
  const std::string now = current->get_name(false, true);
  CLI::Option* old = cmd.add_option(old_name, target, "Deprecated spelling of " + now);
  old->group("");  // hidden from --help
  old->excludes(current);
  old->each([old_name, now](const std::string&) { deprecation_note(old_name, now); });
  return old;
}

}  // namespace floorcast::cli

#define FLOORCAST_CLI_CONCAT_INNER(a, b) a##b
#define FLOORCAST_CLI_CONCAT(a, b) FLOORCAST_CLI_CONCAT_INNER(a, b)
#define FLOORCAST_REGISTER_COMMANDS(fn)                                                  \
  static const bool FLOORCAST_CLI_CONCAT(floorcast_registered_, __LINE__) [[maybe_unused]] = \
      ::floorcast::cli::add_registrar(#fn, &fn)
