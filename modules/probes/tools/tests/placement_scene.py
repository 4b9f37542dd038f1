"""The placement tests' own scene: a closed box room (a colour per wall), a glossy floor and a
chrome sphere, one camera, no probe; an unknown vendor extension and extras that the tool must
keep. Written with the scene generator's glTF builder (tools/scenes) into a folder of the test's
choosing."""
import json
import os
import sys
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[4]
sys.path.insert(0, str(SOURCE / "tools"))
from scenes.document import Gltf  # noqa: E402
from scenes.mesh import MeshData, add_room_faces, lapped_room  # noqa: E402

UNKNOWN_EXT = "VENDOR_placement_test_keep"


def write_scene(folder, name="placement_room"):
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    g = Gltf(name, folder=str(folder))
    W, H, D, LAP = 3.0, 3.0, 3.0, 0.02
    walls = {"back": (0.7, 0.06, 0.05), "front": (0.8, 0.65, 0.06), "left": (0.08, 0.5, 0.1),
             "right": (0.06, 0.12, 0.7)}
    for side, rgb in walls.items():
        g.material("wall." + side, rgb, 0.0, 0.85)
    g.material("ceiling", (0.8, 0.8, 0.78), 0.0, 0.9)
    g.material("floor", (0.05, 0.05, 0.06), 0.0, 0.08)
    g.material("chrome", (0.95, 0.95, 0.95), 1.0, 0.0)
    g.material("panel", (0.0, 0.0, 0.0), 0.0, 1.0, emissive=(1.0, 0.95, 0.85), strength=5.0)
    add_room_faces(g, lapped_room(W, H, D, LAP), [(side, "wall." + side, "wall." + side)
                                                  for side in ("back", "front", "left", "right")]
                   + [("ceiling", "ceiling", "ceiling")])
    m = MeshData()
    m.quad((-W - LAP, 0.0, -D - LAP), (2 * W + 2 * LAP, 0, 0), (0, 0, 2 * D + 2 * LAP), 4, 4, facing=(0, 1, 0))
    g.object("floor", m, "floor")
    m = MeshData()
    m.quad((-0.8, H - 0.005, -0.5), (1.6, 0, 0), (0, 0, 1.0), facing=(0, -1, 0))
    g.object("panel", m, "panel")
    m = MeshData()
    m.uv_sphere(0.6, 48, 24)
    g.object("chrome_sphere", m, "chrome", translation=(0.0, 0.6, -0.6))
    g.light("lamp.a", "point", 14.0, (1.0, 0.9, 0.8), position=(-1.5, 2.6, 1.0))
    g.light("lamp.b", "point", 14.0, (1.0, 0.9, 0.8), position=(1.5, 2.6, -1.2))
    g.camera("main", (0.4, 1.5, 2.4), (0.0, 0.6, -0.6))
    env = os.path.relpath(SOURCE / "assets" / "env" / "interior.exr", folder)
    g.write({"environment": env, "exposure": 0.6})
    path = folder / (name + ".gltf")
    doc = json.loads(path.read_text())
    doc.setdefault("extensions", {})[UNKNOWN_EXT] = {"answer": 42, "nested": {"kept": [1, 2, 3]}}
    doc.setdefault("extensionsUsed", []).append(UNKNOWN_EXT)
    doc["extras"] = {"author": "placement test"}
    path.write_text(json.dumps(doc, indent=1) + "\n")
    return path


if __name__ == "__main__":
    print(write_scene(sys.argv[1]))
