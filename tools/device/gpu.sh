#!/bin/bash
# gpu.sh: issue 23's device run, from the repository root on the lent machine (tools/device/README.md):
#   run(command="bash .devkit/gpu.sh", carry=[".devkit", ".gl"])
# The speed bench at 1920x1080 and 960x540 (every configuration, three views) and the per-pass
# frame bench; with GAME=1 also the game's fps script under the carried Xvfb, last, because the
# one machine that ran the game that way stopped answering (2026-12-05).
set -u
L=$OUT/log.txt
say() { echo "== $* ($(date +%T))" | tee -a $L; }
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
tar -xJf .devkit/kit.tar.xz -C /tmp && source /tmp/kit/env.sh
[ -e /usr/bin/xkbcomp ] || cp /tmp/kit/bin/xkbcomp /usr/bin/xkbcomp
# The carried binaries stand in a build folder of their own, so a checkout's build/ is never touched.
export SPECULUM_BUILD_DIR=build-device
mkdir -p build-device/tools/capture build-device/sample_game
ln -sf /tmp/kit/bin/speculum-capture build-device/tools/capture/; ln -sf /tmp/kit/bin/speculum-game build-device/sample_game/
nvidia-smi --query-gpu=timestamp,clocks.sm,clocks.mem,utilization.gpu --format=csv,noheader -lms 500 > $OUT/clocks.csv &
export PYTHONUNBUFFERED=1
say smoke; nvidia-smi --query-gpu=name,driver_version,clocks.max.sm --format=csv | tee -a $L
timeout 60 build-device/tools/capture/speculum-capture --scene assets/scenes/gallery.gltf --camera main --size 1920x1080 --frames 3 --out /tmp/smoke 2>&1 | tail -2 | tee -a $L
grep -q NVIDIA /tmp/smoke/timings.json 2>/dev/null || { say "no NVIDIA device"; exit 1; }
say frame bench
for s in "" "--set reflections.resolution=half"; do bash tests/bench/frame_bench.sh 1920x1080 60 $s >> $OUT/frames.md 2>>$L; done
V=gallery.main,closed_room.main,cornell_mirrors.main
say bench 1920x1080
timeout 200 python3 tests/bench/speed_bench.py --build build-device --views $V --size 1920x1080 --rounds 2 --frames 30 > $OUT/bench1080.md 2>>$L; echo "rc $?" | tee -a $L
say bench 960x540
timeout 150 python3 tests/bench/speed_bench.py --build build-device --views $V --size 960x540 --rounds 2 --frames 30 > $OUT/bench540.md 2>>$L; echo "rc $?" | tee -a $L
if [ "${GAME:-0}" = 1 ]; then
  say game; timeout 80 bash sample_game/measure_fps.sh 200 > $OUT/game.txt 2>&1; echo "rc $?" | tee -a $L; tail -4 /tmp/xvfb.log >> $L
fi
say end; kill %1; grep -h "^- \|^###" $OUT/bench1080.md
