#!/usr/bin/env bash
# The committed scenes are exactly what tools/make_scenes.py writes: regenerate into a scratch
# tree and compare bytes, so nobody edits a generated file by hand and loses it on the next run.
set -euo pipefail
root=$1
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
mkdir -p "$work/tools" "$work/assets/scenes" "$work/assets/paths" "$work/assets/blender"
# The generator is tools/make_scenes.py and the packages it imports (tools/scenes, tools/speculum_py).
cp "$root/tools/make_scenes.py" "$work/tools/"
cp -r "$root/tools/scenes" "$root/tools/speculum_py" "$work/tools/"
# The CMO placement reports the generator reads (speculum-probes place wrote them).
cp -r "$root/assets/placement" "$work/assets/"
python3 "$work/tools/make_scenes.py" >/dev/null
status=0
for f in $(cd "$work" && find assets -type f -not -path 'assets/placement/*' | sort); do
  if ! cmp -s "$work/$f" "$root/$f"; then echo "differs from the generator's output: $f"; status=1; fi
done
[[ $status -eq 0 ]] && echo "ok: $(cd "$work" && find assets -type f | wc -l) generated files match"
exit $status
