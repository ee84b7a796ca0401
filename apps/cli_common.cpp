#include "cli_common.hpp"

#include <algorithm>
#include <filesystem>
#include <system_error>
#include <utility>
#include <vector>

#include "floorcast/floorplans/io.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast::cli {
namespace {

std::vector<std::pair<std::string, Registrar>>& registrars() {
  static std::vector<std::pair<std::string, Registrar>> list;
  return list;
}

}  // namespace

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

std::string source_dir() { return FLOORCAST_SOURCE_DIR; }

void ensure_directory(const std::string& path) {
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec || !std::filesystem::is_directory(path)) {
    throw InputError(path + ": cannot create directory: " + (ec ? ec.message() : "not a directory"));
  }
}

void write_json(const std::string& path, const nlohmann::ordered_json& json) {
  write_text_file_atomic(path, json.dump(2) + "\n");
}

}  // namespace floorcast::cli
