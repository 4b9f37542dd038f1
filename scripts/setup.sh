#!/usr/bin/env bash
# Installs every Debian 12 package Speculum needs and configures + builds it.
# Run as root (CI and the dev machines are root); as a normal user run it with sudo:
#   sudo bash scripts/setup.sh
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  glslang-tools spirv-tools libspirv-cross-c-shared-dev
  libglm-dev libglfw3-dev libtinygltf-dev libstb-dev nlohmann-json3-dev
  libimgui-dev libopenimageio-dev openimageio-tools libcli11-dev
  libgtest-dev libgmock-dev
  xvfb xauth python3 x11-apps
  libembree-dev python3-matplotlib
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  if [[ $(id -u) -ne 0 ]]; then
    if command -v sudo >/dev/null; then SUDO=sudo; else
      echo "setup: these packages are missing and you are not root: ${missing[*]}" >&2
      echo "setup: run 'sudo bash scripts/setup.sh' or install them as root first." >&2
      exit 1
    fi
  else SUDO=; fi
  echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

BUILD=${SPECULUM_BUILD_DIR:-build}
cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=${SPECULUM_BUILD_TYPE:-Release} >/dev/null
cmake --build "$BUILD" -j "$(nproc)"
