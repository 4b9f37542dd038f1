#!/usr/bin/env python3
"""store.py's keys (tests/reference/README.md, "converged references"): a converged reference
stays fresh when only the scene's reflection probes change (the reference ignores them) and goes
stale when anything it renders changes. Exit 1 names the case."""
import copy, json, sys, tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import store

SCENE = store.SOURCE / "assets" / "scenes" / "closed_room.gltf"


def digest(doc, folder, name):
    path = Path(folder) / name
    path.write_text(json.dumps(doc, indent=1))
    return store.scene_digest(path).hexdigest()


def node(doc, name):
    return next(n for n in doc["nodes"] if n.get("name") == name)


def main():
    base = json.loads(SCENE.read_text())
    cases = []  # (what, edited document, should the key stay)

    d = copy.deepcopy(base)  # a CMO placed: appended to the nodes and the scene
    d["nodes"].append({"name": "cmo.9", "translation": [0, 1, 0], "extensions": {store.PROBE_EXT: {
        "kind": "cmo", "shape": "sphere", "extents": [1, 1, 1], "resolution": 128}}})
    d["scenes"][0]["nodes"].append(len(d["nodes"]) - 1)
    cases.append(("a CMO added", d, True))

    d = copy.deepcopy(base)  # the floor's planar probe removed (the nodes after it renumber)
    i = next(k for k, n in enumerate(d["nodes"]) if n.get("name") == "planar.floor")
    del d["nodes"][i]
    d["scenes"][0]["nodes"] = [k - (k > i) for k in d["scenes"][0]["nodes"] if k != i]
    cases.append(("the planar probe removed", d, True))

    d = copy.deepcopy(base)
    node(d, "reflection_probe.room")["translation"] = [0.5, 1.5, 0.0]
    cases.append(("the box probe moved", d, True))

    d = copy.deepcopy(base)
    d["materials"][0]["pbrMetallicRoughness"]["roughnessFactor"] = 0.5
    cases.append(("a material's roughness", d, False))

    d = copy.deepcopy(base)
    node(d, "main")["translation"] = [0.3, 1.8, 2.6]
    cases.append(("a camera moved", d, False))

    d = copy.deepcopy(base)
    i = next(k for k, n in enumerate(d["nodes"]) if n.get("name") == "pedestal")
    d["scenes"][0]["nodes"] = [k for k in d["scenes"][0]["nodes"] if k != i]
    cases.append(("an object taken out of the scene", d, False))

    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        want = digest(base, tmp, "closed_room.gltf")
        for what, doc, same in cases:
            got = digest(doc, tmp, "closed_room.gltf")
            ok = (got == want) == same
            print(f"{'ok  ' if ok else 'FAIL'} {what}: the key {'stays' if got == want else 'changes'}"
                  f" (it should {'stay' if same else 'change'})")
            failures += not ok
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
