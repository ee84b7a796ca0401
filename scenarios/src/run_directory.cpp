#include "floorcast/core/image_io.hpp"
#include "floorcast/scenarios/run_directory.hpp"

#include <cstdio>
#include <filesystem>

#include "floorcast/core/hash.hpp"
#include "floorcast/floorplans/io.hpp"

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

Json read_json(const fs::path& p) {
  const std::string text = read_text_file(p.string());
  try {
    return Json::parse(text);
  } catch (const Json::exception& e) {
    throw InputError(p.string() + ": malformed JSON: " + e.what());
  }
}

}  // namespace

std::string configuration_hash(const OJson& resolved_full) {
  return hex64(fnv1a64(Json(resolved_full).dump()));
}

RunDirectory::RunDirectory(std::string root) : root_(std::move(root)) {}

void RunDirectory::open(const Scenario& scenario, const OJson& resolved_full) {
  make_dirs(fs::path(root_) / "units");
  const std::string hash = configuration_hash(resolved_full);
  const fs::path info_path = fs::path(root_) / "run.json";
  if (fs::exists(info_path)) {
    const Json info = read_json(info_path);
    const std::string existing = info.value("configuration_hash", std::string());
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

Json RunDirectory::read_run_info() const { return read_json(fs::path(root_) / "run.json"); }
Json RunDirectory::read_resolved_config() const { return read_json(fs::path(root_) / "resolved_config.json"); }

Scenario RunDirectory::stored_scenario() const {
  Json resolved = read_resolved_config();
  resolved.erase("resolved_parameters");
  return scenario_from_resolved(resolved, (fs::path(root_) / "resolved_config.json").string());
}

void RunDirectory::update_run_info(const std::string& key, const Json& value) const {
  const fs::path p = fs::path(root_) / "run.json";
  OJson info = OJson::parse(read_text_file(p.string()));
  info[key] = value;
  write_text_file_atomic(p.string(), info.dump(2) + "\n");
}

std::string RunDirectory::unit_path(const Scenario&, const WorkUnit& unit) const {
  return (fs::path(root_) / "units" / (unit.id + ".json")).string();
}

bool RunDirectory::has_unit(const Scenario& scenario, const WorkUnit& unit) const {
  return fs::is_regular_file(unit_path(scenario, unit));
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
    out.push_back(std::move(r));
  }
  return out;
}

void RunDirectory::write_image(const std::string& relative_path, const cv::Mat& image) const {
  const fs::path p = fs::path(root_) / relative_path;
  make_dirs(p.parent_path());
  write_png(p.string(), image);  // atomic
}

void RunDirectory::write_report(const Report& report) const {
  const fs::path root(root_);
  for (const auto& [name, image] : report.plots) write_image("plots/" + name, image);
  write_text_file_atomic((root / "observations.csv").string(), report.observations_csv);
  write_text_file_atomic((root / "summary.md").string(), report.summary_md);
  write_text_file_atomic((root / "summary.json").string(), report.summary.dump(2) + "\n");
}

}  // namespace floorcast
