#!/usr/bin/env bash
# Installs floorcast's build dependencies from Debian 12 packages (only the missing ones).
# Runs apt-get as root, or through sudo when not root.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  libembree-dev libeigen3-dev libopencv-dev libopencv-contrib-dev libosmesa6-dev libtinygltf-dev libpcl-dev
  libgtest-dev libbenchmark-dev
  nlohmann-json3-dev libyaml-cpp-dev libcli11-dev libtbb-dev libfftw3-dev liblbfgspp-dev
  libnanoflann-dev libpugixml-dev libproj-dev libpng-dev libboost-dev
  libtiff-dev libopenexr-dev
  python3-dev python3-numpy python3-pybind11 pybind11-dev python3-pytest
  python3-matplotlib poppler-utils python3-distributed
  slurm-wlm munge
  chromium
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
  SUDO=()
elif command -v sudo >/dev/null 2>&1; then
  SUDO=(sudo)
else
  echo "install_deps: missing packages (${missing[*]}) and neither root nor sudo is available" >&2
  exit 1
fi

echo "install_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${SUDO[@]}" apt-get update -qq
"${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
