#!/usr/bin/env bash
# screenshot.sh OUT.png [SECONDS]: the game's window (HUD included) under Xvfb at 1280x720, taken
# with xwd (Debian x11-apps) after SECONDS of standing at the start; the XWD dump is turned into a
# PPM here and into PNG by oiiotool. The picture in sample_game/README.md.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=$1; wait_s=${2:-25}
display=:$((90 + RANDOM % 100))
Xvfb "$display" -screen 0 1280x720x24 >/dev/null 2>&1 & xvfb=$!
trap 'kill $xvfb 2>/dev/null || true' EXIT
sleep 1
DISPLAY=$display MESA_SHADER_CACHE_DIR=$root/build/mesa-cache "$root/build/sample_game/speculum-game" \
  "${@:3}" >/dev/null 2>&1 & game=$!
sleep "$wait_s"
xwd -root -silent -display "$display" > "$out.xwd"
kill "$game"
python3 - "$out.xwd" "$out.ppm" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read()
h = struct.unpack(">25I", data[:100])
header_size, width, height, bpp, bytes_per_line, ncolors = h[0], h[4], h[5], h[11], h[12], h[19]
byte_order = h[7]
assert bpp == 32, "expected a 32-bit XWD"
pixels = data[header_size + 12 * ncolors:]
rows = []
for y in range(height):
    row = pixels[y * bytes_per_line:y * bytes_per_line + 4 * width]
    out = bytearray(3 * width)
    for x in range(width):
        b, g, r = (row[4 * x], row[4 * x + 1], row[4 * x + 2]) if byte_order == 0 else (row[4 * x + 3], row[4 * x + 2], row[4 * x + 1])
        out[3 * x:3 * x + 3] = bytes((r, g, b))
    rows.append(bytes(out))
open(sys.argv[2], "wb").write(b"P6 %d %d 255\n" % (width, height) + b"".join(rows))
PY
oiiotool "$out.ppm" -o "$out"
rm -f "$out.xwd" "$out.ppm"
echo "wrote $out"
