#!/usr/bin/env bash
# golden_test.sh CAPTURE SCENE CAMERA GOLDEN OUTDIR
# Renders SCENE from CAMERA at 320x180 on lavapipe and compares the tonemapped colour with the
# committed golden using OpenImageIO's idiff. Tolerances (why):
#   -fail 0.02      per-channel difference a pixel may have (about 5/255): lavapipe is
#                   deterministic for one Mesa/LLVM build, but LLVM's code for a different CPU
#                   (AVX2 vs AVX-512, FMA contraction) rounds shading maths differently.
#   -failpercent 0.5  share of pixels allowed past that: silhouette and shadow-map edges where a
#                   last-bit change flips which triangle or texel wins.
#   -hardfail 0.25  no pixel may differ by more: anything this large is a real change.
# Regenerate all goldens (and say why in the commit): bash tests/capture/regenerate_goldens.sh
set -u
capture=$1; scene=$2; camera=$3; golden=$4; out=$5
rm -rf "$out"; mkdir -p "$out"
"$capture" --scene "$scene" --camera "$camera" --size 320x180 --warmup 0 --frames 1 --aov color,linear \
  --out "$out" >"$out/log.txt" 2>&1 || { cat "$out/log.txt"; echo "capture failed"; exit 1; }
if [[ ! -f "$golden" ]]; then
  echo "missing golden $golden: run bash tests/capture/regenerate_goldens.sh and review the images"; exit 1
fi
idiff -fail 0.02 -failpercent 0.5 -hardfail 0.25 -o "$out/diff.exr" -abs -scale 10 "$golden" "$out/color.0000.png"
rc=$?
if [[ $rc -ge 2 ]]; then echo "golden mismatch (idiff exit $rc); new image: $out/color.0000.png"; exit 1; fi
exit 0
