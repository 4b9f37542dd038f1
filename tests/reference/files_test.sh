#!/usr/bin/env bash
# files_test.sh REFERENCE SCENE OUT: a small render writes NAME.0000.exr for every AOV, color also
# as PNG (speculum-capture's names, engine/platform/output.cpp), and reference.json.
set -euo pipefail
ref=$1; scene=$2; out=$3
rm -rf "$out"
"$ref" --scene "$scene" --camera main --size 48x27 --spp 2 --aov linear,color,reflection,depth,normal,reflective --out "$out"
for f in linear.0000.exr color.0000.exr color.0000.png reflection.0000.exr depth.0000.exr normal.0000.exr \
         reflective.0000.exr reference.json; do
  [[ -s "$out/$f" ]] || { echo "missing $out/$f"; exit 1; }
done
grep -q '"rays_per_second"' "$out/reference.json" || { echo "reference.json lacks rays_per_second"; exit 1; }
echo "ok"
