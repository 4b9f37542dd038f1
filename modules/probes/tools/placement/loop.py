"""The search (PLACEMENT.md): the baseline, then greedily ADD the best of the top candidates,
MOVE the new one along its normal, DROP any CMO the budget does not need, ORDER them by measured
contribution and lower each RESOLUTION while the budget holds; every step measured and recorded."""

import shutil
import tempfile
import time
import urllib.parse
from pathlib import Path

from .candidates import candidates, marginal_rank, reflection_samples
from .edit import dump, edited_document, write_atomic
from .errors import InputError
from .measure import Measurer, config_entry, fmt_pos
from .planar import flat_reflectors, planar_nodes
from .report import write_report
from .scene import Geometry, load_document, resolve_views

IMPROVE_DB = 0.05  # a change must gain this much mean PSNR to be kept (renders are deterministic)


def with_orders(cmos):
    # until the ordering step, the earlier-added CMO is traced first
    n = len(cmos)
    return [dict(c, order=n - 1 - i) for i, c in enumerate(cmos)]


class Search:
    """The configuration so far (`current`, measured as `cur`) and the steps that led to it."""

    def __init__(self, args, meas, cands, resolutions, log, planes=()):
        self.args, self.meas, self.cands, self.log = args, meas, cands, log
        self.planes = list(planes)  # flat reflectors: planar probe proposals, tried before any CMO
        self.planar_seen = set()    # the reflected samples the accepted planar probes cover
        self.resolutions = resolutions
        self.top = resolutions[-1]
        self.steps, self.step_no = [], 0
        self.planned = 1 + min(len(self.planes), args.max_planar) + args.max_cmos * (args.tries + args.move_tries) + args.max_cmos * (1 + len(resolutions))
        self.current, self.cur, self.baseline = [], None, None
        self.gains = {}

    def record(self, action, detail, cmos, r, accepted, prev):
        """`accepted` None: a trial judged after its rivals (add), which says which it kept."""
        self.step_no += 1
        step_no = self.step_no
        delta = "" if prev is None else f" ({r['mean'] - prev:+.1f})"
        verdict = "" if accepted or accepted is None else " (rejected)"
        self.log(f"placement: step {step_no}/{max(self.planned, step_no)} {action} {detail}: {r['mean']:.1f} dB"
                 f"{delta}, {r['ms']:.0f} ms{verdict}")
        accepted = bool(accepted)
        self.steps.append({"step": step_no, "action": action, "detail": detail, "count": len(cmos),
                           "planar": len(self.meas.planars),
                           "resolutions": [c["res"] for c in cmos], "cmos": config_entry(cmos),
                           "mean_psnr_db": r["mean"], "per_view_psnr_db": r["per_view"], "reflection_ms": r["ms"],
                           "accepted": accepted, "seconds": r["seconds"]})
        return self.steps[-1]

    def meets(self, r):
        return r["mean"] >= self.args.budget_db

    def spares(self, r, prev):
        """A cut (DROP, RESOLUTION) that meets the budget is kept only if no view loses more than
        --max-view-loss-db against `prev`: on cornell_mirrors against the converged references
        (2026-12-07) dropping a CMO raised the mean of four views by 0.28 dB while sphere_close
        lost 1.53 (PLACEMENT.md), and the issue asks for every view, not the mean."""
        worst = min((r["per_view"][v] - p for v, p in prev["per_view"].items() if v in r["per_view"]), default=0.0)
        return worst >= -self.args.max_view_loss_db

    def run_baseline(self):
        args = self.args
        self.cur = self.meas.measure(self.current)
        self.baseline = self.cur
        self.record("baseline", "the scene as given (no CMO added)", self.current, self.cur, True, None)
        if args.gain_db is not None:
            # The budget as a gain over the scene as given (its own baseline measured first).
            args.budget_db = self.baseline["mean"] + args.gain_db
            self.log(f"placement: budget {args.budget_db:.2f} dB (baseline {self.baseline['mean']:.2f} + "
                     f"{args.gain_db:g})")

    def add_planar(self):
        """PLANAR: each large flat reflector as a planar probe (exact for a flat mirror), kept when
        it gains; the CMOs are then ranked by what the kept ones leave."""
        for plane in self.planes[:self.args.max_planar]:
            trial = self.meas.planars + [plane]
            r = self.meas.measure(self.current, trial)
            ok = r["mean"] >= self.cur["mean"] + IMPROVE_DB
            self.record("planar", f"planar probe at {fmt_pos(plane['origin'])} {plane['extents'][0]:.2f} x "
                        f"{plane['extents'][1]:.2f} m ({plane['area']:.1f} m^2 of reflector)", self.current, r, ok,
                        self.cur["mean"])
            if ok:
                self.meas.planars = trial
                self.cur = r
                self.planar_seen |= plane["covered"]

    def add_and_move(self):
        """ADD (and MOVE the one added) until the budget is met."""
        args, meas, top = self.args, self.meas, self.top
        while not self.meets(self.cur) and len(self.current) < args.max_cmos:
            current, cur = self.current, self.cur
            chosen_seen = set().union(self.planar_seen, *[c["seen"] for c in current])
            pool = marginal_rank(self.cands, chosen_seen, {c["rank"] for c in current})[:args.tries]
            if not pool:
                self.log("placement: no candidate left to add")
                break
            best, best_r, best_step, tried = None, None, None, 0
            for cand in pool:
                tried += 1
                trial = with_orders(current + [dict(cand, res=top)])
                r = meas.measure(trial)
                st = self.record("add", f"cmo at {fmt_pos(cand['pos'])} {top} px (candidate {cand['rank']})", trial,
                                 r, None, cur["mean"])
                if best_r is None or r["mean"] > best_r["mean"]:
                    best, best_r, best_step = trial, r, st
                if self.meets(r):
                    break  # the fewest CMOs is reached: no need to try the others
            if best_r["mean"] < cur["mean"] + IMPROVE_DB:
                self.log(f"placement: no candidate improves on {cur['mean']:.2f} dB; stopping at {len(current)} CMOs")
                break
            best_step["accepted"] = True
            self.log(f"placement: kept step {best_step['step']} ({best_r['mean'] - cur['mean']:+.2f} dB), "
                     f"the best of {tried} tried")
            self.current, self.cur = best, best_r
            self.move_newest()

    def move_newest(self):
        """MOVE: the new CMO nearer to or farther from its reflector."""
        newest = self.current[-1]
        for v in newest["variants"][:self.args.move_tries]:
            if self.meets(self.cur):
                break
            trial = self.current[:-1] + [dict(newest, pos=v, variants=[])]
            r = self.meas.measure(trial)
            ok = r["mean"] >= self.cur["mean"] + IMPROVE_DB
            self.record("move", f"cmo {len(self.current) - 1} to {fmt_pos(v)}", trial, r, ok, self.cur["mean"])
            if ok:
                self.current, self.cur = trial, r

    def drop(self):
        """DROP: any CMO the budget does not need and no view misses (spares); the measured loss of
        each is its contribution."""
        gains = {}
        if self.meets(self.cur) and len(self.current) > 1:
            changed = True
            while changed and len(self.current) > 1:
                changed = False
                current, cur = self.current, self.cur
                for i in range(len(current)):
                    trial = with_orders(current[:i] + current[i + 1:])
                    r = self.meas.measure(trial)
                    ok = self.meets(r) and self.spares(r, cur)
                    self.record("drop", f"cmo {i} at {fmt_pos(current[i]['pos'])}", trial, r, ok, cur["mean"])
                    gains[current[i]["rank"]] = cur["mean"] - r["mean"]
                    if ok:
                        self.current, self.cur = trial, r
                        changed = True
                        gains = {}
                        break
        current, cur = self.current, self.cur
        if len(current) == 1:
            gains = {current[0]["rank"]: cur["mean"] - self.baseline["mean"]}
        elif len(current) > 1 and not gains:
            for i in range(len(current)):
                r = self.meas.measure(with_orders(current[:i] + current[i + 1:]))
                gains[current[i]["rank"]] = cur["mean"] - r["mean"]
        self.gains = gains

    def order(self):
        """ORDER: the largest measured contribution is traced first (highest order)."""
        current, cur, gains = self.current, self.cur, self.gains
        if len(current) > 1:
            ranked = sorted(current, key=lambda c: -gains.get(c["rank"], 0.0))
            trial = [dict(c, order=len(ranked) - 1 - i) for i, c in enumerate(ranked)]
            if self.meas.key(trial) != self.meas.key(current):
                r = self.meas.measure(trial)
                ok = r["mean"] >= cur["mean"] - 1e-9 or (self.meets(r) and not self.meets(cur))
                self.record("order", "by contribution: " + ", ".join(f"{gains.get(c['rank'], 0):+.2f} dB"
                                                                     for c in ranked),
                            trial, r, ok, cur["mean"])
                if ok:
                    self.current, self.cur = trial, r

    def lower_resolutions(self):
        """RESOLUTION: lower each CMO while the budget holds and no view loses more than
        --max-view-loss-db, the least contributing first."""
        if not self.meets(self.cur):
            return
        for c0 in sorted(self.current, key=lambda c: self.gains.get(c["rank"], 0.0)):
            i = next(j for j, c in enumerate(self.current) if c["rank"] == c0["rank"])
            for res in [x for x in reversed(self.resolutions) if x < self.current[i]["res"]]:
                trial = [dict(c, res=res) if j == i else c for j, c in enumerate(self.current)]
                r = self.meas.measure(trial)
                ok = self.meets(r) and self.spares(r, self.cur)
                self.record("resolution", f"cmo {i} {self.current[i]['res']} -> {res} px", trial, r, ok,
                            self.cur["mean"])
                if not ok:
                    break
                self.current, self.cur = trial, r


def find_candidates(args, doc, buffers, views, src, log):
    t_start = time.monotonic()
    geo = Geometry(doc, buffers, str(src))
    if not geo.tris:
        raise InputError(f"{src}: the active scene has no triangles", 3)
    samples, sky = reflection_samples(geo, doc, views, args.size_wh, grid=args.grid)
    cands = candidates(geo, samples, max_candidates=args.candidates)
    log(f"placement: {len(geo.tris)} triangles, {len(samples)} reflected samples "
        f"({sky / (sky + sum(s['w'] for s in samples) or 1):.0%} of the weight reflects the sky), "
        f"{len(cands)} candidates in {time.monotonic() - t_start:.1f} s")
    for c in cands[:8]:
        log(f"placement:   candidate {c['rank']}: at {fmt_pos(c['pos'])} off {fmt_pos(c['surface'])}, "
            f"sees {c['area']:.1f} of the reflected area (+{c['gain']:.1f} new)")
    planes = flat_reflectors(geo, doc, samples) if args.max_planar > 0 else []
    for p in planes[:4]:
        log(f"placement:   flat reflector {p['rank']}: {p['area']:.1f} m^2 at {fmt_pos(p['origin'])}, "
            f"{p['weight']:.1f} of the reflected weight")
    return cands, planes


def write_outputs(args, src, doc, glb_bin, view_names, cands, search, meas, t_start, log):
    """The edited scene and the report; exit 0 when the budget is met, else 1."""
    current, cur, baseline = search.current, search.cur, search.baseline
    met = search.meets(cur)
    out_path = Path(args.out)
    bin_uri = None
    if glb_bin is not None:
        bin_path = out_path.with_suffix(".bin")
        write_atomic(bin_path, data=glb_bin)
        bin_uri = urllib.parse.quote(bin_path.name, safe="/._-~")
    final_doc = edited_document(doc, current, str(src.resolve().parent), str(out_path.resolve().parent),
                                args.kind, bin_uri, planar_nodes(meas.planars))
    write_atomic(out_path, text=dump(final_doc))
    report = {"scene": str(src), "out": str(out_path), "budget_db": args.budget_db,
              "budget": "mean PSNR over the views >= budget_db (reflection AOV, reflective pixels" +
                        (f" of roughness below {args.max_roughness:g})" if args.max_roughness is not None else ")"),
              "views": view_names, "size": args.size, "spp": args.spp, "reference": f"{args.spp} spp" if args.spp else "converged", "kind": args.kind, "met": met,
              "baseline": {"mean_psnr_db": baseline["mean"], "per_view_psnr_db": baseline["per_view"],
                           "reflection_ms": baseline["ms"]},
              "final": {"count": len(current), "cmos": config_entry(current),
                        "planar": [{"origin": p["origin"], "rotation": p["rotation"], "extents": p["extents"]}
                                   for p in meas.planars], "mean_psnr_db": cur["mean"],
                        "per_view_psnr_db": cur["per_view"], "reflection_ms": cur["ms"]},
              "candidates": [{"rank": c["rank"], "pos": list(c["pos"]), "surface": list(c["surface"]),
                              "area": c["area"], "gain": c["gain"]} for c in cands],
              "measurements": meas.count, "seconds": time.monotonic() - t_start, "steps": search.steps}
    write_report(args, report)
    planar = f"{len(meas.planars)} planar probe{'s' if len(meas.planars) != 1 else ''} and " if meas.planars else ""
    summary = (f"{planar}{len(current)} CMO{'s' if len(current) != 1 else ''} "
               f"({', '.join(str(c['res']) for c in current) or 'none'} px): {cur['mean']:.2f} dB over "
               f"{len(view_names)} view(s) against the budget {args.budget_db:g} dB "
               f"(baseline {baseline['mean']:.2f} dB), {meas.count} measurements in {report['seconds']:.0f} s")
    if met:
        log(f"placement: budget met: {summary}; wrote {out_path}")
        return 0
    log(f"placement: budget NOT met with at most {args.max_cmos} CMOs: {summary}; wrote the best found to {out_path}")
    return 1


def place(args, tools, log):
    src = Path(args.scene)
    doc, buffers, glb_bin = load_document(src)
    view_names, views = resolve_views(args, doc, src)
    t_start = time.monotonic()
    cands, planes = find_candidates(args, doc, buffers, views, src, log)
    resolutions = sorted(args.resolutions_list)
    work = Path(tempfile.mkdtemp(prefix=".placement-", dir=str(Path(args.out).resolve().parent)))
    try:
        meas = Measurer(args, tools, doc, src, glb_bin, view_names, args.kind, work, log)
        search = Search(args, meas, cands, resolutions, log, planes)
        search.run_baseline()
        search.add_planar()
        search.add_and_move()
        search.drop()
        search.order()
        search.lower_resolutions()
        return write_outputs(args, src, doc, glb_bin, view_names, cands, search, meas, t_start, log)
    finally:
        if not args.keep_work:
            shutil.rmtree(work, ignore_errors=True)
