"""Cost of `dnarod rod-to-atoms` on the 158-bp duplex (issue target: 600 frames in
at most 30 s on 2 cores), side by side in one run:

  coarse        beads + d1 tips, multi-model PDB
  atoms         all-atom XTC in the MD build's atoms, no chemistry report
  atoms+chem    the same plus the per-frame O3'-P and closest-contact report (default)

Makes its inputs itself: a 600-frame rod run of workflows/scenes/dna158.toml (600 ps)
and its MD build (dnarod build-md). Writes bench/results/backmap.json.

    /usr/bin/python3 bench/backmap.py [--out DIR] [--frames 600] [--quick]
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _timed(cmd) -> tuple[float, float]:
    t0, c0 = time.perf_counter(), os.times()
    subprocess.run(cmd, check=True, capture_output=True, text=True)
    c1 = os.times()
    return time.perf_counter() - t0, (c1.children_user + c1.children_system) - (c0.children_user + c0.children_system)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=str(ROOT / "bench" / "results"))
    ap.add_argument("--frames", type=int, default=600)
    ap.add_argument("--quick", action="store_true", help="60 frames (tests the script)")
    a = ap.parse_args(argv)
    frames = 60 if a.quick else a.frames
    dnarod = shutil.which("dnarod") or str(ROOT / "build" / "bin" / "dnarod")
    rodsim = shutil.which("rodsim") or str(ROOT / "build" / "bin" / "rodsim")
    work = Path(tempfile.mkdtemp(prefix="bench_backmap_"))
    from dna_models.units import Units
    tau = Units.paper().tau_ps
    scene = (ROOT / "workflows" / "scenes" / "dna158.toml").read_text()
    scene_path = work / "dna158.toml"
    scene_path.write_text(scene)
    rod = work / "rod.h5"
    subprocess.run([rodsim, "run", str(scene_path), "-o", str(rod), "--set", f"output.frames={frames}",
                    "--set", f"output.t_end={frames / tau:.12g}",
                    "--set", 'output.fields=["centerline","directors","internal"]'],
                   check=True, capture_output=True)
    md = work / "md"
    subprocess.run([dnarod, "build-md", str(scene_path), "-o", str(md), "--ps", "5", "--rod", str(rod)],
                   check=True, capture_output=True)
    rows = {}
    for name, extra in (("coarse", ["--coarse", "-o", str(work / "c.pdb")]),
                        ("atoms", ["--like", str(md), "--no-chemistry", "-o", str(work / "a.xtc")]),
                        ("atoms+chem", ["--like", str(md), "-o", str(work / "b.xtc")])):
        wall, cpu = _timed([dnarod, "rod-to-atoms", str(rod), *extra])
        rows[name] = {"wall_s": round(wall, 2), "cpu_s": round(cpu, 2)}
        print(f"{name:12s} {frames} frames: {wall:6.2f} s wall, {cpu:6.2f} s CPU")
    base = rows["atoms"]["wall_s"]
    for r in rows.values():
        r["ratio_to_atoms"] = round(r["wall_s"] / base, 2)
    n_atoms = json.loads((md / "build.json").read_text())["n_atoms"]
    res = {"frames": frames, "n_bp": 158, "n_atoms": n_atoms, "target_s_for_600_frames": 30.0,
           "load_average": os.getloadavg(), "runs": rows}
    Path(a.out).mkdir(parents=True, exist_ok=True)
    (Path(a.out) / "backmap.json").write_text(json.dumps(res, indent=1))
    shutil.rmtree(work)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
