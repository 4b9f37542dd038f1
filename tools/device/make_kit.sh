#!/usr/bin/env bash
# make_kit.sh: packs what a run on a lent GPU machine needs into .devkit/ (ignored by git):
# kit.tar.xz (speculum-capture, speculum-game, the SPIR-V, the shared libraries they load, Xvfb,
# xkbcomp, oiiotool and the XKB data) and, in .gl/, Debian's Vulkan loader and glvnd packages.
# The device machine is Ubuntu with the NVIDIA driver and none of our Debian libraries, and a
# call carries at most 64 MiB with the tree (31 MiB): OpenImageIO's plugins alone pull 263
# libraries (360 MB), so the image formats we never open (video, DICOM, OpenVDB, RAW, HEIF,
# WebP, JPEG 2000, TIFF, GIF, OpenCV) are replaced by stubs (stub.py). See README.md here.
set -euo pipefail
cd "$(dirname "$0")/../.."
B=${SPECULUM_BUILD_DIR:-build}
K=$(mktemp -d)/kit
mkdir -p "$K/bin" "$K/xkb" .devkit .gl
bins=("$B/tools/capture/speculum-capture" "$B/sample_game/speculum-game" /usr/bin/Xvfb /usr/bin/xkbcomp /usr/bin/oiiotool)
python3 tools/device/bundle.py "$K" "${bins[@]}"
cp "${bins[@]}" "$K/bin/"
# GLFW and Xlib open these with dlopen, so no NEEDED entry names them.
for l in libX11-xcb.so.1 libXrandr.so.2 libXinerama.so.1 libXcursor.so.1 libXi.so.6 libXext.so.6 \
         libXrender.so.1 libXfixes.so.3 libXxf86vm.so.1 libxshmfence.so.1; do
  cp -L "/usr/lib/x86_64-linux-gnu/$l" "$K/lib/"; done
# The system path's loader and glvnd serve the NVIDIA ICD (gpu.sh unpacks .gl/): from
# LD_LIBRARY_PATH the ICD answered no vkCreateInstance (2026-12-05).
rm -f "$K"/lib/libvulkan.so.1 "$K"/lib/libGL*
cp -r /usr/share/X11/xkb/. "$K/xkb/"
cp -r "$B/shaders" "$K/shaders"
cp tools/device/xvfb-run "$K/bin/"
cat > "$K/env.sh" <<'ENV'
K=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
export LD_LIBRARY_PATH=$K/lib SPECULUM_SHADER_DIR=$K/shaders PATH=$K/bin:$PATH
ENV
tar -cJf .devkit/kit.tar.xz -C "$(dirname "$K")" kit
o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
mkdir -p /tmp/amd64/partial
if ! ls .gl/libvulkan1_*.deb >/dev/null 2>&1; then
  apt-get $o update -qq
  (cd .gl && apt-get $o download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
fi
cp tools/device/gpu.sh .devkit/
echo "make_kit: .devkit/kit.tar.xz $(du -h .devkit/kit.tar.xz | cut -f1); run: bash .devkit/gpu.sh with carry .devkit and .gl"
