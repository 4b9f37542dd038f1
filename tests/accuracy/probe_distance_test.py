#!/usr/bin/env python3
"""The local probes' captured distances against the converged references (label accuracy;
thresholds.json "probe_distance"):

    probe_distance_test.py TOOLS... --out DIR

Each view of the rule is captured with the default chain twice, with the probes' distance march
(probes.distance_steps, its default) and without it (probes.distance_steps=0: the box or sphere
proxy alone), and both are scored per band against the view's converged reference. The march must
gain min_gain_db where the rule names a band (measured without the scene's planar probes where
it says without_planar) (cornell_mirrors' rough walls: its chrome objects,
near the probe's capture point, fill much of the cube, and their reflections in it land where
they are seen from), and must never cost a view's mirror band more than max_loss_db (it falls
back to the proxy wherever it finds no surface).
"""
import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "bench"))
import speculum_bench as bench  # noqa: E402
from accuracy_args import tool_parser  # noqa: E402
sys.path.insert(0, str(HERE.parent / "capture"))
from stripes_test import without_planar_probes  # noqa: E402


def main():
    p = tool_parser()
    p.add_argument("--out", required=True)
    a = p.parse_args()
    rule = json.loads(Path(a.thresholds).read_text())["probe_distance"]
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    ok = True
    for name, view_rule in rule["views"].items():
        scene, camera = name.split(".")
        view = {"scene": scene, "camera": camera}
        # A view whose mirrors the scene's planar probes serve is measured without them: this
        # rule is about the local probes' march (failure_cases' floor and vertical mirror).
        if view_rule.get("without_planar"):
            view["file"] = without_planar_probes(str(bench.SOURCE / "assets" / "scenes" / f"{scene}.gltf"),
                                                 str(out / f"{name}.scene"))
        ref_dir, _ = bench.render_reference(a, view, rule["size"], rule["reference"], out / "cache")
        exposure = json.loads((ref_dir / "reference.json").read_text())["exposure"]
        got = {}
        for label, sets in (("march", []), ("proxy", ["probes.distance_steps=0"])):
            image, _, _, _ = bench.capture(a, view, rule["size"], sets, "reflection",
                                           {"warmup": rule["warmup"], "frames": 1}, out / f"{name}.{label}")
            got[label] = bench.score(a, image, ref_dir, "reflection", exposure, out / f"{name}.{label}.heatmap.png")
        mirror = got["march"]["mirror_psnr_db"] - got["proxy"]["mirror_psnr_db"]
        rough = got["march"]["rough_psnr_db"] - got["proxy"]["rough_psnr_db"]
        good = mirror >= -rule["max_loss_db"]
        need = ""
        if "min_gain_db" in view_rule:
            band, limit = view_rule["band"], view_rule["min_gain_db"]
            gain = mirror if band == "mirror" else rough
            good &= gain >= limit
            need = f"; the {band} band must gain >= {limit}"
        print(f"{name}: mirror band {got['march']['mirror_psnr_db']:.2f} dB with the march, "
              f"{got['proxy']['mirror_psnr_db']:.2f} with the proxy ({mirror:+.2f}); rough band "
              f"{got['march']['rough_psnr_db']:.2f} / {got['proxy']['rough_psnr_db']:.2f} ({rough:+.2f})"
              f"{need}; the mirror band may lose at most {rule['max_loss_db']}{'' if good else '  FAIL'}")
        ok &= good
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
