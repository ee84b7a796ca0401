#!/usr/bin/env bash
# Installs this build into a temporary prefix, builds tests/install/consumer against it with
# find_package(floorcast COMPONENTS observe match) (the consumer's CMakeLists refuses any package
# those components do not need), runs it, and checks that the program carries no simulator
# back-end (Embree, OSMesa, tinygltf) and no path of the source tree.
set -euo pipefail
build_dir=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build_dir" --prefix "$work/prefix" >/dev/null
if ! cmake -S "$source_dir/tests/install/consumer" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release >"$work/configure.log" 2>&1; then
  cat "$work/configure.log" >&2
  echo "FAILED: the consumer of floorcast::observe and floorcast::match does not configure" >&2
  exit 1
fi
grep "consumer:" "$work/configure.log"
cmake --build "$work/build" -j2 >/dev/null
"$work/build/consumer"
if ldd "$work/build/consumer" | grep -Ei 'embree|osmesa|tinygltf|libLLVM'; then
  echo "FAILED: the consumer links a simulator back-end" >&2
  exit 1
fi
if nm -C "$work/build/consumer" | grep -E ' (T|t) (rtc[A-Z]|OSMesa|tinygltf::)' | head -3 | grep .; then
  echo "FAILED: simulator symbols in the consumer" >&2
  exit 1
fi
# The installed CLI finds its data next to itself and carries no source path.
if grep -q "$source_dir" "$work/prefix/bin/floorcast"; then
  echo "FAILED: the installed floorcast binary contains the source path $source_dir" >&2
  exit 1
fi
(cd "$work" && "$work/prefix/bin/floorcast" plan info "$work/prefix/share/floorcast/floorplans/buildings/two_rooms.json" >/dev/null)
# The installed CLI renders colour views through the OpenGL module installed beside it
# (<prefix>/<libdir>/floorcast/floorcast_gl.so), with no module path from the build tree.
(cd "$work" && env -u FLOORCAST_MODULE_DIR "$work/prefix/bin/floorcast" sim scan \
  "$work/prefix/share/floorcast/floorplans/buildings/two_rooms.json" --pose 2,2,30 --setting single --rgb \
  -o "$work/rgb" >/dev/null)
if [ ! -s "$work/rgb/view_000_rgb.png" ]; then
  echo "FAILED: the installed floorcast wrote no colour view (floorcast_gl.so not found beside it?)" >&2
  exit 1
fi
# A matcher in its own module (examples/own_matchers/module), built against the installed headers
# and found by name by the installed CLI (FLOORCAST_MODULE_DIR), localizes a perfect observation.
cmake -S "$source_dir/examples/own_matchers/module" -B "$work/module" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/module" -j2 >/dev/null
plan="$work/prefix/share/floorcast/floorplans/buildings/two_rooms.json"
(cd "$work" && "$work/prefix/bin/floorcast" sim perfect "$plan" --pose 2.3,1.7,35 --doors-open -o "$work/obs" >/dev/null)
loc=$(cd "$work" && FLOORCAST_MODULE_DIR="$work/module" "$work/prefix/bin/floorcast" localize "$plan" "$work/obs" \
  --matcher chamfer_cpp -o "$work/loc")
echo "$loc"
if ! echo "$loc" | grep -Eq "chamfer_cpp: x 2\.[0-9]+ m, y 1\.[0-9]+ m"; then
  echo "FAILED: the installed CLI did not localize with the module matcher chamfer_cpp" >&2
  exit 1
fi
echo "installed package ok"
