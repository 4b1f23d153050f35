"""Compare what two rodsim builds say about the same scenes, good and bad.

    /usr/bin/python3 scripts/scene_messages_diff.py OLD_RODSIM NEW_RODSIM [--show N]

Runs `rodsim check` of both builds on the shipped scenes (workflows/scenes,
bench/scenes, fuzz/seeds, plus scenes with a material file, an intrinsic-shape
file and an initial-condition file made here) and on variants of each with
one mistake (a key removed, misspelt, of the wrong type, out of range, in
the wrong section; an unknown section; a bad --set), and compares exit
status, stdout (the resolved scene) and stderr (the error message) byte for
byte. Exit status 0 when every case agrees, 1 with the differences.
Used for the one-time check that a refactoring of the scene reader leaves
its messages unchanged (docs/architecture.md); not a test, since a test may
not compare the code with its own earlier output.
"""
import argparse
import math
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    raise TypeError(type(v))


def toml_text(scene):
    out = [f"{k} = {toml_value(v)}" for k, v in scene.items() if not isinstance(v, dict)]  # before any table
    for sec, body in scene.items():
        if not isinstance(body, dict):
            continue
        out.append(f"[{sec}]")
        out += [f"{k} = {toml_value(v)}" for k, v in body.items()]
    return "\n".join(out) + "\n"


def made_scenes(folder):
    """Scenes with the three kinds of input file (relative paths)."""
    N, L = 8, 6.0
    s = np.arange(N) * L / N
    with h5py.File(folder / "ic.h5", "w") as f:
        f["s"] = s
        for name in ("gamma", "omega", "Gamma", "Omega"):
            f[f"fields/{name}"] = np.zeros((N, 3)) + (name == "Gamma") * np.array([0, 0, 1.0])
    with h5py.File(folder / "shape.h5", "w") as f:
        f["Gamma0"] = np.tile([0, 0, 1.0], (N, 1))
        f["Omega0"] = np.tile([0, 0, 0.5], (N, 1))
    with h5py.File(folder / "material.h5", "w") as f:
        f.attrs["format"] = "dnarod-material/1"
        f["K"] = np.tile(np.diag([1, 1, 1.19, 1.21, 1.21, 2.0]), (N, 1, 1))
        f["I"] = np.tile(np.diag([1, 1, 2.0]), (N, 1, 1))
        f["rho"] = np.ones(N)
    rod = {"length": L, "points": N}
    return {
        "made_file_ic": {"rod": dict(rod), "initial": {"kind": "file", "path": "ic.h5"}},
        "made_intrinsic": {"rod": dict(rod, intrinsic_file="shape.h5"), "output": {"t_end": 1.0}},
        "made_material": {"rod": dict(rod), "material": {"material_file": "material.h5"}},
        "made_K": {"rod": dict(rod), "material": {"K": np.diag([1, 1, 1.19, 1.21, 1.21, 2.0]).tolist(),
                                                  "I": [[1.0, 0.1, 0], [0.1, 1.0, 0], [0, 0, 2.0]]}},
        "made_profile": {"rod": dict(rod, Omega0=[[0, 0, 1.0]] * N)},
    }


BAD_VALUES = ["zz", -1, 0, 1e300, True, [1, 2], 2.5, "auto", float("nan")]


def variants(name, scene):
    yield name, scene, []
    for sec, body in scene.items():
        if not isinstance(body, dict):
            continue
        for k in body:
            rest = {kk: vv for kk, vv in body.items() if kk != k}
            yield f"{name}-{sec}.{k}-removed", {**scene, sec: rest}, []
            yield f"{name}-{sec}.{k}-misspelt", {**scene, sec: {**rest, k + "x": body[k]}}, []
            for i, bad in enumerate(BAD_VALUES):
                yield f"{name}-{sec}.{k}-bad{i}", {**scene, sec: {**body, k: bad}}, []
            for other in ("rod", "solver", "output", "initial"):
                if other != sec:
                    moved = {**scene, sec: rest, other: {**scene.get(other, {}), k: body[k]}}
                    yield f"{name}-{sec}.{k}-in-{other}", moved, []
            yield f"{name}-{sec}.{k}-set", scene, [f"{sec}.{k}=zz"]
        yield f"{name}-{sec}-not-a-table", {**scene, sec: 3}, []
    yield f"{name}-unknown-section", {**scene, "solvr": {"rtol": 1e-8}}, []
    yield f"{name}-set-unknown-section", scene, ["thermall.kT=1"]
    yield f"{name}-set-no-dot", scene, ["rtol=1"]
    yield f"{name}-set-fd4", scene, ["solver.space=fd4", "rod.points=4"]
    yield f"{name}-set-dealias", scene, ["solver.space=fd4", "solver.dealias=true"]
    yield f"{name}-set-dt-min", scene, ["solver.dt_min=1"]
    yield f"{name}-set-kind-file", scene, ["initial.kind=file"]
    yield f"{name}-set-path", scene, ["initial.path=ic.h5"]


def check(rodsim, path, sets):
    cmd = [rodsim, "check", str(path)] + [a for s in sets for a in ("--set", s)]
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=path.parent)
    return p.returncode, p.stdout, p.stderr


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--show", type=int, default=10, help="differences to print in full")
    a = ap.parse_args()
    a.old, a.new = (str(Path(p).resolve()) for p in (a.old, a.new))  # each check runs in the scene's folder
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        scenes = made_scenes(folder)
        for d in ("workflows/scenes", "bench/scenes", "fuzz/seeds"):
            for p in sorted((ROOT / d).glob("*.toml")):
                try:
                    scenes[p.stem] = tomllib.loads(p.read_text())
                except tomllib.TOMLDecodeError:
                    pass
        n = same = errors = 0
        diffs = []
        for name, scene in scenes.items():
            for vname, v, sets in variants(name, scene):
                path = folder / f"{vname}.toml"
                try:
                    path.write_text(toml_text(v))
                except TypeError:
                    continue
                old, new = check(a.old, path, sets), check(a.new, path, sets)
                n += 1
                errors += old[0] != 0
                if old == new:
                    same += 1
                else:
                    diffs.append((vname, sets, old, new))
        print(f"{n} scenes ({errors} refused by the old build): {same} the same, {len(diffs)} differ")
        for vname, sets, old, new in diffs[:a.show]:
            print(f"--- {vname} {sets}")
            for label, (code, out, err) in (("old", old), ("new", new)):
                print(f"{label} ({code}): {err or out[:300]}")
        return 0 if not diffs else 1


if __name__ == "__main__":
    sys.exit(main())
