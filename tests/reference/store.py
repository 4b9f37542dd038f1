#!/usr/bin/env python3
"""The converged references kept in the repository (assets/references; README.md here,
"converged references").

    store.py check                                   which entries are fresh, stale or missing (exit 1 if any is not fresh)
    store.py regenerate --reference BIN [--only NAME]... [--force]   render the stale ones, with progress

An entry of assets/references/manifest.json is a view (scene, camera, size, bounces) rendered
with the manifest's settings into NAME = SCENE.CAMERA.SIZE.bBOUNCES/. Its key hashes everything
that changes the image: the scene's files (its probes left out: the reference ignores them),
the camera, the size, the bounces, the settings and
the estimator's version (kEstimatorVersion in reference.hpp; the binary itself is not hashed, it
differs from one compiler to the next). reference.json in the entry records the key it was
rendered for; an entry whose recorded key differs from today's is stale. The bench and the
accuracy tests read the entries through lookup() and stop with this file's regenerate command
when one is stale: a converged render takes minutes, never a test's side effect.
"""
import argparse
import hashlib
import json
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[2]
STORE = SOURCE / "assets" / "references"
MANIFEST = STORE / "manifest.json"
AOVS = "reflection,reflective,roughness,stderror,samples"
REGENERATE = "python3 tests/reference/store.py regenerate --reference build/tests/reference/speculum-reference"


def scene_inputs(gltf):
    """The scene file and every file it names (buffers, images, the environment)."""
    files = [gltf]
    try:
        doc = json.loads(gltf.read_text()) if gltf.is_file() else {}
    except (OSError, ValueError, RecursionError):
        return files  # speculum-capture and speculum-reference report what is wrong with it
    try:
        for key in ("buffers", "images"):
            for item in doc.get(key, []):
                uri = item.get("uri", "")
                if uri and not uri.startswith("data:"):
                    files.append(gltf.parent / uri)
        for scene in doc.get("scenes", []):
            env = scene.get("extras", {}).get("environment")
            if isinstance(env, str):
                files.append(gltf.parent / env)
    except (AttributeError, TypeError):
        pass  # a malformed document: the tools name the problem
    return files


def file_hash(path, cache={}):
    if path not in cache:
        # Only regular files are read (/dev/zero would never end); the tools report the others.
        p = Path(path)
        cache[path] = hashlib.sha256(p.read_bytes()).hexdigest() if p.is_file() else "not-a-file"
    return cache[path]


def estimator_version():
    text = (SOURCE / "tests" / "reference" / "reference.hpp").read_text()
    m = re.search(r"constexpr int kEstimatorVersion = (\d+);", text)
    if not m:
        raise SystemExit("store.py: tests/reference/reference.hpp has no kEstimatorVersion")
    return int(m.group(1))


def manifest():
    return json.loads(MANIFEST.read_text())


def entry_name(e):
    return f"{e['scene']}.{view_label(e)}.{e['size']}.b{e['bounces']}"


def view_label(e):
    """A named camera, or a camera path (assets/paths/NAME.json: NAME_path), as the bench names views."""
    return e["camera"] if "camera" in e else Path(e["path"]).stem + "_path"


def settings_for(doc, e):
    """The manifest's settings for a still view; a camera path's entries take path_settings (one
    render a frame: cheaper, with the reason in the manifest). An entry's own "settings" override
    single values (a view whose rough band needs a larger budget to agree at 40 dB)."""
    return {**(doc["path_settings"] if "path" in e else doc["settings"]), **e.get("settings", {})}


_generated = {}


def scene_file(e):
    """assets/scenes/SCENE.gltf, or the scene its generator writes (once a process)."""
    if "generator" not in e:
        return SOURCE / "assets" / "scenes" / f"{e['scene']}.gltf"
    if e["generator"] not in _generated:
        out = Path(tempfile.mkdtemp(prefix="speculum-store-"))
        subprocess.run([sys.executable, str(SOURCE / e["generator"]), str(out)], check=True,
                       stdout=subprocess.DEVNULL)
        _generated[e["generator"]] = out
    return _generated[e["generator"]] / f"{e['scene']}.gltf"


PROBE_EXT = "SPECULUM_reflection_probe"


def without_probes(gltf):
    """The scene document's bytes with its reflection probes taken out (None: hash the file's own
    bytes). The reference traces the scene and ignores its probes (they are the approximation
    being measured), so a probe placed, moved or removed leaves every converged reference fresh:
    a scene "with its placed probes" (issue 24) is measured against the same images. Probe nodes
    are dropped and the node indices of scenes[].nodes and nodes[].children renumbered; anything
    else changed (a material, a camera, a mesh) changes the digest. A document with skins or
    animations (other node indices) is hashed as it is."""
    try:
        doc = json.loads(gltf.read_text())
    except (OSError, ValueError, RecursionError):
        return None
    if not isinstance(doc, dict) or not isinstance(doc.get("nodes"), list) or "skins" in doc or "animations" in doc:
        return None
    def probe(n):
        return isinstance(n, dict) and isinstance(n.get("extensions"), dict) and PROBE_EXT in n["extensions"]
    if not any(probe(n) for n in doc["nodes"]):
        return None
    renumber, kept = {}, []
    for i, n in enumerate(doc["nodes"]):
        if not probe(n):
            renumber[i] = len(kept)
            kept.append(n)
    def remap(refs):
        return [renumber[r] for r in refs if r in renumber] if isinstance(refs, list) else refs
    try:
        for n in kept:
            if isinstance(n, dict) and "children" in n:
                n["children"] = remap(n["children"])
        for sc in doc.get("scenes", []):
            if isinstance(sc, dict) and "nodes" in sc:
                sc["nodes"] = remap(sc["nodes"])
    except TypeError:  # unhashable indices: malformed, the tools report it
        return None
    doc["nodes"] = kept
    for k in ("extensionsUsed", "extensionsRequired"):
        if isinstance(doc.get(k), list):
            doc[k] = [x for x in doc[k] if x != PROBE_EXT]
    return json.dumps(doc, sort_keys=True, separators=(",", ":")).encode()


def scene_digest(gltf):
    """A sha256 that has taken in the scene's files (the bench's keys start from it too): the
    scene document without its probes (without_probes), the files it names byte for byte."""
    h = hashlib.sha256()
    for f in scene_inputs(gltf):
        body = without_probes(f) if f == gltf else None
        h.update(f.name.encode() + (hashlib.sha256(body).hexdigest() if body is not None else file_hash(f)).encode())
    return h


def key(e, settings):
    h = scene_digest(scene_file(e))
    camera = e["camera"] if "camera" in e else file_hash(SOURCE / e["path"])
    h.update(json.dumps([camera, e["size"], e["bounces"], settings, estimator_version()],
                        sort_keys=True).encode())
    return h.hexdigest()[:24]


def status(e, settings):
    """('fresh' | 'stale' | 'missing', folder)."""
    folder = STORE / entry_name(e)
    info = folder / "reference.json"
    if not info.is_file():
        return "missing", folder
    recorded = json.loads(info.read_text()).get("store_key")
    return ("fresh" if recorded == key(e, settings) else "stale"), folder


# How lookup's `why` starts when the store has no entry for the view at all (not a stale one).
MISSING = "no converged reference"


def lookup(scene, camera, size, bounces, path=None):
    """(folder, why): the fresh entry for this view (a camera, or with path= a camera path file
    relative to the source tree) at `size`, or at a size a whole k times smaller (960x540 ->
    320x180, k = 3; the bench then scores at the reference's pixel centres, speculum-metrics
    --at-reference-pixels, and reads k from the entry's reference.json); or None and why not."""
    doc = manifest()
    w, h = (int(v) for v in size.lower().split("x"))
    label = view_label({"camera": camera} if path is None else {"path": path})
    def factor(e):  # k, or 0 when the entry's size is no whole fraction of `size`
        ew, eh = (int(v) for v in e["size"].split("x"))
        k = w // ew
        return k if k * ew == w and k * eh == h else 0
    matches = [e for e in doc["entries"] if (e["scene"], view_label(e), e["bounces"]) == (scene, label, bounces)
               and factor(e)]
    for e in sorted(matches, key=factor)[:1]:  # the largest entry that fits: k = 1 when there is one
        state, folder = status(e, settings_for(doc, e))
        if state == "fresh":
            return folder, None
        return None, f"the converged reference {entry_name(e)} is {state}; regenerate it: {REGENERATE} --only {entry_name(e)}"
    return None, (f"{MISSING} for {scene}.{label} at {size} or a whole fraction of it "
                  f"with {bounces} bounces: add it to {MANIFEST.relative_to(SOURCE)} and run {REGENERATE}")


def max_reference_error(folder):
    """The standard-error cut an entry's seed agreement was measured at (reference.json's
    max_reference_error; None: speculum-metrics' default, 0.01). An entry may set a tighter one
    in its manifest settings when its rough band needs it to agree at 40 dB."""
    info = json.loads((folder / "reference.json").read_text())
    if "max_reference_error" in info:
        return info["max_reference_error"]
    frames = info.get("frames") or [{}]
    return frames[0].get("seed_agreement", {}).get("max_reference_error")


def ref_error_args(folder, aov=False):
    """speculum-metrics' flags that leave a converged entry's unconverged pixels unscored, at the
    cut its seeds were compared at, so that a score and its reference_agreement_db count the
    same pixels; [] for a folder without a stderror AOV. aov=True: the flicker's per-frame form."""
    if not (folder / "stderror.0000.exr").is_file():
        return []
    cut = max_reference_error(folder)
    flags = ["--ref-error-aov", "stderror"] if aov else ["--ref-error", str(folder / "stderror.0000.exr")]
    return flags + (["--max-ref-error", f"{cut:.6g}"] if cut else [])


def render(binary, e, settings, folder, scene=None):
    """Renders entry e (or the same view of `scene`) with the store's settings into folder."""
    s = settings
    view = ["--camera", e["camera"]] if "camera" in e else ["--path", str(SOURCE / e["path"])]
    cmd = [binary, "--scene", str(scene or scene_file(e)), *view, "--size", e["size"],
           "--bounces", str(e["bounces"]), "--spp", str(s["spp"]), "--target-error", str(s["target_error"]),
           "--min-batches", str(s["min_batches"]), "--max-spp", str(s["max_spp"]),
           "--rough-max-spp", str(s["rough_max_spp"]), "--seed", str(s["seed"]), "--seeds", str(s["seeds"]),
           "--aov", AOVS, "--out", str(folder)]
    if "max_reference_error" in s:  # only where an entry sets it: the other entries' keys stay as they are
        cmd += ["--max-reference-error", str(s["max_reference_error"])]
    # stderr passes through: the reference draws its progress bar there on a terminal.
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def regenerate(binary, only, force):
    doc = manifest()
    todo = [e for e in doc["entries"] if (not only or entry_name(e) in only)
            and (force or status(e, settings_for(doc, e))[0] != "fresh")]
    unknown = set(only or []) - {entry_name(e) for e in doc["entries"]}
    if unknown:
        raise SystemExit(f"store.py: not in {MANIFEST.relative_to(SOURCE)}: {', '.join(sorted(unknown))}")
    start = time.time()
    for i, e in enumerate(todo):
        name = entry_name(e)
        print(f"[{i + 1}/{len(todo)}] {name}: rendering ({time.time() - start:.0f} s so far)", flush=True)
        tmp = STORE / f".{name}.tmp"
        shutil.rmtree(tmp, ignore_errors=True)
        render(binary, e, settings_for(doc, e), tmp)
        info = json.loads((tmp / "reference.json").read_text())
        info["store_key"] = key(e, settings_for(doc, e))
        info["scene"] = str(scene_file(e).relative_to(SOURCE)) if "generator" not in e else e["generator"]
        (tmp / "reference.json").write_text(json.dumps(info, indent=2) + "\n")
        final = STORE / name
        shutil.rmtree(final, ignore_errors=True)
        tmp.rename(final)
        frames = info["frames"]
        agree = worst_agreement(frames)
        print(f"[{i + 1}/{len(todo)}] {name}: {sum(f['seconds'] for f in frames):.0f} s for {len(frames)} frame(s), "
              f"{sum(f['samples']['mean'] for f in frames) / len(frames):.0f} samples a reflective pixel; seeds agree "
              f"at {fmt(agree.get('mirror'))} (mirror band), {fmt(agree.get('rough'))} (rough band), "
              f"{agree.get('unconverged_pixels', 0)} pixels unconverged{' (worst frame)' if len(frames) > 1 else ''}",
              flush=True)
    print(f"store.py: {len(todo)} reference(s) rendered in {time.time() - start:.0f} s")


def worst_agreement(frames):
    """The seed agreement of the frame whose mirror band agrees least (a path's weakest frame)."""
    def mirror(f):
        band = f.get("seed_agreement", {}).get("mirror") or {}
        return band.get("psnr_db") if band.get("psnr_db") is not None else 1e9
    return min(frames, key=mirror).get("seed_agreement", {})


def fmt(band):
    if not band or band.get("psnr_db") is None:
        return "-"
    return f"{band['psnr_db']:.1f} dB on {band['pixels']} px"


def check():
    doc = manifest()
    bad = 0
    for e in doc["entries"]:
        state, folder = status(e, settings_for(doc, e))
        line = f"{entry_name(e)}: {state}"
        if state == "fresh":
            frames = json.loads((folder / "reference.json").read_text())["frames"]
            agree = worst_agreement(frames)
            line += (f" (seeds agree at {fmt(agree.get('mirror'))} mirror, {fmt(agree.get('rough'))} rough"
                     f"{f'; the worst of {len(frames)} frames' if len(frames) > 1 else ''})")
        else:
            bad += 1
        print(line)
    if bad:
        print(f"FAIL: {bad} converged reference(s) not fresh; regenerate: {REGENERATE}")
    return bad == 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="command", required=True)
    sub.add_parser("check")
    r = sub.add_parser("regenerate")
    r.add_argument("--reference", required=True, help="the speculum-reference binary")
    r.add_argument("--only", action="append", help="an entry name (SCENE.CAMERA.SIZE.bBOUNCES); repeatable")
    r.add_argument("--force", action="store_true", help="render even fresh entries")
    a = ap.parse_args()
    if a.command == "check":
        sys.exit(0 if check() else 1)
    regenerate(a.reference, a.only, a.force)


if __name__ == "__main__":
    main()
