#!/usr/bin/env bash
# Re-renders every golden in tests/capture/views.json into assets/goldens/. Review the images
# (git diff shows which changed) and give the reason in the commit message.
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${SPECULUM_BUILD_DIR:-build}
capture="$BUILD/tools/capture/speculum-capture"
tmp=$(mktemp -d)
python3 - "$capture" "$tmp" <<'PY'
import json, subprocess, sys, shutil, os
capture, tmp = sys.argv[1], sys.argv[2]
views = json.load(open("tests/capture/views.json"))["views"]
os.makedirs("assets/goldens", exist_ok=True)
for i, v in enumerate(views, 1):
    out = os.path.join(tmp, f"{v['scene']}.{v['camera']}")
    subprocess.run([capture, "--scene", v.get("file", f"assets/scenes/{v['scene']}.gltf"), "--camera", v["camera"],
                    "--size", "320x180", "--warmup", "0", "--frames", "1", "--aov", "color",
                    "--out", out], check=True, stdout=subprocess.DEVNULL)
    shutil.copy(os.path.join(out, "color.0000.png"), f"assets/goldens/{v['scene']}.{v['camera']}.png")
    print(f"goldens: {i}/{len(views)} {v['scene']}.{v['camera']}", file=sys.stderr)
PY
rm -rf "$tmp"
