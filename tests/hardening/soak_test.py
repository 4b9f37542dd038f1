#!/usr/bin/env python3
"""soak_test.py LIMIT_MB CMD...: runs the game's frame loop (CMD prints "frame N: rss X MB" every
100 frames, as speculum-game --frames does) and fails when it exits non-zero (the game exits 1
on any Vulkan validation message when SPECULUM_VALIDATION=1), prints no memory lines, or its
resident set grows by LIMIT_MB or more between the first quarter of the run and the end (the
first quarter absorbs pipeline compilation and the driver's caches)."""
import re, subprocess, sys


def main():
    limit, cmd = float(sys.argv[1]), sys.argv[2:]
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    out = p.stdout.decode(errors="replace")
    samples = [(int(f), float(m)) for f, m in re.findall(r"^frame (\d+): rss ([\d.]+) MB", out, re.M)]
    if p.returncode != 0:
        print("exit %d from %s\n%s" % (p.returncode, " ".join(cmd), out[-4000:]))
        return 1
    if len(samples) < 4:
        print("too few memory lines (%d) in the output:\n%s" % (len(samples), out[-4000:]))
        return 1
    last = samples[-1][0]
    base = next(s for s in samples if s[0] >= last // 4)
    growth = samples[-1][1] - base[1]
    for f, m in samples[:: max(1, len(samples) // 10)] + [samples[-1]]:
        print("frame %6d: rss %.1f MB" % (f, m))
    print("growth from frame %d to %d: %.2f MB (limit %.1f MB)" % (base[0], last, growth, limit))
    return 0 if growth < limit else 1


if __name__ == "__main__":
    sys.exit(main())
