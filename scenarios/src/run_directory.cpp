#include "floorcast/core/image_io.hpp"
#include "floorcast/scenarios/run_directory.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/hash.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/scenarios/driver.hpp"

namespace floorcast {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using OJson = nlohmann::ordered_json;

namespace {

void make_dirs(const fs::path& p) {
  std::error_code ec;
  fs::create_directories(p, ec);
  if (ec || !fs::is_directory(p)) throw InputError(p.string() + ": cannot create directory: " + (ec ? ec.message() : "not a directory"));
}

Json read_json(const fs::path& p) { return read_json_file(p.string()); }

}  // namespace

std::string configuration_hash(const OJson& resolved_full) { return scenario_hash(Json(resolved_full)); }

RunDirectory::RunDirectory(std::string root) : root_(std::move(root)) {}

RunDirectory::~RunDirectory() {
  if (lock_fd_ >= 0) {
    // Unlinked while still locked: a process waiting on this inode re-checks the path (acquire).
    std::error_code ec;
    fs::remove(fs::path(root_) / "run.lock", ec);
    ::close(lock_fd_);
  }
}

std::size_t RunDirectory::acquire() {
  if (lock_fd_ >= 0) return 0;
  const fs::path root(root_);
  std::error_code ec;
  // A file, device or FIFO where the run folder should be: refused, naming what it is.
  if (fs::exists(root, ec) && !fs::is_directory(root, ec)) create_directories_or_throw(root_);
  if (fs::is_directory(root, ec) && !fs::exists(root / "run.json", ec) && !fs::exists(root / "run.lock", ec) &&
      fs::directory_iterator(root, ec) != fs::directory_iterator()) {
    throw InputError(root_ + ": folder is not empty and holds no run (no run.json); give a new or empty folder, so "
                     "nothing else is overwritten or mixed into the results");
  }
  make_dirs(root);
  const fs::path lock_path = root / "run.lock";
  for (int attempt = 0;; ++attempt) {
    const int fd = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) {
      throw InputError(root_ + ": cannot write into the run folder (creating run.lock: " + std::strerror(errno) + ")");
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      char buf[64] = {0};
      const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
      ::close(fd);
      if (err == EWOULDBLOCK) {
        std::string holder = n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string("unknown");
        while (!holder.empty() && (holder.back() == '\n' || holder.back() == ' ')) holder.pop_back();
        throw InputError(root_ + ": in use by another floorcast process (pid " + holder +
                         " holds run.lock); wait for it to finish or stop it, or use another output folder");
      }
      throw InputError(root_ + ": cannot lock run.lock: " + std::strerror(err));
    }
    // The lock is ours if the path still names the file we locked (a previous holder unlinks it
    // on exit; we may have opened it just before).
    struct stat a {}, b {};
    if (::fstat(fd, &a) == 0 && ::stat(lock_path.c_str(), &b) == 0 && a.st_ino == b.st_ino && a.st_dev == b.st_dev) {
      lock_fd_ = fd;
      break;
    }
    ::close(fd);
    if (attempt > 100) throw InputError(root_ + ": cannot lock run.lock (it keeps being replaced)");
  }
  // Files below a run folder we hold are our own state (rewritten as the run goes), not inputs.
  note_owned_output_folder(root_);
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(lock_fd_, 0) != 0 || ::pwrite(lock_fd_, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
    throw InputError(root_ + ": cannot write into the run folder (run.lock: " + std::strerror(errno) + ")");
  }
  // Writable? A probe file in the folder and in units/ (where the results go).
  make_dirs(root / "units");
  for (const fs::path& dir : {root, root / "units"}) {
    const fs::path probe = dir / ".write_probe.tmp";
    write_text_file_atomic(probe.string(), "probe\n");
    fs::remove(probe, ec);
  }
  // Stray temporary files of a killed run (atomic writes that never reached their rename).
  std::size_t removed = 0;
  for (auto it = fs::recursive_directory_iterator(root, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const bool tmp = name.size() > 4 && (name.compare(name.size() - 4, 4, ".tmp") == 0 || name.find(".tmp.") != std::string::npos);
    if (tmp && it->is_regular_file(ec)) {
      std::error_code rm;
      if (fs::remove(it->path(), rm)) ++removed;
    }
  }
  return removed;
}

void RunDirectory::open(const Scenario& scenario, const OJson& resolved_full) {
  acquire();
  make_dirs(fs::path(root_) / "units");
  const std::string hash = configuration_hash(resolved_full);
  const fs::path info_path = fs::path(root_) / "run.json";
  if (fs::exists(info_path)) {
    const Json info = read_run_info();
    const std::string existing = info["configuration_hash"].get<std::string>();
    if (existing != hash) {
      throw InputError(root_ + ": holds a run of a different configuration (hash " + existing + ", this one " + hash +
                       "); use a new output folder or remove it");
    }
    return;  // resuming
  }
  OJson info;
  info["scenario"] = scenario.name;
  info["configuration_hash"] = hash;
  info["format"] = 1;
  write_text_file_atomic((fs::path(root_) / "resolved_config.json").string(), resolved_full.dump(2) + "\n");
  write_text_file_atomic(info_path.string(), info.dump(2) + "\n");
}

Json RunDirectory::read_run_info() const {
  const fs::path p = fs::path(root_) / "run.json";
  const Json info = read_json(p);
  // Checked here so every reader may use its fields as they are.
  if (!info.is_object()) throw InputError(p.string() + ": not a run description (expected a JSON object)");
  if (!info.contains("configuration_hash") || !info["configuration_hash"].is_string()) {
    throw InputError(p.string() + ": configuration_hash: missing or not a string");
  }
  if (info.contains("reference_s") && !info["reference_s"].is_object()) {
    throw InputError(p.string() + ": reference_s: expected an object of seconds");
  }
  return info;
}
Json RunDirectory::read_resolved_config() const { return read_json(fs::path(root_) / "resolved_config.json"); }

namespace {

/// The file a stored configuration names (as its scenario named it: relative to the scenario's
/// folder or floorcast's data folder, or absolute) with the bytes it hashed: the name as it stands
/// (absolute, or relative to the working folder), else under the data folder. "" when neither has
/// those bytes.
std::string find_recorded_file(const std::string& given, const std::string& hash) {
  if (given.empty()) return "";
  for (const fs::path& candidate : {fs::path(given), fs::path(data_dir()) / given}) {
    std::error_code ec;
    if (!fs::is_regular_file(candidate, ec)) continue;
    try {
      if (hash.empty() || hex64(fnv1a64(read_text_file(candidate.string()))) == hash) return candidate.string();
    } catch (const InputError&) {
    }
  }
  return "";
}

}  // namespace

Scenario RunDirectory::stored_scenario() const {
  Json resolved = read_resolved_config();
  resolved.erase("resolved_parameters");
  Scenario s = scenario_from_resolved(resolved, (fs::path(root_) / "resolved_config.json").string());
  // The configuration records plans by name and content, not location: find them again (for work
  // done on a finished run, e.g. the report drawing heatmaps the run did not keep). A plan not
  // found keeps its recorded name, and using it fails with that name.
  for (BuildingSpec& b : s.buildings) {
    if (const std::string f = find_recorded_file(b.file_given, b.file_hash); !f.empty()) b.file = f;
    if (const std::string f = find_recorded_file(b.rooms_given, b.rooms_hash); !f.empty()) b.rooms_file = f;
  }
  return s;
}

void RunDirectory::update_run_info(const std::string& key, const Json& value) const {
  const fs::path p = fs::path(root_) / "run.json";
  OJson info = parse_ordered_json_text(read_text_file(p.string()), p.string());
  info[key] = value;
  write_text_file_atomic(p.string(), info.dump(2) + "\n");
}

std::string RunDirectory::unit_path(const Scenario&, const WorkUnit& unit) const {
  return (fs::path(root_) / "units" / (unit.id + ".json")).string();
}

bool RunDirectory::has_unit(const Scenario& scenario, const WorkUnit& unit) const {
  const std::string path = unit_path(scenario, unit);
  if (!fs::is_regular_file(path)) return false;
  // A unit where a method misbehaved (an external method's error) is run again.
  const std::string text = read_text_file(path);
  if (text.find("\"error\"") == std::string::npos) return true;
  return !unit_has_errors(unit_from_json(nlohmann::json::parse(text), path));
}

void RunDirectory::write_unit(const Scenario& scenario, const UnitResult& result) const {
  const fs::path p = unit_path(scenario, result.unit);
  make_dirs(p.parent_path());
  write_text_file_atomic(p.string(), unit_to_json(result).dump(1) + "\n");
}

std::vector<UnitResult> RunDirectory::read_units(const Scenario& scenario) const {
  std::vector<UnitResult> out;
  for (const WorkUnit& u : enumerate_units(scenario)) {
    const std::string p = unit_path(scenario, u);
    if (!fs::is_regular_file(p)) continue;
    UnitResult r = unit_from_json(read_json(p), p);
    if (r.unit.id != u.id) throw InputError(p + ": holds unit \"" + r.unit.id + "\", expected \"" + u.id + "\"");
    // The unit's indices and matchers must be the ones its id names (a damaged or foreign file
    // is refused, not reported).
    if (r.unit.cell != u.cell || r.unit.building != u.building || r.unit.point != u.point) {
      throw InputError(p + ": cell/building/point " + std::to_string(r.unit.cell) + "/" + std::to_string(r.unit.building) +
                       "/" + std::to_string(r.unit.point) + " do not match unit \"" + u.id + "\"");
    }
    const CellSpec& cell = scenario.cells[static_cast<std::size_t>(u.cell)];
    std::set<std::string> labels;
    for (const MatcherSpec& m : cell.matchers) labels.insert(m.label);
    std::set<std::string> seen;
    for (const MatcherOutcome& o : r.outcomes) {
      if (!labels.count(o.label) || !seen.insert(o.label).second) {
        throw InputError(p + ": outcome for matcher \"" + o.label + "\" is not one of the cell's matchers (or repeats)");
      }
    }
    if (seen.size() != labels.size()) {
      throw InputError(p + ": " + std::to_string(seen.size()) + " matcher outcomes, the cell has " +
                       std::to_string(labels.size()) + " matchers");
    }
    out.push_back(std::move(r));
  }
  return out;
}

void RunDirectory::write_image(const std::string& relative_path, const cv::Mat& image) const {
  const fs::path p = fs::path(root_) / relative_path;
  make_dirs(p.parent_path());
  write_png(p.string(), image);  // atomic
}

void RunDirectory::write_file(const std::string& relative_path, const std::string& bytes) const {
  const fs::path p = fs::path(root_) / relative_path;
  make_dirs(p.parent_path());
  write_text_file_atomic(p.string(), bytes);
}

void RunDirectory::write_report(const Report& report) const {
  const fs::path root(root_);
  for (const auto& [name, image] : report.plots) write_image("plots/" + name, image);
  write_text_file_atomic((root / "observations.csv").string(), report.observations_csv);
  write_text_file_atomic((root / "summary.md").string(), report.summary_md);
  write_text_file_atomic((root / "summary.json").string(), report.summary.dump(2) + "\n");
}

void refuse_output_inside_inputs(const std::string& output, const std::vector<std::string>& input_dirs,
                                 const std::string& what) {
  std::error_code ec;
  const fs::path out = fs::weakly_canonical(fs::absolute(output, ec), ec);
  for (const std::string& in : input_dirs) {
    if (!fs::is_directory(in, ec)) continue;
    const fs::path dir = fs::weakly_canonical(fs::absolute(in, ec), ec);
    auto o = out.begin();
    auto d = dir.begin();
    for (; d != dir.end() && o != out.end() && *d == *o; ++d, ++o) {
    }
    if (d == dir.end() || (d != dir.end() && d->empty() && std::next(d) == dir.end())) {
      throw InputError(what + " " + output + ": lies inside the input folder " + in +
                       "; write the output elsewhere so the input stays as it was");
    }
  }
}

}  // namespace floorcast
