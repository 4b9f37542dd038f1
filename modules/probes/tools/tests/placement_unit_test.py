#!/usr/bin/env python3
"""placement.unit: speculum-probes place without a GPU: material weights, candidate generation on
the test room (off the surfaces, outside geometry, spread apart, ranked by reflected area), the
glTF edit (CMO nodes appended, unknown content kept, file references that still resolve), atomic
writes and the argument checks (exit 2 and 3 before anything renders)."""
import contextlib
import io
import json
import math
import os
import sys
import tempfile
import unittest
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))
import placement_scene  # noqa: E402
import speculum_probes as sp  # noqa: E402  (the command line; it puts tools/ on sys.path)
from placement import candidates as cand, edit, loop, planar, scene  # noqa: E402
from speculum_py.enums import PROBE_EXT  # noqa: E402

SPHERE_C, SPHERE_R = (0.0, 0.6, -0.6), 0.6


class Scene(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = Path(cls.tmp.name)
        cls.path = placement_scene.write_scene(cls.dir / "scene")
        cls.doc, cls.buffers, _ = scene.load_document(cls.path)
        cls.geo = scene.Geometry(cls.doc, cls.buffers, str(cls.path))
        cls.views = scene.cameras(cls.doc)
        cls.samples, cls.sky = cand.reflection_samples(cls.geo, cls.doc, cls.views, (160, 90), grid=32)
        cls.cands = cand.candidates(cls.geo, cls.samples, max_candidates=10)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()


class Candidates(Scene):
    def test_material_weights(self):
        w = scene.material_weight
        self.assertEqual(w({"extensions": {"KHR_materials_unlit": {}}}), 0.0)
        self.assertEqual(w({"extensions": {"SPECULUM_reflections": {"mode": "off"}}}), 0.0)
        self.assertEqual(w({"extensions": {"SPECULUM_reflections": {"traceCmos": False}}}), 0.0)
        chrome = w({"pbrMetallicRoughness": {"metallicFactor": 1.0, "roughnessFactor": 0.0}})
        floor = w({"pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.08}})
        rough = w({"pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.9}})
        self.assertGreater(chrome, floor)
        self.assertGreater(floor, rough)
        self.assertEqual(w({}), 0.0, "glTF defaults (metal, roughness 1) matter too little")
        overridden = w({"pbrMetallicRoughness": {"metallicFactor": 1.0, "roughnessFactor": 1.0},
                        "extensions": {"SPECULUM_reflections": {"roughnessOverride": 0.0}}})
        self.assertAlmostEqual(overridden, 1.0)

    def test_geometry_and_camera(self):
        self.assertEqual([v[0] for v in self.views], ["main"])
        self.assertGreater(len(self.geo.tris), 1000)
        # a ray straight down from the room's middle meets the floor at y = 0
        t, tri = self.geo.cast((1.5, 1.0, 1.5), (0.0, -1.0, 0.0))
        self.assertAlmostEqual(t, 1.0, places=4)
        self.assertTrue(self.geo.inside((0.0, 0.6, -0.6)), "the sphere's centre is inside it")
        self.assertFalse(self.geo.inside((1.5, 1.5, 1.5)), "the room's air is not inside anything")

    def test_samples_hit_the_reflectors(self):
        self.assertGreater(len(self.samples), 100)
        self.assertEqual(self.sky, 0.0, "a closed room reflects no sky")
        on_sphere = [s for s in self.samples if abs(scene.dist(s["p"], SPHERE_C) - SPHERE_R) < 0.02]
        self.assertTrue(on_sphere, "the chrome sphere is sampled")
        self.assertGreater(max(s["w"] for s in on_sphere), max(s["w"] for s in self.samples if s["p"][1] < 1e-3),
                           "chrome weighs more than the glossy floor")

    def test_candidates_are_near_reflectors_off_the_surface_and_spread(self):
        self.assertGreaterEqual(len(self.cands), 2)
        offset = min(max(0.04 * self.geo.diagonal, 0.05), 0.6)
        for c in self.cands:
            p = c["pos"]
            self.assertTrue(all(-3.0 < p[k] < 3.0 for k in (0, 2)) and 0.0 < p[1] < 3.0, f"outside the room: {p}")
            self.assertGreater(scene.dist(p, SPHERE_C), SPHERE_R + 0.02, f"inside or on the sphere: {p}")
            self.assertGreater(p[1], 0.02, f"on the floor: {p}")
            self.assertFalse(self.geo.inside(p))
            gap = scene.dist(p, c["surface"])
            self.assertTrue(0.0 < gap <= offset * 1.0001, f"offset {gap} from its reflector")
            self.assertGreater(c["area"], 0.0)
            self.assertGreater(c["radius"], 0.0)
        for i, a in enumerate(self.cands):
            for b in self.cands[i + 1:]:
                self.assertGreaterEqual(scene.dist(a["pos"], b["pos"]), offset * 0.999, "candidates not spread apart")
        # ranked by a greedy cover: the first sees at least as much as any other
        self.assertEqual([c["rank"] for c in self.cands], list(range(len(self.cands))))
        self.assertGreaterEqual(self.cands[0]["area"], max(c["area"] for c in self.cands) - 1e-9)
        gains = [c["gain"] for c in self.cands]
        self.assertEqual(gains, sorted(gains, reverse=True))

    def test_place_off_surface_refuses_inside_and_cramped(self):
        # from the sphere's top along the inward normal: the point would be inside the sphere
        self.assertIsNone(cand.place_off_surface(self.geo, (0.0, 1.2, -0.6), (0.0, -1.0, 0.0), 0.3, 0.05))
        # from the floor toward the sphere 0.02 m above it: too cramped
        self.assertIsNone(cand.place_off_surface(self.geo, (0.0, -0.02, -0.6), (0.0, 1.0, 0.0), 0.3, 0.05))
        c = cand.place_off_surface(self.geo, (2.0, 0.0, 2.0), (0.0, 1.0, 0.0), 0.3, 0.05)
        self.assertAlmostEqual(c[1], 0.3, places=6)
        # toward a wall 0.2 m away: shortened to half the gap, off the wall
        c = cand.place_off_surface(self.geo, (2.8, 0.5, 0.0), (1.0, 0.0, 0.0), 0.5, 0.05)
        self.assertIsNotNone(c)
        self.assertLess(c[0], 3.0 - 0.05)


class Edit(Scene):
    CMOS = [{"pos": (0.1, 1.2, 0.3), "res": 64, "order": 1, "radius": 2.5},
            {"pos": (-1.0, 0.4, 1.0), "res": 32, "order": 0, "radius": 0.0}]

    def test_nodes_appended_unknown_content_kept(self):
        before = json.loads(json.dumps(self.doc))
        out = edit.edited_document(self.doc, self.CMOS, str(self.path.parent), str(self.path.parent))
        self.assertEqual(self.doc, before, "the source document is not modified")
        n = len(before["nodes"])
        self.assertEqual(out["nodes"][:n], before["nodes"])
        self.assertEqual([x["name"] for x in out["nodes"][n:]], ["cmo.0", "cmo.1"])
        roots = out["scenes"][out.get("scene", 0)]["nodes"]
        self.assertEqual(roots[:-2], before["scenes"][0]["nodes"])
        self.assertEqual(roots[-2:], [n, n + 1])
        e = out["nodes"][n]["extensions"][PROBE_EXT]
        self.assertEqual(e, {"kind": "cmo", "resolution": 64, "order": 1, "update": "once", "shape": "sphere",
                             "extents": [2.5, 2.5, 2.5], "blendDistance": 0.0})
        self.assertTrue(all(x > 0 for x in out["nodes"][n + 1]["extensions"][PROBE_EXT]["extents"]))
        self.assertEqual(out["extensions"][placement_scene.UNKNOWN_EXT], before["extensions"][placement_scene.UNKNOWN_EXT])
        self.assertEqual(out["extras"], {"author": "placement test"})
        self.assertIn(placement_scene.UNKNOWN_EXT, out["extensionsUsed"])
        self.assertEqual(out["extensionsUsed"].count(PROBE_EXT), 1)
        for key in before:
            if key not in ("nodes", "scenes", "extensionsUsed"):
                self.assertEqual(out[key], before[key], key)
        # again on its own output: the extension is listed once, names do not clash
        again = edit.edited_document(out, self.CMOS[:1], str(self.path.parent), str(self.path.parent))
        self.assertEqual(again["extensionsUsed"].count(PROBE_EXT), 1)
        self.assertEqual(again["nodes"][-1]["name"], "cmo.2")

    def test_file_references_follow_the_output(self):
        other = self.dir / "elsewhere" / "deeper"
        other.mkdir(parents=True, exist_ok=True)
        out = edit.edited_document(self.doc, self.CMOS, str(self.path.parent), str(other))
        bin_uri = out["buffers"][0]["uri"]
        self.assertEqual(bin_uri, "../../scene/placement_room.bin")
        self.assertTrue((other / bin_uri).resolve() == (self.path.parent / self.doc["buffers"][0]["uri"]).resolve())
        env = out["scenes"][0]["extras"]["environment"]
        self.assertTrue(os.path.isfile(os.path.join(str(other), env)), env)
        same = edit.edited_document(self.doc, [], str(self.path.parent), str(self.path.parent))
        self.assertEqual(same, self.doc, "no CMO and the same folder: the document is unchanged")
        self.assertEqual(edit.relocate_uri("a%20b.bin", "/x/s", "/x/t"), "../s/a%20b.bin")
        self.assertEqual(edit.relocate_uri("data:application/octet-stream;base64,AAAA", "/x", "/y"),
                         "data:application/octet-stream;base64,AAAA")

    def test_write_atomic(self):
        target = self.dir / "atomic.gltf"
        edit.write_atomic(target, text="{}\n")
        edit.write_atomic(target, text='{"a": 1}\n')
        self.assertEqual(json.loads(target.read_text()), {"a": 1})
        self.assertEqual([p.name for p in self.dir.iterdir() if p.name.startswith(".atomic")], [])


class Arguments(Scene):
    def run_cli(self, *argv):
        err = io.StringIO()
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            code = sp.main(["--capture", "/bin/true", "--reference", "/bin/true", "--metrics", "/bin/true", "place",
                            *argv])
        return code, err.getvalue()

    def base(self, **over):
        a = {"--scene": str(self.path), "--budget-db": "20", "--out": str(self.dir / "o.gltf")}
        a.update(over)
        return [x for k, v in a.items() if v is not None for x in (k, v)]

    def test_bad_input(self):
        cases = [
            ({"--budget-db": "nan"}, 2, "finite"),
            ({"--budget-db": "inf"}, 2, "finite"),
            ({"--budget-db": "twenty"}, 2, "not a number"),
            ({"--size": "160by90"}, 2, "WxH"),
            ({"--resolutions": "48,128"}, 2, "power of two"),
            ({"--resolutions": "16"}, 2, "power of two"),
            ({"--max-cmos": "0"}, 2, "at least 1"),
            ({"--max-view-loss-db": "-1"}, 2, "0 or more"),
            ({"--max-view-loss-db": "nan"}, 2, "0 or more"),
            ({"--out": str(self.dir)}, 2, ".gltf"),
            ({"--out": str(self.dir / "x.glb")}, 2, ".gltf"),
            ({"--out": str(self.dir / "no" / "such" / "o.gltf")}, 2, "does not exist"),
            ({"--scene": str(self.dir / "missing.gltf")}, 3, "missing.gltf: no such file"),
            ({"--scene": str(self.dir)}, 3, "is a folder"),
            ({"--scene": "/dev/zero"}, 3, "not a regular file"),
            ({"--views": "main,nobody"}, 2, "no camera named 'nobody'"),
        ]
        for over, code, text in cases:
            got, err = self.run_cli(*self.base(**over))
            self.assertEqual(got, code, f"{over}: {err}")
            self.assertIn(text, err, over)
            self.assertEqual(len(err.strip().splitlines()), 1, f"one line: {err}")
        folder = self.dir / "a_folder.gltf"
        folder.mkdir(exist_ok=True)
        got, err = self.run_cli(*self.base(**{"--out": str(folder)}))
        self.assertEqual(got, 2, err)

    def test_no_camera(self):
        doc = json.loads(self.path.read_text())
        for n in doc["nodes"]:
            n.pop("camera", None)
        bad = self.path.parent / "nocam.gltf"
        bad.write_text(json.dumps(doc))
        got, err = self.run_cli(*self.base(**{"--scene": str(bad)}))
        self.assertEqual(got, 3, err)
        self.assertIn("no camera", err)
        broken = self.path.parent / "broken.gltf"
        broken.write_text("{ not json")
        got, err = self.run_cli(*self.base(**{"--scene": str(broken)}))
        self.assertEqual((got, "broken.gltf" in err), (3, True), err)


class Planar(Scene):
    def test_a_glossy_floor_is_proposed_as_a_planar_probe(self):
        # The room's floor is a glossy dielectric (0.08): proposed, as one plane (y = 0) spanning
        # the lapped floor, 3.02 m each way (the closed room's tile floor, 0.1, is such a one:
        # planar.MIN_WEIGHT). Rough (0.6), it is left to the CMOs.
        doc = json.loads(json.dumps(self.doc))
        floor = next(m for m in doc["materials"] if m["name"] == "floor")
        floor["pbrMetallicRoughness"].update(metallicFactor=0.0, roughnessFactor=0.6)
        samples, _ = cand.reflection_samples(self.geo, doc, self.views, (160, 90), grid=32)
        self.assertEqual(planar.flat_reflectors(self.geo, doc, samples), [])
        doc = self.doc
        planes = planar.flat_reflectors(self.geo, doc, self.samples)
        self.assertEqual(len(planes), 1, planes)
        p = planes[0]
        self.assertAlmostEqual(p["normal"][1], 1.0, places=5)
        self.assertAlmostEqual(p["offset"], 0.0, places=5)
        for got, want in zip(p["origin"], (0.0, 0.0, 0.0)):
            self.assertAlmostEqual(got, want, places=4)
        for e in p["extents"]:
            self.assertAlmostEqual(e, 3.03, places=3)  # 3.02 m and 1 cm of margin
        self.assertTrue(p["covered"], "the floor's reflected samples are the plane's")
        # Written as the engine reads it: kind planar, two extents, +Y the plane's normal.
        node = planar.planar_nodes([p])[0]
        out = edit.edited_document(doc, [], str(self.path.parent), str(self.path.parent), extra_nodes=[node])
        added = out["nodes"][-1]
        self.assertEqual(added["extensions"][PROBE_EXT]["kind"], "planar")
        self.assertEqual(len(added["extensions"][PROBE_EXT]["extents"]), 2)
        self.assertEqual(added["rotation"], [0.0, 0.0, 0.0, 1.0])
        self.assertIn(len(out["nodes"]) - 1, out["scenes"][0]["nodes"])
        # With that probe in the scene the plane is served: not proposed again.
        self.assertEqual(planar.flat_reflectors(self.geo, out, self.samples), [])


class Loop(Scene):
    """The greedy loop against a synthetic measurer: each candidate adds a fixed gain, scaled
    down at lower resolutions, so the right answer is known."""

    def run_loop(self, budget, max_cmos=3, tries=3):
        gains = {0: 3.0, 1: 2.0}
        factor = {128: 1.0, 64: 0.9, 32: 0.6}
        calls = []

        class FakeMeasurer:
            def __init__(self, *a, **k):
                self.count = 0
                self.planars = []

            def key(self, cmos, planars=None):
                return json.dumps([[list(c["pos"]), c["res"], c["order"]] for c in cmos])

            def measure(self, cmos, planars=None):
                self.count += 1
                calls.append(cmos)
                mean = 10.0 + sum(gains.get(c["rank"], 0.3) * factor[c["res"]] for c in cmos)
                return {"mean": mean, "per_view": {"main": mean}, "ms": 1.0 + len(cmos), "seconds": 0.0}

        real_m, real_p = loop.Measurer, sp.probe_capture
        loop.Measurer, sp.probe_capture = FakeMeasurer, lambda *a: None
        out = self.dir / f"loop{budget}.gltf"
        try:
            with contextlib.redirect_stdout(io.StringIO()) as log:
                code = sp.main(["--capture", "/bin/true", "--reference", "/bin/true", "--metrics", "/bin/true",
                                "place", "--scene", str(self.path), "--budget-db", str(budget), "--out", str(out),
                                "--max-cmos", str(max_cmos), "--tries", str(tries), "--move-tries", "0",
                                "--resolutions", "32,64,128", "--size", "160x90", "--grid", "32",
                                # one view: the budget alone decides here (ViewGuard tests the guard)
                                "--max-view-loss-db", "100"])
        finally:
            loop.Measurer, sp.probe_capture = real_m, real_p
        report = json.loads(out.with_name(out.stem + ".placement.json").read_text())
        return code, report, json.loads(out.read_text()), log.getvalue()

    def test_fewest_lowest_ordered(self):
        code, rep, doc, log = self.run_loop(14.0)
        self.assertEqual(code, 0, log)
        final = rep["final"]
        self.assertEqual(final["count"], 2)
        by_rank = {c["candidate"]: c for c in final["cmos"]}
        self.assertEqual(set(by_rank), {0, 1})
        # the smaller contributor is lowered first, as far as the budget allows; then the other stops
        self.assertEqual((by_rank[0]["resolution"], by_rank[1]["resolution"]), (128, 32))
        self.assertGreater(by_rank[0]["order"], by_rank[1]["order"], "the larger contribution is traced first")
        self.assertGreaterEqual(final["mean_psnr_db"], 14.0)
        nodes = [n for n in doc["nodes"] if PROBE_EXT in n.get("extensions", {})]
        self.assertEqual(sorted(n["extensions"][PROBE_EXT]["resolution"] for n in nodes), [32, 128])
        self.assertIn("placement: step 2/", log)
        self.assertIn("budget met", log)

    def test_baseline_meets_budget_adds_nothing(self):
        code, rep, doc, log = self.run_loop(9.0)
        self.assertEqual((code, rep["final"]["count"]), (0, 0), log)
        self.assertNotIn(PROBE_EXT, doc.get("extensionsUsed", []))

    def test_unreachable_budget_writes_best_and_fails(self):
        code, rep, doc, log = self.run_loop(30.0, max_cmos=2)
        self.assertEqual(code, 1, log)
        self.assertFalse(rep["met"])
        self.assertEqual(rep["final"]["count"], 2)
        self.assertAlmostEqual(rep["final"]["mean_psnr_db"], 15.0)
        self.assertIn("NOT met", log)


class ViewGuard(Scene):
    """DROP judged per view, not by the budget alone (cornell_mirrors, 2026-12-07): once the
    second CMO is placed, the scene without the first still meets the budget, while view `main`
    loses 1.5 dB."""

    def run_guard(self, *extra):
        def views(cmos):
            has0 = any(c["rank"] == 0 for c in cmos)
            other = any(c["rank"] != 0 for c in cmos)
            a, b = {(False, False): (10.0, 10.0), (True, False): (11.0, 10.5),
                    (False, True): (10.5, 13.5), (True, True): (12.0, 13.0)}[(has0, other)]
            return {"main": a, "second": b}  # the scene has one camera: the second view is the fake's

        class FakeMeasurer:
            def __init__(self, *a, **k):
                self.planars = []
                self.count = 0

            def key(self, cmos, planars=None):
                return json.dumps([[list(c["pos"]), c["res"], c["order"]] for c in cmos])

            def measure(self, cmos, planars=None):
                self.count += 1
                v = views(cmos)
                return {"mean": (v["main"] + v["second"]) / 2, "per_view": v, "ms": 1.0, "seconds": 0.0}

        real_m, real_p = loop.Measurer, sp.probe_capture
        loop.Measurer, sp.probe_capture = FakeMeasurer, lambda *a: None
        out = self.dir / "guard.gltf"
        try:
            with contextlib.redirect_stdout(io.StringIO()) as log:
                code = sp.main(["--capture", "/bin/true", "--reference", "/bin/true", "--metrics", "/bin/true",
                                "place", "--scene", str(self.path), "--budget-db", "11.5", "--out", str(out),
                                "--max-cmos", "2", "--tries", "1", "--move-tries", "0", "--views", "main",
                                "--resolutions", "32,64,128", "--size", "160x90", "--grid", "32", *extra])
        finally:
            loop.Measurer, sp.probe_capture = real_m, real_p
        return code, json.loads(out.with_name(out.stem + ".placement.json").read_text()), log.getvalue()

    def test_a_drop_that_costs_one_view_is_refused(self):
        code, rep, log = self.run_guard()
        self.assertEqual(code, 0, log)
        self.assertEqual(rep["final"]["count"], 2, log)
        self.assertEqual(rep["final"]["per_view_psnr_db"], {"main": 12.0, "second": 13.0})
        # Without the guard the mean alone decides: the first CMO is dropped (12.0 >= 11.5).
        code, rep, log = self.run_guard("--max-view-loss-db", "100")
        self.assertEqual((code, rep["final"]["count"]), (0, 1), log)


if __name__ == "__main__":
    unittest.main(verbosity=2)
