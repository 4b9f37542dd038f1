#!/usr/bin/env python3
"""Accuracy on edge pixels of a finished speculum-bench run (issue 13: half resolution may lose at
most 1.5 dB against full resolution on pixels within 2 px of a depth or normal edge).

    edge_pixels.py --bench-out DIR --suite SUITE.json --capture C --reference R --metrics M
                   [--cache DIR] [--methods hiz+probes,half] [--radius 2]

Per view and size it captures depth and normal once, marks the pixels within RADIUS px of an
edge (a neighbour's view depth differs by more than 5%, or its normal by more than 25 degrees),
writes that mask as an image and scores each method's last reflection frame against the cached
reference on the masked pixels (`speculum-metrics compare --band-image MASK --bands 0.5,1.5`).
Prints per view and pooled PSNR (dB) on edge pixels and on all reflective pixels."""
import json, math, struct, subprocess, sys, tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "capture"))
import speculum_bench as bench  # noqa: E402
from stripes_test import load  # noqa: E402


def edge_mask(depth, normal, w, h, radius):
    """1 within `radius` px (Chebyshev) of an edge between 4-neighbours."""
    d = depth["Y"] if "Y" in depth else depth["R"]
    n = [normal[c] for c in ("R", "G", "B")]
    edge = bytearray(w * h)
    cos_limit = math.cos(math.radians(25))
    for y in range(h):
        for x in range(w):
            a = d[y][x]
            for dx, dy in ((1, 0), (0, 1)):
                xx, yy = x + dx, y + dy
                if xx >= w or yy >= h:
                    continue
                b = d[yy][xx]
                cut = (a > 0) != (b > 0)
                if a > 0 and b > 0 and abs(1 / a - 1 / b) > 0.05 * min(1 / a, 1 / b):
                    cut = True
                if not cut and a > 0 and b > 0:
                    dot = sum(n[c][y][x] * n[c][yy][xx] for c in range(3))
                    la = math.sqrt(sum(n[c][y][x] ** 2 for c in range(3)))
                    lb = math.sqrt(sum(n[c][yy][xx] ** 2 for c in range(3)))
                    cut = la > 0 and lb > 0 and dot / (la * lb) < cos_limit
                if cut:
                    edge[y * w + x] = edge[yy * w + xx] = 1
    # Dilate by `radius` (separable max).
    for _ in range(radius):
        grown = bytearray(edge)
        for y in range(h):
            for x in range(w):
                if edge[y * w + x]:
                    for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1)):
                        xx, yy = x + dx, y + dy
                        if 0 <= xx < w and 0 <= yy < h:
                            grown[yy * w + xx] = 1
        edge = grown
    return edge


def write_mask(mask, w, h, path, tmp):
    pfm = Path(tmp) / "mask.pfm"
    with open(pfm, "wb") as f:
        f.write(f"Pf\n{w} {h}\n-1.0\n".encode())
        for y in range(h - 1, -1, -1):  # PFM rows run bottom to top
            f.write(struct.pack(f"<{w}f", *mask[y * w:(y + 1) * w]))
    subprocess.run(["oiiotool", str(pfm), "-o", str(path)], check=True)


def main():
    ap = bench.rescore_parser()
    ap.add_argument("--methods", default="hiz+probes,half"); ap.add_argument("--radius", type=int, default=2)
    a = ap.parse_args()
    out, suite, tools, views = bench.finished_run(a)
    methods = a.methods.split(",")
    pooled = {}
    print("| view | method | PSNR edge pixels | PSNR all | edge pixels |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for view, size, name, ref_dir, exposure in views:
            gdir = out / "runs" / f"{name}.edges"
            mask_file = gdir / "edge_mask.exr"
            if not mask_file.exists():
                gdir.mkdir(parents=True, exist_ok=True)
                cmd = [a.capture, "--scene", str(bench.scene_file(view)), *bench.camera_args(view), "--size", size,
                       "--warmup", "0", "--aov", "depth,normal", "--out", str(gdir)]
                if bench.run(cmd, gdir / "log.txt") != 0:
                    bench.fail(f"depth/normal capture failed for {name}; see {gdir / 'log.txt'}", 1)
                w, h, depth = load(str(bench.last_frame(gdir, "depth")), tmp)
                _, _, normal = load(str(bench.last_frame(gdir, "normal")), tmp)
                write_mask(edge_mask(depth, normal, w, h, a.radius), w, h, mask_file, tmp)
            for method in methods:
                test = bench.last_frame(out / "runs" / f"{name}.{method}", "reflection")
                cmd = [a.metrics, "compare", "--test", str(test), "--ref", str(ref_dir / "reflection.0000.exr"),
                       "--ref-mask", str(ref_dir / "reflective.0000.exr"), "--test-mask", str(test),
                       "--scale", str(exposure), "--band-image", str(mask_file), "--bands", "0.5,1.5"]
                r = subprocess.run(cmd, capture_output=True, text=True)
                if r.returncode != 0:
                    bench.fail(f"speculum-metrics failed: {r.stderr.strip()}", 1)
                j = json.loads(r.stdout)
                e = j["bands"][0]
                for key, s in (("edge", e), ("all", j)):
                    if s["pixels"] and s["psnr_db"] is not None:
                        acc = pooled.setdefault((method, key), [0.0, 0])
                        acc[0] += 10 ** (-s["psnr_db"] / 10) * s["pixels"]
                        acc[1] += s["pixels"]
                print(f"| {name} | {method} | {e['psnr_db'] or float('nan'):.2f} | {j['psnr_db']:.2f} | {e['pixels']} |",
                      flush=True)
    for method in methods:
        cells = []
        for key in ("edge", "all"):
            se, n = pooled.get((method, key), [0.0, 1])
            cells.append(f"{10 * math.log10(n / se):.2f}" if se > 0 else "-")
        print(f"| pooled | {method} | {cells[0]} | {cells[1]} | {pooled.get((method, 'edge'), [0, 0])[1]} |")


if __name__ == "__main__":
    main()
