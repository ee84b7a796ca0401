// Optional back-ends loaded on first use (dlopen): code whose dependencies are heavy (OpenGL via
// OSMesa pulls LLVM; TIFF/EXR readers) lives in a shared module beside the libraries, so a process
// that never renders or reads those files never maps them. `floorcast --help` stays light.
//
// A module NAME is the file NAME.so, searched in this order:
//   1. the folder in $FLOORCAST_MODULE_DIR, when set;
//   2. beside the executable or shared object holding this code (found with dladdr), in its
//      `floorcast/` sub-folder, and in `lib/floorcast/` and `<libdir>/floorcast/` of it and of
//      up to three of its ancestors (build tree: build/bin/floorcast -> build/lib/floorcast;
//      installed: PREFIX/bin/floorcast -> PREFIX/<libdir>/floorcast);
//   3. the dynamic loader's own search path (LD_LIBRARY_PATH, ...).
// No path of the build machine is compiled in.
#pragma once

#include <string>

namespace floorcast {

/// Opens module `name` once per process (later calls return the same handle). Throws InputError
/// listing every place tried and the loader's last error when it cannot be opened.
void* load_module(const std::string& name);

/// Address of `symbol` in a module opened by load_module; throws InputError naming both.
void* module_symbol(void* handle, const std::string& name, const char* symbol);

/// Where load_module found (or would look for) `name`: the path opened, or "" when not found.
std::string module_path(const std::string& name);

}  // namespace floorcast
