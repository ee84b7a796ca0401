#include "floorcast/core/module.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <vector>

#include "floorcast/core/types.hpp"

#ifndef FLOORCAST_MODULE_SUBDIR
#define FLOORCAST_MODULE_SUBDIR "lib/floorcast"
#endif

namespace floorcast {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> candidates(const std::string& name) {
  const std::string file = name + ".so";
  std::vector<fs::path> out;
  if (const char* env = std::getenv("FLOORCAST_MODULE_DIR"); env && *env) out.push_back(fs::path(env) / file);
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&candidates), &info) != 0 && info.dli_fname && *info.dli_fname) {
    std::error_code ec;
    fs::path self = fs::canonical(fs::path(info.dli_fname), ec);
    if (ec) self = fs::path(info.dli_fname);
    fs::path dir = self.parent_path();
    out.push_back(dir / file);
    out.push_back(dir / "floorcast" / file);
    for (int up = 0; up < 4 && !dir.empty(); ++up) {
      out.push_back(dir / FLOORCAST_MODULE_SUBDIR / file);
      out.push_back(dir / "lib" / "floorcast" / file);
      if (dir == dir.root_path()) break;
      dir = dir.parent_path();
    }
  }
  return out;
}

struct Registry {
  std::mutex mutex;
  std::map<std::string, std::pair<void*, std::string>> open;  // name -> handle, path
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

std::string module_path(const std::string& name) {
  {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    if (auto it = r.open.find(name); it != r.open.end()) return it->second.second;
  }
  for (const fs::path& p : candidates(name)) {
    std::error_code ec;
    if (fs::is_regular_file(p, ec)) return p.string();
  }
  return "";
}

void* load_module(const std::string& name) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  if (auto it = r.open.find(name); it != r.open.end()) return it->second.first;
  std::string tried;
  std::string last_error;
  for (const fs::path& p : candidates(name)) {
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) {
      tried += "\n  " + p.string() + " (absent)";
      continue;
    }
    void* h = dlopen(p.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (h) {
      r.open[name] = {h, p.string()};
      return h;
    }
    const char* e = dlerror();
    last_error = e ? e : "unknown error";
    tried += "\n  " + p.string() + " (" + last_error + ")";
  }
  const std::string file = name + ".so";
  if (void* h = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL)) {
    r.open[name] = {h, file};
    return h;
  }
  const char* e = dlerror();
  tried += "\n  " + file + " on the loader's search path (" + std::string(e ? e : "not found") + ")";
  throw InputError("cannot load the floorcast module \"" + name + "\" (set FLOORCAST_MODULE_DIR to the folder holding " +
                   file + "); tried:" + tried);
}

void* module_symbol(void* handle, const std::string& name, const char* symbol) {
  dlerror();
  void* s = dlsym(handle, symbol);
  if (!s) {
    const char* e = dlerror();
    throw InputError("floorcast module \"" + name + "\" has no symbol " + symbol + (e ? std::string(": ") + e : ""));
  }
  return s;
}

}  // namespace floorcast
