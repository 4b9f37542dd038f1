"""The glTF document builder (one .gltf, one .bin, shared accessors) and the camera-path
writer: the file layout every generated scene shares."""

import array
import json
import os
import sys

from speculum_py.enums import KIND, PROBE_EXT, REFLECT_EXT, SHAPE, UPDATE
from speculum_py.vec import quat_look_at

from .catalog import PATH_DIR, PLACEMENT_DIR, SCENE_DIR
from .numbers import f32, r6, r6v


class Gltf:
    def __init__(self, name, folder=SCENE_DIR):
        self.name = name
        self.folder = folder  # the placement tests write their own room elsewhere
        self.bin = bytearray()
        self.doc = {
            "asset": {"version": "2.0", "generator": "speculum tools/make_scenes.py"},
            "scene": 0,
            "scenes": [{"name": name, "nodes": []}],
            "nodes": [], "meshes": [], "materials": [], "cameras": [],
            "accessors": [], "bufferViews": [],
            "buffers": [{"uri": name + ".bin", "byteLength": 0}],
        }
        self.lights = []
        self.used = set()
        self.material_ids = {}
        self.geometry = {}  # key -> attributes dict + index accessor, for shared accessors

    # binary data
    def _view(self, data, target):
        while len(self.bin) % 4:
            self.bin.append(0)
        off = len(self.bin)
        self.bin.extend(data)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": off, "byteLength": len(data), "target": target})
        return len(self.doc["bufferViews"]) - 1

    def _accessor(self, values, comps, ctype, typ, target, minmax=False):
        if ctype == 5126:
            arr = array.array("f", [c for v in values for c in v])
        else:
            arr = array.array("I", values)
        if sys.byteorder != "little":
            arr.byteswap()
        view = self._view(arr.tobytes(), target)
        acc = {"bufferView": view, "componentType": ctype, "count": len(values), "type": typ}
        if minmax:
            cols = [[f32(v[k]) for v in values] for k in range(comps)]
            acc["min"] = [min(c) for c in cols]
            acc["max"] = [max(c) for c in cols]
        self.doc["accessors"].append(acc)
        return len(self.doc["accessors"]) - 1

    def geometry_of(self, key, mesh):
        if key not in self.geometry:
            attrs = {
                "POSITION": self._accessor(mesh.pos, 3, 5126, "VEC3", 34962, minmax=True),
                "NORMAL": self._accessor(mesh.nrm, 3, 5126, "VEC3", 34962),
                "TEXCOORD_0": self._accessor(mesh.uv, 2, 5126, "VEC2", 34962),
            }
            ind = self._accessor(mesh.idx, 1, 5125, "SCALAR", 34963)
            self.geometry[key] = (attrs, ind)
        return self.geometry[key]

    # objects
    def material(self, name, base=(0.8, 0.8, 0.8), metallic=0.0, roughness=0.9, emissive=None,
                 strength=None, reflections=None, double_sided=False):
        m = {"name": name, "pbrMetallicRoughness": {
            "baseColorFactor": [r6(c) for c in base] + [1.0],
            "metallicFactor": r6(metallic), "roughnessFactor": r6(roughness)}}
        if emissive is not None:
            m["emissiveFactor"] = r6v(emissive)
            if strength is not None and strength != 1.0:
                m.setdefault("extensions", {})["KHR_materials_emissive_strength"] = {"emissiveStrength": r6(strength)}
                self.used.add("KHR_materials_emissive_strength")
        if reflections is not None:
            m.setdefault("extensions", {})[REFLECT_EXT] = reflections
            self.used.add(REFLECT_EXT)
        if double_sided:
            m["doubleSided"] = True
        self.doc["materials"].append(m)
        self.material_ids[name] = len(self.doc["materials"]) - 1
        return self.material_ids[name]

    def mesh(self, name, mesh, material, geometry_key=None):
        attrs, ind = self.geometry_of(geometry_key or name, mesh)
        mat = material if isinstance(material, int) else self.material_ids[material]
        self.doc["meshes"].append({"name": name, "primitives": [
            {"attributes": dict(attrs), "indices": ind, "material": mat, "mode": 4}]})
        return len(self.doc["meshes"]) - 1

    def node(self, name, translation=None, rotation=None, scale=None, root=True, **extra):
        n = {"name": name}
        if translation is not None and any(abs(c) > 0 for c in translation):
            n["translation"] = r6v(translation)
        if rotation is not None and abs(rotation[3]) < 1.0 - 1e-12:
            n["rotation"] = [round(c, 9) for c in rotation]
        if scale is not None and any(abs(c - 1.0) > 0 for c in scale):
            n["scale"] = r6v(scale)
        n.update(extra)
        self.doc["nodes"].append(n)
        idx = len(self.doc["nodes"]) - 1
        if root:
            self.doc["scenes"][0]["nodes"].append(idx)
        return idx

    def object(self, name, mesh, material, translation=None, rotation=None, geometry_key=None):
        m = self.mesh(name, mesh, material, geometry_key)
        return self.node(name, translation, rotation, mesh=m)

    def camera(self, name, eye, target, yfov=0.95):
        self.doc["cameras"].append({"name": name, "type": "perspective",
                                    "perspective": {"yfov": yfov, "znear": 0.05}})
        return self.node(name, eye, quat_look_at(eye, target), camera=len(self.doc["cameras"]) - 1,
                         extras={"target": r6v(target)})

    def light(self, name, kind, intensity, color=(1.0, 1.0, 1.0), position=None, direction=None):
        self.lights.append({"name": name, "type": kind, "color": r6v(color), "intensity": r6(intensity)})
        self.used.add("KHR_lights_punctual")
        rot = None
        if direction is not None:
            rot = quat_look_at((0.0, 0.0, 0.0), direction)
        return self.node(name, position, rot, extensions={"KHR_lights_punctual": {"light": len(self.lights) - 1}})

    def probe(self, name, center, rotation=None, **fields):
        self.used.add(PROBE_EXT)
        return self.node(name, center, rotation, extensions={PROBE_EXT: fields})

    def box_probe(self, name, center, extents, blend, resolution, kind=KIND.local_cubemap, order=0):
        """The probe every scene places: an axis-aligned box captured once."""
        return self.probe(name, center, kind=kind, shape=SHAPE.box, extents=extents, blendDistance=blend,
                          resolution=resolution, update=UPDATE.once, order=order)

    def write(self, extras):
        d = self.doc
        d["scenes"][0]["extras"] = extras
        if self.lights:
            d["extensions"] = {"KHR_lights_punctual": {"lights": self.lights}}
        if self.used:
            d["extensionsUsed"] = sorted(self.used)
        while len(self.bin) % 4:
            self.bin.append(0)
        d["buffers"][0]["byteLength"] = len(self.bin)
        order = ["asset", "extensionsUsed", "extensions", "scene", "scenes", "nodes", "cameras", "meshes",
                 "materials", "accessors", "bufferViews", "buffers"]
        out = {k: d[k] for k in order if k in d}
        os.makedirs(self.folder, exist_ok=True)
        with open(os.path.join(self.folder, self.name + ".gltf"), "w", encoding="utf-8", newline="\n") as f:
            json.dump(out, f, indent=1, sort_keys=False)
            f.write("\n")
        with open(os.path.join(self.folder, self.name + ".bin"), "wb") as f:
            f.write(bytes(self.bin))


def add_placed_cmos(g):
    """The CMOs `speculum-probes place` proposed for this scene (assets/placement/NAME.placement.json,
    its report, committed beside its markdown), as nodes: the generator writes what the tool
    measured, so a regenerated scene keeps them."""
    path = os.path.join(PLACEMENT_DIR, g.name + ".placement.json")
    if not os.path.isfile(path):
        return
    with open(path, "r", encoding="utf-8") as f:
        report = json.load(f)
    for i, c in enumerate(report["final"]["cmos"]):
        g.box_probe("cmo.placed%d" % i, tuple(c["pos"]), [0.25, 0.25, 0.25], 0.0, c["resolution"], kind=KIND.cmo,
                    order=c["order"])


def write_path(name, keys, frames=24, fov_deg=55):
    os.makedirs(PATH_DIR, exist_ok=True)
    doc = {"scene": name, "frames": frames, "fov_deg": fov_deg,
           "keys": [{"eye": r6v(e), "target": r6v(t)} for e, t in keys]}
    with open(os.path.join(PATH_DIR, name + ".json"), "w", encoding="utf-8", newline="\n") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
