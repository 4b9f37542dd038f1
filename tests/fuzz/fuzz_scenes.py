#!/usr/bin/env python3
"""JSON-aware mutation fuzzer over the scene corpus (issue 15).

    fuzz_scenes.py --check TOOL [--capture CAPTURE] --corpus DIR... --work DIR
                   [--seconds S] [--runs N] [--seed K] [--capture-every N] [--batch N] [--replay]

Each run takes a seed scene (assets/scenes/*.gltf, tests/data/**/*.gltf, tests/fuzz/corpus/*),
applies 1-4 structural mutations to its JSON (a value replaced by a hostile one, a key deleted, an
array grown, shrunk or duplicated, an index pushed out of range, a deep nest, a hostile path) or
to its bytes (truncation, a flipped byte), and runs TOOL (speculum-scene-check, 25 mutants per
process) on it. Every N-th mutant the loader accepts also goes through speculum-capture (device,
renderer, module, with validation) at 32x18.

A run FAILS on: an exit other than 0, 2 or 3; a signal; a timeout; "internal error"; or exit 3
without a message naming the mutant file. Each failing mutant is kept in WORK/failures/ with the
command, so it can become a regression file in tests/fuzz/corpus/. Same seed, same mutants.
"""
import argparse, copy, json, os, random, shutil, subprocess, sys, time

HOSTILE_NUMBERS = [-1, 0, 1, 2, 3, 7, 255, 256, 65535, 65536, 2**31 - 1, 2**31, 2**32 - 1, 2**32,
                   2**53, 2**63 - 1, 2**64 - 1, -2**31, -2**63, 1e308, -1e308, 1e-320, 0.5, -0.0, 3.4e38,
                   3.5e38]
HOSTILE_PATHS = ["/dev/zero", "/dev/urandom", "/dev/null", ".", "..", "", "/", "nonexistent.bin",
                 "../env/sunset.exr", "../env", "data:application/octet-stream;base64,AAAA",
                 "data:image/png;base64,iVBORw0KGgo=", "%2e%2e/%2e%2e/etc/passwd", "a" * 5000]
HOSTILE_VALUES = [None, True, False, "", "x" * 10000, [], {}, [[]], {"": {}}, "NaN", "Infinity"]


def all_paths(doc, prefix=()):
    """Every (container, key) path in the document, for picking a mutation site."""
    out = []
    stack = [(doc, prefix)]
    while stack:
        node, path = stack.pop()
        if isinstance(node, dict):
            for k, v in node.items():
                out.append(path + (k,))
                stack.append((v, path + (k,)))
        elif isinstance(node, list):
            for i, v in enumerate(node):
                out.append(path + (i,))
                stack.append((v, path + (i,)))
    return out


def get(doc, path):
    for p in path:
        doc = doc[p]
    return doc


def deep(depth):
    """A token that make_mutant turns into DEPTH nested arrays after json.dumps (which recurses)."""
    return "@@DEEP:%d@@" % depth


def expand_deep(text):
    out, start = [], 0
    while True:
        i = text.find('"@@DEEP:', start)
        if i < 0:
            return "".join(out) + text[start:]
        j = text.index('@@"', i + 8)
        n = int(text[i + 8:j])
        out.append(text[start:i] + "[" * n + "0" + "]" * n)
        start = j + 3


def mutate_json(doc, rng):
    paths = all_paths(doc)
    if not paths:
        return doc
    path = rng.choice(paths)
    parent, key = get(doc, path[:-1]), path[-1]
    value = parent[key]
    op = rng.randrange(10)
    if op == 0 and isinstance(parent, dict):
        del parent[key]
    elif op == 1:
        parent[key] = rng.choice(HOSTILE_NUMBERS)
    elif op == 2:
        parent[key] = copy.deepcopy(rng.choice(HOSTILE_VALUES))
    elif op == 3 and isinstance(value, int) and not isinstance(value, bool):
        parent[key] = value + rng.choice([-1, 1, 1000, 2**20, -value - 1])  # near and past the range
    elif op == 4 and isinstance(value, list) and value:
        parent[key] = value * rng.choice([2, 8, 64]) if len(value) < 64 else value[: len(value) // 2]
    elif op == 5 and isinstance(value, list) and value:
        del value[rng.randrange(len(value))]
    elif op == 6:
        parent[key] = deep(rng.choice([100, 600, 5000, 20000]))
    elif op == 7 and isinstance(value, str):
        parent[key] = rng.choice(HOSTILE_PATHS)
    elif op == 8:
        # A hostile environment or buffer/image uri where the loader or renderer will look.
        where = rng.choice(["environment", "buffer", "image"])
        if where == "environment" and isinstance(doc.get("scenes"), list) and doc["scenes"] and isinstance(doc["scenes"][0], dict):
            doc["scenes"][0].setdefault("extras", {})
            if isinstance(doc["scenes"][0]["extras"], dict):
                doc["scenes"][0]["extras"]["environment"] = rng.choice(HOSTILE_PATHS)
        elif isinstance(doc.get(where + "s"), list) and doc[where + "s"] and isinstance(doc[where + "s"][0], dict):
            doc[where + "s"][0]["uri"] = rng.choice(HOSTILE_PATHS)
    elif isinstance(value, (dict, list)):
        parent[key] = copy.deepcopy(value)  # a sibling of the same shape under a new name
        if isinstance(parent, dict):
            parent[key + "_copy" if isinstance(key, str) else key] = copy.deepcopy(value)
    return doc


def mutate_bytes(data, rng):
    data = bytearray(data)
    if not data:
        return bytes(data)
    if rng.random() < 0.5:
        return bytes(data[: rng.randrange(len(data))])
    for _ in range(rng.randint(1, 8)):
        data[rng.randrange(len(data))] = rng.randrange(256)
    return bytes(data)


def make_mutant(seed_path, rng):
    with open(seed_path, "rb") as f:
        raw = f.read()
    if seed_path.endswith(".glb") or rng.random() < 0.1:
        return mutate_bytes(raw, rng), os.path.splitext(seed_path)[1]
    try:
        doc = json.loads(raw)
    except (ValueError, UnicodeDecodeError, RecursionError):
        return mutate_bytes(raw, rng), ".gltf"
    for _ in range(rng.choice([1, 1, 1, 2, 3, 4])):
        doc = mutate_json(doc, rng)
    return expand_deep(json.dumps(doc)).encode(), ".gltf"


def setup_work(work, corpus_dirs):
    """WORK/scenes holds links to every corpus file and its neighbours (.bin, images), and
    WORK/env links the environment maps, so the mutants' relative uris resolve as the seeds' do."""
    scenes = os.path.join(work, "scenes")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(scenes)
    seeds = []
    for d in corpus_dirs:
        for name in sorted(os.listdir(d)):
            src = os.path.abspath(os.path.join(d, name))
            if not os.path.isfile(src):
                continue
            dst = os.path.join(scenes, name)
            if not os.path.exists(dst):
                os.symlink(src, dst)
            if name.endswith((".gltf", ".glb")):
                seeds.append(src)
        env = os.path.join(os.path.dirname(os.path.abspath(d)), "env")
        if os.path.isdir(env) and not os.path.exists(os.path.join(work, "env")):
            os.symlink(env, os.path.join(work, "env"))
    return scenes, seeds


def judge(cmd, mutant, timeout):
    """One process on one mutant: (why it failed or None, output, seconds)."""
    start = time.time()
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "timeout after %ds" % timeout, "", time.time() - start
    out = p.stdout.decode(errors="replace")
    took = time.time() - start
    if p.returncode < 0:
        return "signal %d" % -p.returncode, out, took
    return verdict(p.returncode, out, mutant), out, took


def verdict(code, out, mutant):
    if code not in (0, 2, 3):
        return "exit %d" % code
    if "internal error" in out:
        return "internal error"
    if code == 3 and os.path.basename(mutant) not in out:
        return "exit 3 without naming the file"
    return None


def judge_batch(check, mutants, timeout):
    """speculum-scene-check on many mutants in one process (it prints each file's message, then
    "@@ exit N"). Returns {mutant: (why, output)}; mutants a dead or hung process did not finish
    are judged one by one, which names the culprit."""
    cmd = [check]
    for m in mutants:
        cmd += ["--scene", m]
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=timeout)
        out = p.stdout.decode(errors="replace")
    except subprocess.TimeoutExpired as e:
        out = (e.stdout or b"").decode(errors="replace")
    results, text = {}, ""
    lines = iter(out.splitlines(keepends=True))
    done = 0
    for line in lines:
        if line.startswith("@@ exit ") and done < len(mutants):
            m = mutants[done]
            code = int(line[8:])
            results[m] = (verdict(code, text, m) or "", text, code)
            text, done = "", done + 1
        else:
            text += line
    for m in mutants[done:]:
        why, out, _ = judge([check, "--scene", m], m, timeout)
        results[m] = (why or "", out, -1)
    return results


def replay(a, scenes, seeds):
    bad = 0
    for seed in seeds:
        link = os.path.join(scenes, os.path.basename(seed))
        cmds = [[a.check, "--scene", link]]
        if a.capture:
            cmds.append([a.capture, "--scene", link, "--size", "32x18", "--warmup", "0", "--out",
                         os.path.join(a.work, "out")])
        for cmd in cmds:
            why, out, _ = judge(cmd, link, a.timeout)
            print("%s %s: %s" % ("FAIL" if why else "ok", os.path.basename(seed), why or out.strip()[-200:]))
            bad += bool(why)
    print("replay: %d corpus files, %d failures" % (len(seeds), bad))
    return 1 if bad else 0


def fuzz(a, rng, scenes, seeds, failures):
    start, runs, captures, bad, outcomes, loaded = time.time(), 0, 0, 0, {}, 0
    # Four mutants in five start from a seed that loads: those reach deeper than the bad files.
    seed_results = judge_batch(a.check, seeds, a.timeout)
    good = [sd for sd in seeds if seed_results[sd][2] == 0] or seeds
    while runs < a.runs and time.time() - start < a.seconds:
        batch = []
        for _ in range(min(a.batch, a.runs - runs)):
            seed = rng.choice(good if rng.random() < 0.8 else seeds)
            data, ext = make_mutant(seed, rng)
            mutant = os.path.join(scenes, "mutant%06d%s" % (runs, ext))
            with open(mutant, "wb") as f:
                f.write(data)
            batch.append((runs, mutant, seed))
            runs += 1
        results = judge_batch(a.check, [m for _, m, _ in batch], a.timeout)
        for index, mutant, seed in batch:
            why, out, code = results[mutant]
            why = why or None
            # The device path for mutants the loader accepted: they reach the renderer and module.
            loaded = loaded + 1 if code == 0 else loaded
            if a.capture and code == 0 and loaded % a.capture_every == 0:
                captures += 1
                cmd = [a.capture, "--scene", mutant, "--size", "32x18", "--warmup", "0",
                       "--out", os.path.join(a.work, "out")]
                cwhy, cout, _ = judge(cmd, mutant, a.timeout)
                if cwhy:
                    why, out = "speculum-capture: " + cwhy, cout
            key = why or ("exit %d" % code if code >= 0 else "fine alone after a batch failure")
            outcomes[key] = outcomes.get(key, 0) + 1
            if why:
                bad += 1
                kept = os.path.join(failures, os.path.basename(mutant))
                shutil.copy(mutant, kept)
                print("FAIL %s (%s)\n  seed %s\n  %s" % (kept, why, seed, out.strip()[-600:]), flush=True)
            else:
                os.remove(mutant)
    print("fuzz: %d mutants in %.0f s (seed %d; %d also through speculum-capture), %d failures"
          % (runs, time.time() - start, a.seed, captures, bad))
    print("outcomes: " + ", ".join("%s %d" % kv for kv in sorted(outcomes.items())))
    return 1 if bad else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", required=True, help="speculum-scene-check (loader and limits, no device)")
    ap.add_argument("--capture", help="speculum-capture, for every --capture-every-th mutant")
    ap.add_argument("--corpus", nargs="+", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--seconds", type=float, default=150)
    ap.add_argument("--runs", type=int, default=1000000)
    ap.add_argument("--seed", type=int, default=15)
    ap.add_argument("--capture-every", type=int, default=3, help="every N-th mutant the loader accepts")
    ap.add_argument("--batch", type=int, default=25, help="mutants per speculum-scene-check process")
    ap.add_argument("--timeout", type=int, default=60)
    ap.add_argument("--replay", action="store_true", help="run every corpus file once, unmutated")
    a = ap.parse_args()
    scenes, seeds = setup_work(a.work, a.corpus)
    if a.replay:
        return replay(a, scenes, seeds)
    failures = os.path.join(a.work, "failures")
    os.makedirs(failures)
    return fuzz(a, random.Random(a.seed), scenes, seeds, failures)


if __name__ == "__main__":
    sys.exit(main())
