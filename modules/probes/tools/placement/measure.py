"""Measuring a configuration: the scene with its CMOs rendered by speculum-capture and scored
against speculum-reference as the bench scores it."""

import json
import os
import shutil
import subprocess
import time
from pathlib import Path

from .edit import dump, edited_document
from .planar import planar_nodes


class Measurer:
    def __init__(self, args, tools, doc, src, glb_bin, view_names, kind, work, log):
        import speculum_bench as bench
        self.bench, self.args, self.tools, self.doc, self.src = bench, args, tools, doc, src
        self.view_names, self.kind, self.work, self.log = view_names, kind, work, log
        self.count, self.cache = 0, {}
        self.planars = []  # the accepted planar probes, in every measured configuration
        self.bin_uri = None
        if glb_bin is not None:
            (work / "scene_glb.bin").write_bytes(glb_bin)
            self.bin_uri = "scene_glb.bin"
        self.suite = {"warmup": args.warmup, "frames": args.frames}
        # Converged references (assets/references' settings, rendered into the cache once a view)
        # unless --spp asks for a fixed rate (the tests' quick runs): a CMO judged against a noisy
        # reference was rejected as "-1.0 dB" when the difference was the reference's noise.
        self.ref_settings = ({"spp": args.spp, "bounces": args.bounces, "seed": 1} if args.spp
                             else {"converged": True, "bounces": args.bounces, "render_missing": True})
        self.refs = {}
        for v in view_names:
            view = {"scene": src.stem, "camera": v, "file": str(src)}
            ref_dir, cached = self.guard(lambda: bench.render_reference(tools, view, args.size, self.ref_settings,
                                                                        Path(args.cache)), f"reference {v}")
            info = json.loads((ref_dir / "reference.json").read_text())
            self.refs[v] = (ref_dir, info["exposure"])
            log(f"placement: reference {v} {args.size} {f'{args.spp} spp' if args.spp else 'converged'}"
                f"{' (cached)' if cached else ''}")
        # --max-roughness: score only pixels below it (the roughness AOV does not change with CMOs).
        self.rough = {}
        if args.max_roughness is not None:
            for v in view_names:
                out = work / f"roughness_{v.replace('/', '_')}"
                out.mkdir(parents=True, exist_ok=True)
                cmd = [tools.capture, "--scene", str(src), "--camera", v, "--size", args.size, "--warmup", "0",
                       "--aov", "roughness", "--out", str(out)]
                if bench.run(cmd, out / "log.txt") != 0:
                    raise RuntimeError(f"roughness capture failed for {v}; see {out / 'log.txt'}")
                self.rough[v] = bench.last_frame(out, "roughness")

    def score(self, v, image, ref_dir, exposure, heatmap):
        if v not in self.rough:
            return self.bench.score(self.tools, image, ref_dir, "reflection", exposure, heatmap)
        cmd = [self.tools.metrics, "compare", "--test", str(image), "--ref", str(ref_dir / "reflection.0000.exr"),
               "--ref-mask", str(ref_dir / "reflective.0000.exr"), "--test-mask", str(image),
               "--scale", str(exposure), "--band-image", str(self.rough[v]),
               "--bands", f"0,{self.args.max_roughness:g}"]
        cmd += self.bench.store.ref_error_args(ref_dir)  # converged: its unconverged pixels are not scored
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"speculum-metrics failed: {r.stderr.strip()}")
        return json.loads(r.stdout)["bands"][0]

    @staticmethod
    def guard(fn, what):
        try:
            return fn()
        except SystemExit as e:  # the bench's fail(): its message is already on stderr
            raise RuntimeError(f"{what} failed (exit {e.code})")

    def key(self, cmos, planars=None):
        planars = self.planars if planars is None else planars
        return json.dumps([[[[round(x, 5) for x in c["pos"]], c["res"], c["order"]] for c in cmos],
                           [p["rank"] for p in planars]])

    def measure(self, cmos, planars=None):
        """The configuration's scores: `cmos` and the planar probes (the accepted ones by default)."""
        planars = self.planars if planars is None else planars
        k = self.key(cmos, planars)
        if k in self.cache:
            return self.cache[k]
        self.count += 1
        folder = self.work / f"m{self.count:03d}"
        folder.mkdir(parents=True, exist_ok=True)
        gltf = folder / "scene.gltf"
        gltf.write_text(dump(edited_document(self.doc, cmos, str(self.src.parent), str(folder), self.kind,
                                             os.path.relpath(self.work / "scene_glb.bin", folder)
                                             if self.bin_uri else None, planar_nodes(planars))))
        per_view, ms_sum = {}, 0.0
        t0 = time.monotonic()
        for v in self.view_names:
            view = {"scene": self.src.stem, "camera": v, "file": str(gltf)}
            out = folder / v.replace("/", "_")
            image, refl_ms, _, _ = self.guard(lambda: self.bench.capture(
                self.tools, view, self.args.size, self.args.set, "reflection", self.suite, out), f"capture {v}")
            ref_dir, exposure = self.refs[v]
            m = self.guard(lambda: self.score(v, image, ref_dir, exposure, out / "heatmap.png"), f"score {v}")
            per_view[v] = m["psnr_db"] if m["psnr_db"] is not None else float("nan")
            ms_sum += refl_ms
        vals = list(per_view.values())
        result = {"mean": sum(vals) / len(vals), "per_view": per_view, "ms": ms_sum / len(vals),
                  "seconds": time.monotonic() - t0}
        if not self.args.keep_work:
            shutil.rmtree(folder, ignore_errors=True)
        self.cache[k] = result
        return result


def fmt_pos(p):
    return "(" + ",".join(f"{x:.2f}" for x in p) + ")"


def config_entry(cmos):
    return [{"pos": [round(x, 5) for x in c["pos"]], "resolution": c["res"], "order": c["order"],
             "candidate": c.get("rank")} for c in cmos]
