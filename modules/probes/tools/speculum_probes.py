#!/usr/bin/env python3
"""speculum-probes place: the fewest CMOs, the lowest resolutions and their order that meet an
accuracy budget against the reference renderer (docs/design.md section 4, probes; seed 000 section 3.8).

    speculum-probes place --scene FILE --budget-db D [--views CAM1,CAM2,...] [--size WxH]
                          [--max-cmos N] [--resolutions 64,128,256] [--spp N]
                          --out FILE.gltf [--report FILE.json]

The budget: the configuration must reach a mean PSNR >= D dB over the views, where each view's
PSNR is the bench's score of the engine's `reflection` AOV against speculum-reference's, on
reflective pixels (clamped linear after the scene's exposure; tests/bench/speculum_bench.py).

How (modules/probes/PLACEMENT.md):
1. Candidates, from geometry alone (standard-library ray casting over the glTF's triangles):
   rays from each view's camera find reflective surfaces (every lit material whose
   SPECULUM_reflections mode is not "off"; metals and low roughness weigh most); each reflects
   a sample ray; what it hits is the "potentially reflected area" (seed 000 section 3.8).
   Reflector samples are clustered (farthest-point seeds), and each cluster proposes a CMO
   centre near its reflector, offset along the normal (not at the surface, not inside
   geometry). Candidates are ranked by the reflected area they see (a greedy set cover, so the
   ranking spreads them apart).
2. Measuring: the baseline (the scene as given), then greedily ADD the best of the top
   candidates, MOVE the new one along its normal, DROP any CMO the budget does not need, order
   them by measured contribution (higher "order" is traced first) and lower each resolution
   while the budget holds. Every configuration is a temporary glTF rendered by
   speculum-capture (--aov reflection, warm-up frames) and scored as the bench does.
3. Output: the scene's glTF with the CMO nodes added through SPECULUM_reflection_probe (every
   other key kept), written atomically; a report (JSON and markdown) beside it or at --report.

Exit status: 0 the budget is met (the output is written); 1 it is not met with --max-cmos CMOs
(the best configuration found is written) or a tool failed; 2 bad arguments; 3 bad scene.
"""
import argparse
import math
import os
import shutil
import sys
import tempfile
from pathlib import Path

# placement/ (beside this file) puts the source tree's tools/ (the shared speculum_py) and
# tests/bench on sys.path when imported, so it is imported first.
from placement.errors import InputError
from placement.loop import place
from placement.scene import load_document, resolve_views
from speculum_py.enums import KIND


# ------------------------------------------------------------------------------------------
# Command line.


def parse_size(text):
    try:
        w, h = text.lower().split("x")
        w, h = int(w), int(h)
    except ValueError:
        raise InputError(f"--size {text}: needs WxH with two whole numbers", 2)
    if not (1 <= w <= 16384 and 1 <= h <= 16384):
        raise InputError(f"--size {text}: each side must be in 1..16384", 2)
    return w, h


def check_args(args):
    if (args.budget_db is None) == (args.gain_db is None):
        raise InputError("give one of --budget-db and --gain-db", 2)
    if args.gain_db is not None:
        if not math.isfinite(args.gain_db):
            raise InputError(f"--gain-db {args.gain_db}: must be a finite number of dB", 2)
        args.budget_db = 0.0  # set from the baseline once it is measured
    try:
        args.budget_db = float(args.budget_db)
    except ValueError:
        raise InputError(f"--budget-db {args.budget_db}: not a number", 2)
    if not math.isfinite(args.budget_db):
        raise InputError(f"--budget-db {args.budget_db}: must be a finite number of dB", 2)
    if not (math.isfinite(args.max_view_loss_db) and args.max_view_loss_db >= 0.0):
        raise InputError(f"--max-view-loss-db {args.max_view_loss_db}: must be a finite number of dB, 0 or more", 2)
    args.size_wh = parse_size(args.size)
    try:
        res = [int(x) for x in args.resolutions.split(",") if x.strip()]
    except ValueError:
        raise InputError(f"--resolutions {args.resolutions}: needs whole numbers separated by commas", 2)
    if not res or any(r < 32 or r > 4096 or r & (r - 1) for r in res):
        raise InputError(f"--resolutions {args.resolutions}: each must be a power of two in [32, 4096]", 2)
    args.resolutions_list = sorted(set(res))
    for name, lo in (("max_cmos", 1), ("max_planar", 0), ("spp", 0), ("tries", 1), ("move_tries", 0), ("warmup", 0), ("frames", 1),
                     ("bounces", 1), ("candidates", 1), ("grid", 4)):
        if getattr(args, name) < lo:
            raise InputError(f"--{name.replace('_', '-')} {getattr(args, name)}: must be at least {lo}", 2)
    out = Path(args.out)
    if out.suffix.lower() != ".gltf":
        raise InputError(f"--out {args.out}: must name a .gltf file", 2)
    if out.exists() and not out.is_file():
        raise InputError(f"--out {args.out}: is a folder or a device, not a file", 2)
    parent = out.resolve().parent
    if not parent.is_dir():
        raise InputError(f"--out {args.out}: the folder {parent} does not exist", 2)
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(f"--out {args.out}: the folder {parent} is not writable", 2)
    if args.report:
        rp = Path(args.report)
        if rp.exists() and not rp.is_file():
            raise InputError(f"--report {args.report}: is a folder or a device, not a file", 2)
        if not rp.resolve().parent.is_dir() or not os.access(rp.resolve().parent, os.W_OK | os.X_OK):
            raise InputError(f"--report {args.report}: its folder does not exist or is not writable", 2)
    for s in args.set:
        if "=" not in s:
            raise InputError(f"--set {s}: needs KEY=VALUE", 2)


def probe_capture(args, tools):
    """One tiny render of the scene as given: a bad scene is exit 3 here, in seconds."""
    import speculum_bench as bench
    scratch = Path(tempfile.mkdtemp(prefix=".placement-probe-", dir=str(Path(args.out).resolve().parent)))
    try:
        cmd = [tools.capture, "--scene", str(args.scene), "--size", "32x18", "--warmup", "0", "--aov", "reflection",
               "--out", str(scratch / "out")]
        for s in args.set:
            cmd += ["--set", s]
        rc = bench.run(cmd, scratch / "log.txt")
        text = (scratch / "log.txt").read_text(errors="replace").strip().splitlines()
        last = text[-1] if text else ""
        if rc == 3:
            raise InputError(f"{args.scene}: speculum-capture refuses the scene: {last}", 3)
        if rc == 2:
            raise InputError(f"speculum-capture refuses the arguments (--set, or no reflection AOV): {last}", 2)
        if rc != 0:
            raise RuntimeError(f"speculum-capture failed on {args.scene} (exit {rc}): {last}")
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


def main(argv=None):
    p = argparse.ArgumentParser(prog="speculum-probes", description=__doc__.split("\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    for hidden in ("--capture", "--reference", "--metrics", "--cache-default"):  # set by the wrapper
        p.add_argument(hidden, help=argparse.SUPPRESS)
    sub_p = p.add_subparsers(dest="command", metavar="place")
    pl = sub_p.add_parser("place", help="propose CMOs that meet an accuracy budget", description=__doc__,
                          formatter_class=argparse.RawDescriptionHelpFormatter)
    pl.add_argument("--scene", required=True, help="glTF scene (.gltf or .glb)")
    pl.add_argument("--gain-db", type=float,
                    help="instead of --budget-db: the budget is the scene's own baseline (as given) plus this")
    pl.add_argument("--budget-db",
                    help="the budget: the configuration must reach a mean PSNR >= D dB over the views "
                         "(each view: the reflection AOV against speculum-reference on reflective pixels)")
    pl.add_argument("--views", help="comma list of camera names (default: every camera of the scene)")
    pl.add_argument("--size", default="240x135", help="render size WxH (default 240x135)")
    pl.add_argument("--max-cmos", type=int, default=4, help="at most this many CMOs (default 4)")
    pl.add_argument("--max-planar", type=int, default=4,
                    help="planar probes tried first, one per large flat reflector, at most this many (default 4, "
                         "the engine's limit; 0: none)")
    pl.add_argument("--resolutions", default="64,128,256",
                    help="cube face sizes to choose from, powers of two >= 32 (default 64,128,256); "
                         "CMOs are added at the largest and lowered while the budget holds")
    pl.add_argument("--spp", type=int, default=0,
                    help="reference samples per pixel at a fixed rate (default 0: converged references, "
                         "tests/reference/README.md; a fixed rate is for quick runs only)")
    pl.add_argument("--bounces", type=int, default=2, help="reference bounces (default 2: a scene the store lacks renders its converged reference in "
                         "minutes at 2, about 1.5x that at 4, the depth presets_suite.json scores at)")
    pl.add_argument("--warmup", type=int, default=3, help="speculum-capture warm-up frames (default 3)")
    pl.add_argument("--frames", type=int, default=2, help="speculum-capture counted frames (default 2)")
    pl.add_argument("--tries", type=int, default=3, help="candidates measured per ADD step (default 3)")
    pl.add_argument("--move-tries", type=int, default=2, help="positions tried per MOVE step (default 2)")
    pl.add_argument("--max-view-loss-db", type=float, default=0.5,
                    help="DROP and RESOLUTION keep a cut only where no view loses more than this against the "
                         "configuration before it (default 0.5 dB; PLACEMENT.md: the mean alone traded one "
                         "view's 1.5 dB for another's 1.9)")
    pl.add_argument("--candidates", type=int, default=12, help="candidate centres proposed (default 12)")
    pl.add_argument("--grid", type=int, default=48, help="sample rays across each view (default 48)")
    pl.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="engine setting for every capture (repeatable)")
    pl.add_argument("--max-roughness", type=float,
                    help="score only pixels whose roughness is below this (CMOs trace up to "
                         "reflections.cmo_max_roughness; default: every reflective pixel)")
    pl.add_argument("--kind", choices=(KIND.cmo, KIND.local_cubemap), default=KIND.cmo,
                    help="probe kind written (default cmo; local_cubemap measures the loop with local "
                         "cubemaps as a stand-in)")
    pl.add_argument("--out", required=True, help="output .gltf (written atomically)")
    pl.add_argument("--report", help="report JSON (default OUT-stem.placement.json; a .md beside it)")
    pl.add_argument("--cache", help="reference image cache (default: a folder beside --out)")
    pl.add_argument("--keep-work", action="store_true", help="keep every measured configuration's files")
    args = p.parse_args(argv)
    if args.command != "place":
        p.print_usage(sys.stderr)
        print("speculum-probes: a command is required: place", file=sys.stderr)
        return 2
    try:
        check_args(args)
        for tool in (args.capture, args.reference, args.metrics):
            if not tool or not os.access(tool, os.X_OK):
                raise InputError(f"{tool}: not built (run the wrapper in the build folder)", 2)
        if args.cache is None:
            args.cache = args.cache_default or str(Path(args.out).resolve().parent / ".placement-cache")
        doc = load_document(args.scene)[0]  # the scene's own problems first, before any device starts
        resolve_views(args, doc, Path(args.scene))
        probe_capture(args, args)
        return place(args, args, lambda line: print(line, flush=True))
    except InputError as e:
        print(f"speculum-probes: {e}", file=sys.stderr)
        return e.code
    except RuntimeError as e:
        print(f"speculum-probes: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
