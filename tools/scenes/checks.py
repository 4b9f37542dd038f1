"""What every written scene must pass (make_scenes.py --check): a valid glTF, meshes wound to
their normals, probes whose capture points stand in the open, cameras that see reflective
surfaces, and each scene's own promise (a sealed room keeps every ray inside, a plain export uses
no Speculum extension, the failure cases show what they stage)."""

import json
import math
import os

from speculum_py.enums import KIND, MODE, PROBE_EXT, REFLECT_EXT, SHAPE, UPDATE
from speculum_py.gltf import CheckError, load_document, read_accessor, require, world_matrices
from speculum_py.raycast import RayCaster
from speculum_py.vec import add, cross, dot, length, mat_dir, mat_point, mul, normalize, sub

from .catalog import PATH_DIR, PLAIN, SCENE_DIR, SEALED
from .numbers import r6v

__all__ = ["CheckError", "check_path", "check_scene", "finite"]


def finite(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def mirror(d, nrm):
    """The hit's normal turned towards the ray and the mirror direction of d about it."""
    nn = nrm if dot(nrm, d) < 0 else mul(nrm, -1.0)
    return nn, sub(d, mul(nn, 2.0 * dot(d, nn)))


def _check_json(name, doc):
    def walk(x, where):
        if isinstance(x, float):
            require(math.isfinite(x), "%s: non-finite number at %s" % (name, where))
        elif isinstance(x, dict):
            for k, v in x.items():
                walk(v, where + "." + k)
        elif isinstance(x, list):
            for i, v in enumerate(x):
                walk(v, "%s[%d]" % (where, i))
    walk(doc, "$")
    require(doc["asset"]["version"] == "2.0", "asset.version")


def _check_buffers(name, doc, buffers):
    for b, data in zip(doc["buffers"], buffers):
        require(len(data) == b["byteLength"], "%s: buffer length %d != %d" % (name, len(data), b["byteLength"]))
        require(len(data) < 2 * 1024 * 1024, "%s: .bin over 2 MB" % name)


def _check_materials(mats):
    for m in mats:
        ext = m.get("extensions", {}).get(REFLECT_EXT)
        if ext is not None:
            require(ext.get("mode", MODE.screen_space) in MODE.names, "bad mode in " + m["name"])
            for k in ("roughnessScale", "roughnessOverride", "maxScreenSpaceRoughness"):
                require(k not in ext or finite(ext[k]), "bad %s in %s" % (k, m["name"]))
            for k in ("traceCmos", "mirrorForSelfReflections"):
                require(k not in ext or isinstance(ext[k], bool), "bad %s in %s" % (k, m["name"]))


def _primitive_triangles(doc, buffers, mesh, prim):
    """The primitive's local triangles, after checking its accessors and winding."""
    pos = read_accessor(doc, buffers, prim["attributes"]["POSITION"])
    nrm = read_accessor(doc, buffers, prim["attributes"]["NORMAL"])
    uv = read_accessor(doc, buffers, prim["attributes"]["TEXCOORD_0"])
    idx = read_accessor(doc, buffers, prim["indices"])
    require(len(pos) == len(nrm) == len(uv), "%s: attribute counts differ" % mesh["name"])
    require(len(idx) % 3 == 0 and len(idx) > 0, "%s: index count" % mesh["name"])
    require(max(idx) < len(pos), "%s: index out of range" % mesh["name"])
    acc = doc["accessors"][prim["attributes"]["POSITION"]]
    for k in range(3):
        require(acc["min"][k] == min(p[k] for p in pos) and acc["max"][k] == max(p[k] for p in pos),
                "%s: POSITION min/max wrong" % mesh["name"])
    for n in nrm:
        require(abs(length(n) - 1.0) < 1e-3, "%s: normal not unit" % mesh["name"])
    bad = 0
    tris = []
    for t in range(0, len(idx), 3):
        a, b, c = pos[idx[t]], pos[idx[t + 1]], pos[idx[t + 2]]
        gn = cross(sub(b, a), sub(c, a))
        vn = add(add(nrm[idx[t]], nrm[idx[t + 1]]), nrm[idx[t + 2]])
        if dot(gn, vn) <= 0.0:
            bad += 1
        tris.append((a, b, c))
    require(bad <= len(idx) // 3 // 1000, "%s: %d triangles wound against their normals" % (mesh["name"], bad))
    return tris


def _check_planar_ext(n, ext):
    """A planar probe (issue 24): two positive extents, an optional image height in [16, 4096]."""
    require(len(ext["extents"]) == 2 and all(finite(c) and c > 0 for c in ext["extents"]),
            "planar probe %s: extents" % n["name"])
    res = ext.get("resolution", 16)
    require(isinstance(res, int) and 16 <= res <= 4096, "planar probe %s: resolution %r" % (n["name"], res))


def _check_probe_ext(n, ext):
    require(ext["kind"] in KIND.names and ext["shape"] in SHAPE.names and ext["update"] in UPDATE.names,
            "bad probe enum on " + n["name"])
    require(len(ext["extents"]) == 3 and all(finite(c) and c > 0 for c in ext["extents"]), "probe extents")
    res = ext["resolution"]
    require(isinstance(res, int) and 8 <= res <= 4096 and res & (res - 1) == 0,
            "probe %s: resolution %r is not a power of two in [8, 4096]" % (n["name"], res))
    require(finite(ext["blendDistance"]) and ext["blendDistance"] >= 0, "probe %s: blendDistance" % n["name"])
    # the extents are in the node's space; ours are unrotated and unscaled, so the box is
    # world-aligned and the checks below can work in world space
    require("rotation" not in n and "scale" not in n and "matrix" not in n,
            "probe %s: rotated or scaled" % n["name"])


class SceneCheck:
    """One scene's checks over its world-space triangles, shared by the probe, camera and
    per-scene checks."""

    def __init__(self, name):
        self.name = name
        self.path = os.path.join(SCENE_DIR, name + ".gltf")
        self.doc, self.buffers, _ = load_document(self.path)
        _check_json(name, self.doc)
        _check_buffers(name, self.doc, self.buffers)
        self.mats = self.doc["materials"]
        _check_materials(self.mats)
        self.sealed = name in SEALED
        self._gather()

    def _gather(self):
        """World transforms, the probes' nodes, the scene's bounds and its ray caster."""
        doc = self.doc
        mesh_tris = {mi: [(_primitive_triangles(doc, self.buffers, mesh, prim), prim.get("material", -1))
                          for prim in mesh["primitives"]]
                     for mi, mesh in enumerate(doc["meshes"])}
        self.nodes = doc["nodes"]
        self.world = world_matrices(doc)
        lo, hi = [1e30] * 3, [-1e30] * 3
        self.ntris = 0
        self.probes = []
        cast_tris = []
        for i, n in enumerate(self.nodes):
            ext = n.get("extensions", {}).get(PROBE_EXT)
            if ext is not None and ext.get("kind") == KIND.planar:
                _check_planar_ext(n, ext)  # a plane, not a capture point: no probe checks below
            elif ext is not None:
                _check_probe_ext(n, ext)
                self.probes.append((n["name"], i, ext))
            if "mesh" not in n:
                continue
            require(self.world[i] is not None, "node %s not in scene" % n["name"])
            for tris, mat in mesh_tris[n["mesh"]]:
                wt = [tuple(mat_point(self.world[i], p) for p in t) for t in tris]
                for t in wt:
                    for p in t:
                        for k in range(3):
                            lo[k] = min(lo[k], p[k])
                            hi[k] = max(hi[k], p[k])
                    tri = RayCaster.triangle(t[0], t[1], t[2], mat)
                    if tri is not None:
                        cast_tris.append(tri)
                self.ntris += len(wt)
        self.lo, self.hi = lo, hi
        self.caster = RayCaster(cast_tris)

    def inside(self, p, pad=0.01):
        return all(self.lo[k] - pad <= p[k] <= self.hi[k] + pad for k in range(3))

    def cast(self, o, d):
        """(t, material, unit normal) of the closest hit, or None."""
        h = self.caster.cast(o, d)
        return None if h is None else (h[0], h[1][4], h[1][3])

    def check_probes(self):
        """A probe's capture point (its centre) must be in the open: a back face first along any
        axis means it sits inside a closed object and would capture that object's inside."""
        report = []
        for pn, pi, ext in self.probes:
            c = (self.world[pi][12], self.world[pi][13], self.world[pi][14])
            require(self.inside(c), "probe %s: centre outside the scene" % pn)
            nearest = 1e30
            for k in range(3):
                for sgn in (1.0, -1.0):
                    d = tuple(sgn if j == k else 0.0 for j in range(3))
                    h = self.cast(c, d)
                    if h is None:
                        continue
                    require(dot(h[2], d) < 0.0, "probe %s: capture point inside an object" % pn)
                    nearest = min(nearest, h[0])
                    # In a sealed room the box proxy is the interior: along each axis the first hit
                    # is the room's face at the box's face (1 cm: the 5 mm ceiling panel).
                    if self.sealed and ext["shape"] == SHAPE.box:
                        require(abs(h[0] - ext["extents"][k]) <= 0.01,
                                "probe %s: proxy face %s%s at %.3f m, the room's at %.3f m" % (
                                    pn, "+" if sgn > 0 else "-", "xyz"[k], ext["extents"][k], h[0]))
            if self.sealed:
                self._check_sealed_probe(pn, c, ext)
            report.append((pn, c, ext, nearest))
        return report

    def _check_sealed_probe(self, pn, c, ext):
        # every direction from the capture point hits the room inside the proxy box
        for j in range(16):
            for i in range(32):
                th, ph = (j + 0.5) / 16 * math.pi, (i + 0.5) / 32 * 2.0 * math.pi
                d = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
                h = self.cast(c, d)
                require(h is not None, "probe %s: the capture sees the sky along %s" % (pn, r6v(d)))
                q = add(c, mul(d, h[0]))
                require(all(abs(q[k] - c[k]) <= ext["extents"][k] + 0.01 for k in range(3)),
                        "probe %s: a surface outside the proxy box at %s" % (pn, r6v(q)))

    def reflective(self, mat):
        if mat < 0:
            return False
        pbr = self.mats[mat].get("pbrMetallicRoughness", {})
        return pbr.get("metallicFactor", 1.0) >= 0.5 and pbr.get("roughnessFactor", 1.0) <= 0.6

    def emissive(self, mat):
        return mat >= 0 and any(c > 0 for c in self.mats[mat].get("emissiveFactor", [0, 0, 0]))

    def check_cameras(self):
        doc, name = self.doc, self.name
        cams = [(i, n) for i, n in enumerate(self.nodes) if "camera" in n]
        require(len(cams) >= 2, "%s: fewer than two cameras" % name)
        require(cams[0][1]["name"] == "main", "%s: first camera is not 'main'" % name)
        env = doc["scenes"][0].get("extras", {}).get("environment")
        require(env and os.path.isfile(os.path.normpath(os.path.join(SCENE_DIR, env))),
                "%s: environment missing" % name)
        return {n["name"]: self._check_camera(doc["cameras"][n["camera"]], n, self.world[ci]) for ci, n in cams}

    def _check_camera(self, cam, n, m):
        require(cam["type"] == "perspective" and 0.9 <= cam["perspective"]["yfov"] <= 1.0, "camera fov")
        require(cam["perspective"]["znear"] == 0.05 and "zfar" not in cam["perspective"], "camera near/far")
        eye = (m[12], m[13], m[14])
        fwd = normalize(mat_dir(m, (0, 0, -1)))
        right = normalize(mat_dir(m, (1, 0, 0)))
        up = normalize(mat_dir(m, (0, 1, 0)))
        require(up[1] > 0.0, "camera %s upside down" % n["name"])
        target = n.get("extras", {}).get("target")
        require(target is not None and self.inside(target), "camera %s: target outside the scene" % n["name"])
        require(abs(dot(normalize(sub(target, eye)), fwd) - 1.0) < 1e-5, "camera %s: rotation != look-at" % n["name"])
        hit = self.cast(eye, fwd)
        require(hit is not None and self.inside(add(eye, mul(fwd, hit[0]))), "camera %s looks at nothing" % n["name"])
        W, H = 48, 27
        stats = self._camera_stats(eye, fwd, right, up, math.tan(cam["perspective"]["yfov"] / 2.0), W, H)
        require(stats["backfaces"] <= W * H // 100, "camera %s sees %d back faces" % (n["name"], stats["backfaces"]))
        require(not self.sealed or stats["escapes"] == 0,
                "camera %s: %d rays or their mirror bounces reach the sky" % (n["name"], stats["escapes"]))
        frac = stats["reflective"] / float(W * H)
        require(frac >= 0.05, "camera %s sees little reflective surface (%.1f%%)" % (n["name"], 100 * frac))
        stats["reflective_fraction"] = frac
        return stats

    def _camera_stats(self, eye, fwd, right, up, th, W, H):
        """What a W x H grid of rays from the camera meets, and what the reflective hits mirror."""
        tw = th * 16.0 / 9.0
        stats = {"backfaces": 0, "reflective": 0, "reflect_hits_emissive": 0, "escapes": 0, "direct": {},
                 "reflected": {}}
        for py in range(H):
            for px in range(W):
                sx = ((px + 0.5) / W * 2.0 - 1.0) * tw
                sy = (1.0 - (py + 0.5) / H * 2.0) * th
                d = normalize(add(fwd, add(mul(right, sx), mul(up, sy))))
                h = self.cast(eye, d)
                if h is None:
                    stats["escapes"] += 1
                    continue
                stats["direct"][h[1]] = stats["direct"].get(h[1], 0) + 1
                p = add(eye, mul(d, h[0]))
                nn, r = mirror(d, h[2])
                if self.sealed:  # the mirror bounce of every surface must stay in the room too
                    if self.cast(add(p, mul(nn, 1e-4)), r) is None:
                        stats["escapes"] += 1
                if dot(h[2], d) > 0.0:
                    stats["backfaces"] += 1
                if self.reflective(h[1]):
                    stats["reflective"] += 1
                    h2 = self.cast(add(p, mul(nn, 1e-4)), r)
                    if h2 is not None:
                        stats["reflected"][h2[1]] = stats["reflected"].get(h2[1], 0) + 1
                        if self.emissive(h2[1]):
                            stats["reflect_hits_emissive"] += 1
        return stats

    def check_lights_and_looks(self):
        name, mats = self.name, self.mats
        lights = self.doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
        if self.sealed:
            require(self.probes, "%s: sealed room without a probe" % name)
            require(all(lt["type"] != "directional" for lt in lights), "%s: a sun in a sealed room" % name)
        if name in PLAIN:
            # what a plain exporter writes: no Speculum extension anywhere, by any name
            with open(self.path, "r", encoding="utf-8") as f:
                require("SPECULUM_" not in f.read(), "%s: uses a Speculum extension" % name)
            require(any(lt["type"] == "directional" for lt in lights), "%s: no sun" % name)

            def has(metal, r0, r1):
                return any(m["pbrMetallicRoughness"]["metallicFactor"] == metal
                           and r0 <= m["pbrMetallicRoughness"]["roughnessFactor"] <= r1 for m in mats)
            require(has(1.0, 0.0, 0.0), "%s: no chrome (metallic 1, roughness 0)" % name)
            require(has(1.0, 0.15, 0.4), "%s: no glossy metal (roughness 0.15-0.4)" % name)
            require(has(0.0, 0.05, 0.3), "%s: no glossy dielectric (roughness 0.05-0.3)" % name)

    def check_failure_cases(self, cameras):
        """Each staged failure is there: what main must not see directly, it sees mirrored."""
        main = cameras["main"]
        matid = {m["name"]: i for i, m in enumerate(self.mats)}
        hid = matid["hidden_box.cyan"]
        require(main["direct"].get(hid, 0) == 0, "hidden box is directly visible from main")
        require(main["reflected"].get(hid, 0) > 0, "hidden box is not seen in the floor from main")
        for g in ("glow.magenta", "glow.cyan", "glow.warm", "glow.overhead"):
            require(main["direct"].get(matid[g], 0) == 0, "%s directly visible from main" % g)
        require(sum(main["reflected"].get(matid[g], 0) for g in ("glow.magenta", "glow.cyan", "glow.warm")) > 0,
                "emissive objects behind the camera are not reflected")
        require(main["reflected"].get(matid["glow.overhead"], 0) > 0, "overhead glow not reflected by the floor")

    def print_report(self, probe_report, cameras):
        lo, hi = self.lo, self.hi
        print("%s: %d triangles, bin %d bytes, bounds %s..%s" % (self.name, self.ntris, len(self.buffers[0]),
              [round(c, 2) for c in lo], [round(c, 2) for c in hi]))
        for pn, c, ext, nearest in probe_report:
            print("  probe  %-24s %s at %s, extents %s, blend %g, %d^2, order %d; first hit along the axes"
                  " %.2f m" % (pn, ext["shape"], r6v(c), ext["extents"], ext["blendDistance"], ext["resolution"],
                               ext["order"], nearest))
        for cn, st in cameras.items():
            refl = sorted(((c, self.mats[k]["name"]) for k, c in st["reflected"].items()), reverse=True)[:4]
            print("  camera %-16s reflective %4.1f%%  reflections show: %s" % (
                cn, 100 * st["reflective_fraction"], ", ".join("%s %d" % (nm, c) for c, nm in refl)))


def check_scene(name, verbose=True):
    """Every check of one written scene; its world bounds, which its camera path must keep to."""
    sc = SceneCheck(name)
    probe_report = sc.check_probes()
    cameras = sc.check_cameras()
    sc.check_lights_and_looks()
    if name == "failure_cases":
        sc.check_failure_cases(cameras)
    if verbose:
        sc.print_report(probe_report, cameras)
    return sc.lo, sc.hi


def check_path(name, lo, hi):
    with open(os.path.join(PATH_DIR, name + ".json"), "r", encoding="utf-8") as f:
        p = json.load(f)
    require(p["scene"] == name and p["frames"] >= 2 and finite(p["fov_deg"]), "path header " + name)
    require(len(p["keys"]) >= 2, "path keys " + name)
    for k in p["keys"]:
        for what in ("eye", "target"):
            v = k[what]
            require(len(v) == 3 and all(finite(c) for c in v), "path %s %s" % (name, what))
            pad = 0.01 if what == "target" else 5.0  # eyes may stand in front of an open box
            require(all(lo[i] - pad <= v[i] <= hi[i] + pad for i in range(3)), "path %s %s outside scene" % (name, what))
        require(length(sub(k["target"], k["eye"])) > 0.1, "path %s: eye == target" % name)
