// Running another program with a time limit: the external-program matcher (match/external.hpp)
// and the CLI's benches run children through this one function.
#pragma once

#include <string>
#include <vector>

namespace floorcast {

struct ProcessOptions {
  /// Seconds before the child and every process it started (its process group) are killed;
  /// <= 0 waits without limit.
  double timeout_s = 0.0;
  /// Files receiving the child's standard output / error ("" = /dev/null); created or truncated.
  std::string stdout_path;
  std::string stderr_path;
};

struct ProcessResult {
  bool started = false;     ///< false: the program could not be run (`error` says why)
  std::string error;
  bool timed_out = false;   ///< killed after timeout_s
  int exit_code = -1;       ///< when it exited normally
  int signal = 0;           ///< the signal that ended it, 0 when it exited
  double wall_s = 0.0;
  double cpu_s = 0.0;       ///< user + system time of the child and its waited-for children
  double max_rss_mb = 0.0;
  bool ok() const { return started && !timed_out && signal == 0 && exit_code == 0; }
  /// One sentence: "exited with status 3", "was killed by signal 11 (Segmentation fault)",
  /// "did not finish within 5 s and was killed", "could not be started: ...".
  std::string describe(double timeout_s) const;
};

/// Runs argv[0] (searched on PATH when it has no slash) with arguments argv[1..] in its own
/// process group, waits for it (or kills the group at the timeout) and reports how it ended.
/// Never throws for the child's behaviour; thread-safe (posix_spawn).
ProcessResult run_process(const std::vector<std::string>& argv, const ProcessOptions& options = {});

/// The last `max_lines` lines of a text file (at most 4 KB), "" when it is missing or empty: the
/// tail of a child's standard error for messages.
std::string file_tail(const std::string& path, int max_lines = 12);

}  // namespace floorcast
