#include "cli_common.hpp"

#include <cstring>
#include "floorcast/core/file_io.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/core/limits.hpp"
#include "floorcast/core/process.hpp"
#include "floorcast/match/external.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <iostream>
#include <mutex>
#include <thread>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <system_error>
#include <utility>
#include <vector>

#include "floorcast/floorplans/io.hpp"
#include "floorcast/core/hash.hpp"
#include "floorcast/core/math.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast::cli {
namespace {

std::vector<std::pair<std::string, Registrar>>& registrars() {
  static std::vector<std::pair<std::string, Registrar>> list;
  return list;
}

}  // namespace

namespace {

/// Every floating-point option of every command refuses NaN and inf (CLI11 converts "nan" and
/// "inf", and its Range validator lets NaN through: every comparison with NaN is false).
void refuse_non_finite_numbers(CLI::App& app) {
  static const CLI::Validator finite(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (end != text.c_str() && !std::isfinite(v)) return "value " + text + " is not a finite number";
        return std::string();
      },
      "", "FINITE");
  // CLI11 2.1 turns "-1" into 18446744073709551615 for an unsigned option and wraps numbers
  // beyond the type: integers must be written as such and fit.
  static const CLI::Validator non_negative_integer(
      [](std::string& text) -> std::string {
        if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) {
          return "value " + text + " is not a non-negative integer";
        }
        errno = 0;
        (void)std::strtoull(text.c_str(), nullptr, 10);
        if (errno == ERANGE) return "value " + text + " is out of range (at most 18446744073709551615)";
        return std::string();
      },
      "", "UNSIGNED");
  static const CLI::Validator integer(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        errno = 0;
        const long long v = std::strtoll(text.c_str(), &end, 10);
        if (end == text.c_str() || *end != '\0') return "value " + text + " is not an integer";
        if (errno == ERANGE || v < INT_MIN || v > INT_MAX) return "value " + text + " is out of range for an integer";
        return std::string();
      },
      "", "INTEGER");
  for (CLI::Option* opt : app.get_options()) {
    const std::string type = opt->get_type_name();
    if (type.find("FLOAT") != std::string::npos) opt->check(finite);
    else if (type.find("UINT") != std::string::npos) opt->check(non_negative_integer);
    else if (type.find("INT") != std::string::npos) opt->check(integer);
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) refuse_non_finite_numbers(*sub);
}

}  // namespace

int run_cli(int argc, char** argv) {
  CLI::App app{"floorcast: floor-plan-based indoor localization test-bed (PALMS / PALMS+ family)"};
  app.set_version_flag("--version", std::string("floorcast ") + FLOORCAST_VERSION);
  app.require_subcommand(1);
  register_all(app);
  refuse_non_finite_numbers(app);
  // The command's inputs are remembered as they are read: no output may replace one.
  const CommandFiles files;
  try {
    apply_limits_from_environment();
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {  // a usage error: one exit code (README, "Exit codes")
    (void)app.exit(e);
    return kExitUsage;
  } catch (const CommandExit& e) {
    return e.code;
  } catch (const InputError& e) {
    std::cerr << "floorcast: error: " << e.what() << "\n";
    return kExitUsage;
  } catch (const ExternalMethodError& e) {  // a user's matcher (program, module) misbehaved: its input, not ours
    std::cerr << "floorcast: error: " << e.what() << "\n";
    return kExitUsage;
  } catch (const std::exception& e) {
    std::cerr << "floorcast: internal error: " << e.what() << "\n";
    return kExitInternal;
  }
  return 0;
}

bool add_registrar(const char* name, Registrar registrar) {
  registrars().emplace_back(name, registrar);
  return true;
}

void register_all(CLI::App& root) {
  auto list = registrars();
  std::sort(list.begin(), list.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [name, fn] : list) fn(root);
}

CLI::App& group(CLI::App& parent, const std::string& name, const std::string& description) {
  for (CLI::App* sub : parent.get_subcommands([](CLI::App*) { return true; })) {
    if (sub->get_name() == name) return *sub;
  }
  CLI::App* sub = parent.add_subcommand(name, description);
  sub->require_subcommand(1);
  return *sub;
}

Pose2 parse_pose(const std::string& text, const std::string& option) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    while (used < item.size() && std::isspace(static_cast<unsigned char>(item[used]))) ++used;
    if (item.empty() || used != item.size() || !std::isfinite(x)) {
      throw InputError(option + " \"" + text + "\": \"" + item + "\" is not a finite number (expected X,Y,YAW_DEG)");
    }
    v.push_back(x);
  }
  if (v.size() != 3 || (!text.empty() && text.back() == ',')) {
    throw InputError(option + " \"" + text + "\": expected three numbers X,Y,YAW_DEG");
  }
  return {v[0], v[1], v[2] * kPi / 180.0};
}

std::string format_pose(const Pose2& p) {
  std::ostringstream s;
  s << std::setprecision(10) << p.x_m << "," << p.y_m << "," << p.yaw_rad * 180.0 / kPi;
  return s.str();
}


void add_override(nlohmann::json& overrides, const std::string& text, const std::string& option) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) throw InputError(option + " \"" + text + "\": expected KEY=VALUE");
  const std::string key = text.substr(0, eq), value = text.substr(eq + 1);
  // Valid JSON is taken as JSON (depth-limited); anything else is the string itself, except text
  // that opens an object or a list: that is meant as JSON, and its error (a duplicate key, a
  // missing bracket) is reported instead of passing the text on as a string.
  nlohmann::json parsed;
  try {
    parsed = parse_json_text(value, option + " " + key);
  } catch (const LimitError&) {
    throw;
  } catch (const InputError&) {
    const auto first = value.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && (value[first] == '{' || value[first] == '[')) throw;
    parsed = value;
  }
  overrides[key] = parsed;
}

void ensure_directory(const std::string& path) { create_directories_or_throw(path); }

namespace {

CLI::Validator interval(double lo, double hi, bool open_below) {
  std::ostringstream desc;
  desc << (open_below ? "(" : "[") << lo << ", " << hi << "]";
  const std::string range = desc.str();
  return CLI::Validator(
      [lo, hi, open_below, range](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0') return "must be a number, got \"" + text + "\"";
        if (!std::isfinite(v)) return "value " + text + " is not a finite number";
        if (!(open_below ? v > lo : v >= lo) || !(v <= hi)) return "must be in " + range + ", got " + text;
        return std::string();
      },
      range, "RANGE");
}

}  // namespace

CLI::Validator in_range(double lo, double hi) { return interval(lo, hi, false); }
CLI::Validator above(double lo, double hi) { return interval(lo, hi, true); }

CLI::Validator non_empty() {
  return CLI::Validator([](std::string& text) { return text.empty() ? std::string("must not be empty") : std::string(); },
                        "", "NONEMPTY");
}

void prepare_output_file(const std::string& path) {
  if (path == "-") return;
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  check_output_path(path);
  if (!parent.empty()) ensure_directory(parent.string());
}

std::ostream& message_stream(const std::string& output) { return output == "-" ? std::cerr : std::cout; }

void deprecation_note(const std::string& old_spelling, const std::string& current_spelling) {
  static std::mutex mutex;
  static std::vector<std::string> said;
  std::lock_guard<std::mutex> lock(mutex);
  if (std::find(said.begin(), said.end(), old_spelling) != said.end()) return;
  said.push_back(old_spelling);
  std::cerr << "floorcast: note: " << old_spelling << " is deprecated, use " << current_spelling
            << " (the command-line grammar: docs/cli.md)\n";
}

bool is_random_pose(const std::string& text) { return text == "random"; }

void warn_plan_mismatch(const std::string& source, const std::string& recorded_hash, const std::string& plan_path,
                        const FloorPlan& plan) {
  if (recorded_hash.empty()) return;
  const std::string have = hex64(plan_hash(plan));
  if (recorded_hash == have) return;
  std::cerr << "floorcast: warning: " << source << " was made on a plan with hash " << recorded_hash << ", but "
            << plan_path << " has hash " << have
            << " (another building or another version of the plan): the estimate may be meaningless\n";
}

std::string duration_text(double s) {
  if (!std::isfinite(s) || s < 0) return "--";
  char buf[32];
  const int total = static_cast<int>(std::lround(s));
  if (total >= 3600) std::snprintf(buf, sizeof buf, "%dh%02dm", total / 3600, (total / 60) % 60);
  else if (total >= 60) std::snprintf(buf, sizeof buf, "%dm%02ds", total / 60, total % 60);
  else std::snprintf(buf, sizeof buf, "%ds", total);
  return buf;
}

ProgressMeter::ProgressMeter(std::string what, bool quiet)
    : what_(std::move(what)), quiet_(quiet), tty_(isatty(fileno(stderr)) != 0) {}

void ProgressMeter::update(std::size_t done, std::size_t total, double elapsed_s, const std::string& note) {
  if (quiet_) return;
  const double eta = done > 0 ? elapsed_s / static_cast<double>(done) * static_cast<double>(total - std::min(done, total)) : NAN;
  const std::string tail = note.empty() ? "" : " " + note;
  if (tty_) {
    const int width = 30;
    const int filled = total ? static_cast<int>(width * std::min(done, total) / total) : width;
    std::fprintf(stderr, "\r[%s%s] %zu/%zu %s%s  elapsed %s  ETA %s   ", std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), done, total, what_.c_str(), tail.c_str(),
                 duration_text(elapsed_s).c_str(), duration_text(eta).c_str());
    if (done >= total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
    return;
  }
  const int decile = total ? static_cast<int>(10 * std::min(done, total) / total) : 10;
  if (done == 0 || done >= total || decile > last_decile_ || elapsed_s - last_print_s_ >= 15.0) {
    std::fprintf(stderr, "progress: %zu/%zu %s%s, elapsed %s, ETA %s\n", done, total, what_.c_str(), tail.c_str(),
                 duration_text(elapsed_s).c_str(), duration_text(eta).c_str());
    last_decile_ = decile;
    last_print_s_ = elapsed_s;
  }
}

struct Heartbeat::State {
  std::string what;
  std::mutex mutex;
  std::condition_variable wake;
  bool stop = false;
  bool printed = false;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  std::thread thread;
};

Heartbeat::Heartbeat(std::string what, bool quiet) {
  if (quiet) return;
  state_ = std::make_unique<State>();
  state_->what = std::move(what);
  State* st = state_.get();
  const double period = isatty(fileno(stderr)) ? 5.0 : 15.0;
  st->thread = std::thread([st, period] {
    std::unique_lock<std::mutex> lock(st->mutex);
    double next = 3.0;
    while (!st->stop) {
      st->wake.wait_until(lock, st->start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                  std::chrono::duration<double>(next)));
      if (st->stop) break;
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - st->start).count();
      if (t >= next) {
        std::cerr << st->what << "... " << duration_text(t) << "\n";
        st->printed = true;
        next = t + period;
      }
    }
  });
}

Heartbeat::~Heartbeat() {
  if (!state_) return;
  {
    std::lock_guard<std::mutex> lock(state_->mutex);
    state_->stop = true;
  }
  state_->wake.notify_all();
  state_->thread.join();
  if (state_->printed) {
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - state_->start).count();
    std::cerr << state_->what << ": done in " << duration_text(t) << "\n";
  }
}

void write_json(const std::string& path, const nlohmann::ordered_json& json) {
  write_text_file_atomic(path, json.dump(2) + "\n");
}

ChildCost run_child(const std::string& exe, const std::vector<std::string>& args, const std::string& stdout_path,
                    const std::string& what) {
  std::vector<std::string> argv{exe};
  argv.insert(argv.end(), args.begin(), args.end());
  ProcessOptions options;
  options.stdout_path = stdout_path;
  const ProcessResult r = run_process(argv, options);
  if (!r.started) throw InputError(what + ": cannot run " + exe + ": " + r.error);
  if (!r.ok()) {
    std::string cmd = exe;
    for (const std::string& a : args) cmd += " " + a;
    throw InputError(what + ": `" + cmd + "` did not exit with status 0 (it " + r.describe(0.0) + ")");
  }
  ChildCost c;
  c.cpu_s = r.cpu_s;
  c.wall_s = r.wall_s;
  c.max_rss_mb = r.max_rss_mb;
  return c;
}

}  // namespace floorcast::cli
