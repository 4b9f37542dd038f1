#!/usr/bin/env python3
"""Resolution-dependent stripes (issue 3): the gallery at 320x180, 317x181, 641x359, 400x300 and
333x187 shows no row or column structure in the reflection error against the reference
renderer on the mirror (roughness 0) pixels screen space covers (after warm-up frames, so that reflections of
reflections have arrived through the history): the worst row's and column's mean error on reflective pixels is at most twice the
median row's and column's. Rows and columns with fewer than MIN_PIXELS reflective pixels are
left out (their mean is noise).

REFERENCE is speculum-reference, or `exhaustive`: the engine's own linear march at one-pixel
steps over the whole screen, which has no hierarchy and no cell crossing, so the comparison
isolates what the Hi-Z traversal adds. The ctest uses `exhaustive`: against speculum-reference
the mirror error on this scene is dominated by content the engine cannot have yet (reflections
of reflections differ after 3 frames, off-screen geometry), which has row structure of its own.

With the environment variable STRIPES_SET="key=value ..." both captures get those settings
(e.g. reflections.multi_bounce=false, so that both sample the same colour and only the tracer
differs).

usage: stripes_test.py CAPTURE REFERENCE SCENE OUTDIR [--trace hiz|linear]"""
import os, struct, subprocess, sys, tempfile

SIZES = [(320, 180), (317, 181), (641, 359), (400, 300), (333, 187)]
MIN_PIXELS = 16
RATIO = 2.0
# The exhaustive march (also modules/reflections/bench.py's accuracy reference): the linear
# tracer at one-pixel steps across the whole screen with deep refinement.
EXHAUSTIVE = ["reflections.trace=linear", "reflections.linear_stride=1", "reflections.linear_max_steps=4096",
              "reflections.refine_steps=12"]


def read_exr(path):
    """Uncompressed scanline float EXR (written by oiiotool below): {channel: rows}."""
    b = open(path, "rb").read()
    pos, attrs = 8, {}
    while b[pos] != 0:
        e = b.index(b"\0", pos); name = b[pos:e].decode(); pos = e + 1
        e = b.index(b"\0", pos); pos = e + 1
        size = struct.unpack_from("<i", b, pos)[0]; pos += 4
        attrs[name] = b[pos:pos + size]; pos += size
    pos += 1
    chl, chans, p = attrs["channels"], [], 0
    while chl[p] != 0:
        e = chl.index(b"\0", p); chans.append(chl[p:e].decode()); p = e + 1 + 16
    x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"])
    w, h = x1 - x0 + 1, y1 - y0 + 1
    pos += 8 * h
    data = {c: [] for c in chans}
    for _ in range(h):
        _, size = struct.unpack_from("<2i", b, pos); pos += 8
        vals = struct.unpack_from("<%df" % (w * len(chans)), b, pos); pos += size
        for i, c in enumerate(chans):
            data[c].append(vals[i * w:(i + 1) * w])
    return w, h, data


def load(path, tmp):
    raw = os.path.join(tmp, os.path.basename(path) + ".raw.exr")
    subprocess.run(["oiiotool", path, "-d", "float", "--compression", "none", "-o", raw], check=True)
    return read_exr(raw)


def median(v):
    s = sorted(v)
    return s[len(s) // 2] if len(s) % 2 else 0.5 * (s[len(s) // 2 - 1] + s[len(s) // 2])


def structure(errors, mask, w, h):
    """(worst / median) of the row means and of the column means."""
    out = []
    for lines in ([[(x, y) for x in range(w)] for y in range(h)], [[(x, y) for y in range(h)] for x in range(w)]):
        means = []
        for line in lines:
            vals = [errors[y][x] for x, y in line if mask[y][x]]
            if len(vals) >= MIN_PIXELS:
                means.append(sum(vals) / len(vals))
        m = median(means)
        out.append((max(means) / m if m > 0 else 0.0, max(means), m, len(means)))
    return out


def main():
    capture, reference, scene, outdir = sys.argv[1:5]
    trace = sys.argv[6] if len(sys.argv) > 6 and sys.argv[5] == "--trace" else "hiz"
    extra = [a for kv in os.environ.get("STRIPES_SET", "").split() for a in ("--set", kv)]
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        for w, h in SIZES:
            tag = f"{w}x{h}"
            eng, ref = os.path.join(outdir, "engine." + tag), os.path.join(outdir, "reference." + tag)
            subprocess.run([capture, "--scene", scene, "--camera", "main", "--size", tag, "--warmup", "3",
                            "--set", f"reflections.trace={trace}", *extra, "--aov", "reflection,method,roughness", "--out", eng],
                           check=True, stdout=subprocess.DEVNULL)
            if reference == "exhaustive":
                exhaustive = [a for kv in EXHAUSTIVE for a in ("--set", kv)]
                subprocess.run([capture, "--scene", scene, "--camera", "main", "--size", tag, "--warmup", "3",
                                *exhaustive, *extra, "--aov", "reflection", "--out", ref], check=True,
                               stdout=subprocess.DEVNULL)
            elif not os.path.exists(os.path.join(ref, "reflection.0000.exr")):
                subprocess.run([reference, "--scene", scene, "--camera", "main", "--size", tag, "--spp", "16",
                                "--aov", "reflection", "--out", ref], check=True, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
            _, _, e = load(os.path.join(eng, "reflection.0000.exr"), tmp)
            _, _, m = load(os.path.join(eng, "method.0000.exr"), tmp)
            _, _, r = load(os.path.join(ref, "reflection.0000.exr"), tmp)
            _, _, g = load(os.path.join(eng, "roughness.0000.exr"), tmp)
            rough = g[list(g.keys())[0]]
            clamp = lambda v: min(max(v, 0.0), 1.0)
            errors = [[sum(abs(clamp(e[c][y][x]) - clamp(r[c][y][x])) for c in "RGB") / 3 for x in range(w)]
                      for y in range(h)]
            # Pixels screen space covers: stripes come from the tracer; what falls back to the
            # environment (off-screen content) is a different, resolution-independent error.
            # Mirrors only (roughness 0): there the reference is exact, not a noisy glossy estimate.
            mask = [[m["R"][y][x] > 0.5 and rough[y][x] < 0.02 for x in range(w)] for y in range(h)]
            (rows, rmax, rmed, rn), (cols, cmax, cmed, cn) = structure(errors, mask, w, h)
            print(f"{tag}: rows worst/median {rows:.2f} ({rmax:.4f}/{rmed:.4f}, {rn} rows), "
                  f"columns {cols:.2f} ({cmax:.4f}/{cmed:.4f}, {cn} columns)")
            if rows > RATIO or cols > RATIO:
                failures.append(tag)
    if failures:
        print("row or column structure in the reflection error at " + ", ".join(failures), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
