#!/usr/bin/env bash
# bench_smoke_test.sh BENCH SUITE OUT: runs the bench twice on a tiny suite; the first run
# renders the reference, the second must take it from the cache; every output must exist.
set -euo pipefail
bench=$1; suite=$2; out=$3
rm -rf "$out"
"$bench" --suite "$suite" --out "$out/a" --cache "$out/cache"
"$bench" --suite "$suite" --out "$out/b" --cache "$out/cache"
for f in results.csv results.json chart.png chart.svg summary.md; do
  [[ -s "$out/b/$f" ]] || { echo "missing $out/b/$f"; exit 1; }
done
ls "$out"/b/heatmaps/*.png >/dev/null
/usr/bin/python3 - "$out" <<'PY'
import json, sys
a = json.load(open(sys.argv[1] + "/a/results.json"))
b = json.load(open(sys.argv[1] + "/b/results.json"))
assert a["rows"] and all(not r["reference_cached"] for r in a["rows"]), "first run must render the reference"
assert all(r["reference_cached"] for r in b["rows"]), "second run must reuse the cached reference"
assert b["stability"] and all(0.0 <= s["excess_flicker"] < 1.0 and s["frames"] > 1 for s in b["stability"]), b["stability"]
for r in b["rows"]:
    assert r["pixels"] > 0, f"no reflective pixels in {r}"
    assert r["psnr_db"] is not None and 5.0 < r["psnr_db"] <= 100.0, f"implausible PSNR in {r}"
print("ok:", [(r["method"], round(r["psnr_db"], 2), round(r["reflection_ms"], 2)) for r in b["rows"]])
PY
