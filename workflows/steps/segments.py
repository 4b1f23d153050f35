"""A long MD carried over sessions in segments, reduced segment by segment.

A run longer than a session continues from its checkpoint on the next machine as a new
segment (`dnarod run-md`: md.part.cpt without the outputs it appended to;
mdbridge/md/gromacs/run.py). The trajectory of each segment never leaves its machine: before
it goes, `reduce` turns it into what the analyses read (docs/intact.md, "The
intact runs, across sessions"):

    python3 -m dnarod.steps.segments reduce MDDIR OUT/segNN

      OUT/segNN/mode_series.npz   `dnarod modes` of the segment's frames (the raw amplitudes)
      OUT/segNN/integrity.npz     N1-N3 distance of every pair in every frame (float16)
      OUT/segNN/energies.npz      the virial tension, the box and, with --hold-pairs, the
                                  restraint energy per energy frame
      OUT/segNN/steps.npz         the six step parameters of every step (the closing one
                                  last) every STEPS_STRIDE-th frame (float16), what the
                                  coarse-graining reads; `steps` writes it alone:

    python3 -m dnarod.steps.segments steps MDDIR OUT/segNN

and `join` puts the segments of one run together in time: a segment's frames past the next
segment's start (written after its last checkpoint, then continued differently) are left
out, and the segments must follow one another without a gap:

    python3 -m dnarod.steps.segments join OUT/seg01 OUT/seg02 ... -o OUT --discard-ps T

      OUT/mode_series.npz  one realisation, the layout of every mode_series.npz
      OUT/integrity.json   open fraction after the discard, per pair, at the junction; with
                           steps.npz, the unstacked fraction of the steps (`stacking`)
      OUT/energies.npz     the joined energy series
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from mdbridge.jsonio import write_json
from mdbridge.md.segments import kept_frames

# the trajectory of a finished run or of the segment being written (run.py's part files)
_VIEWS = ({"md.tpr": "md.tpr", "md.xtc": "md.xtc", "md.edr": "md.edr"},
          {"md.tpr": "md.part.tpr", "md.xtc": "md.part.xtc", "md.edr": "md.part.edr"})


def _sources(md_dir: Path) -> dict:
    views = list(_VIEWS)
    xtc = sorted(md_dir.glob("md.part.part[0-9][0-9][0-9][0-9].xtc"))
    if xtc:    # a segment still being run, or stopped, after a continuation without its outputs
        edr = xtc[-1].name.replace(".xtc", ".edr")
        views.append({"md.tpr": "md.part.tpr", "md.xtc": xtc[-1].name, "md.edr": edr})
    for view in views:
        if all((md_dir / f).is_file() for f in view.values()):
            return view
    raise InputError(f"{md_dir}: neither md.tpr + md.xtc + md.edr (a finished run) nor md.part.tpr + "
                     "md.part.xtc + md.part.edr (a segment being run): nothing to reduce")


STEPS_STRIDE = 2        # 1 ps at the intact runs' 0.5-ps frames: the fastest step motions
                        # decorrelate within ~1 ps, and 6.6 MB per 3.5 ns of 158 bp is committable


def _universe(d: Path, src: dict):
    import MDAnalysis as mda
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return mda.Universe(str(d / src["md.tpr"]), str(d / src["md.xtc"]))


def reduce_steps(md_dir, out, stride: int = STEPS_STRIDE) -> dict:
    """OUT/steps.npz: the segment's step parameters (shift, slide, rise [A], tilt, roll,
    twist [deg], 3DNA's branch), the periodic closing step last, every STRIDE-th frame (on
    the grid of multiples of STRIDE frame times), and
    what the coarse-graining reads from the atoms besides (mdbridge/coarsegrain/reader.py
    mass_inertia): each base pair's mass and inertia averaged over INERTIA_FRAMES frames, and
    the pairs' residue labels."""
    from mdbridge.coarsegrain.reader import INERTIA_FRAMES, mass_inertia
    from mdbridge.geometry.structure import BasePairFrames
    from mdbridge.md.builder.duplex import base_pairs
    d, out = Path(md_dir), Path(out)
    build = json.loads((d / "build.json").read_text())
    u = _universe(d, _sources(d))
    # the frames on one grid for every segment (times that are multiples of STRIDE frames), so
    # that the joined record is evenly spaced whatever time a segment starts at
    # (the frame times from the first frame and the spacing: mdrun writes evenly; no extra pass)
    traj = u.trajectory
    t_all = traj[0].time + traj.dt * np.arange(len(traj))
    period = stride * traj.dt
    frames = np.flatnonzero(np.abs(t_all / period - np.round(t_all / period)) < 1e-3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bpf = BasePairFrames(u, pairs=base_pairs(int(build["n_bp"]))).run(frames=frames)
    q = bpf.step_parameters(periodic=True)
    times = np.asarray(bpf.results.time, float)
    mi = mass_inertia(bpf, np.unique(np.linspace(0, len(frames) - 1, min(len(frames), INERTIA_FRAMES)).astype(int)))
    out.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(out / "steps.npz", times_ps=times, q=q.astype(np.float16),
                        columns=np.array(["shift_A", "slide_A", "rise_A", "tilt_deg", "roll_deg", "twist_deg"]),
                        sequence=np.array(build["sequence"]), stride=stride,
                        pairs=np.array([(f"{a.resname}{a.resid}", f"{b.resname}{b.resid}") for a, b in bpf.pairs]),
                        **{f"mi_{k}": np.asarray(v) for k, v in mi.items()})
    return {"frames": int(len(frames)), "stride": stride}


def reduce_segment(md_dir, out) -> dict:
    """The segment's mode series, pair distances and energies into OUT (module doc)."""
    from mdbridge.md.builder.duplex import base_pairs
    from mdbridge.md.gromacs.energy import read_energies
    from mdbridge.md.gromacs.gmx import find_gmx
    from mdbridge.md.gromacs.tension import tension_series
    from mdbridge.md.integrity import PairIntegrity
    d, out = Path(md_dir), Path(out)
    src = _sources(d)
    build = json.loads((d / "build.json").read_text())
    out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="dnarod-segment-") as tmp:
        view = Path(tmp) / "md"
        view.mkdir()
        for name in ("build.json", "conf.gro"):
            (view / name).symlink_to((d / name).resolve())
        for name, real in src.items():
            (view / name).symlink_to((d / real).resolve())
        subprocess.run([sys.executable, "-m", "dnarod.cli", "modes", str(view), "--discard-ps", "0",
                        "-o", str(Path(tmp) / "modes")], check=True)
        (Path(tmp) / "modes" / "mode_series.npz").replace(out / "mode_series.npz")
        gmx = find_gmx(None)
        energies = read_energies(view, gmx, edr="md.edr")
        tension = tension_series(view, gmx, edr="md.edr")
    u = _universe(d, src)
    res = {int(r.resid): r for r in u.residues}
    pairs = [(res[i], res[j]) for i, j in base_pairs(int(build["n_bp"]))]
    a = PairIntegrity(u, pairs).run()
    np.savez_compressed(out / "integrity.npz", times_ps=np.asarray(a.times_ps, float),
                        n1_n3_A=a.results.distance_A.astype(np.float16))
    extra = {"restraint_kJ_mol": energies["Restraint Pot."]} if "Restraint Pot." in energies else {}
    np.savez_compressed(out / "energies.npz", times_ps=np.asarray(tension["time"], float),
                        tension_pN=tension["tension_pN"], length_nm=tension["length_nm"],
                        area_nm2=tension["area_nm2"], temperature_K=energies["Temperature"], **extra)
    steps = reduce_steps(d, out)
    rec = {"md_dir": str(d.resolve()), "files": src, "frames": int(len(a.times_ps)),
           "times_ps": [float(a.times_ps[0]), float(a.times_ps[-1])], "steps": steps}
    write_json(out / "segment.json", rec)
    return rec


def join_segments(segments, out, discard_ps: float = 0.0) -> dict:
    """The segments of one run (in time order) as one mode series, integrity and energies."""
    from mdbridge.analysis.mode_spectra import ModeSeries, load_npz, save_npz
    from mdbridge.md.integrity import integrity_summary, stacking_summary
    segs = [Path(s) for s in segments]
    series = []
    for s in segs:
        r = load_npz(s / "mode_series.npz")
        if len(r) != 1:
            raise InputError(f"{s / 'mode_series.npz'}: {len(r)} realisations; a segment has one")
        series.append(r[0])
    names = [str(s) for s in segs]
    keep = kept_frames([s.times_ps for s in series], "mode frames", names)
    first = series[0]
    cat = {k: np.concatenate([getattr(s, k)[kk] for s, kk in zip(series, keep)])
           for k in ("times_ps", "bend", "twist", "stretch")}
    fractions = [s.open_fraction for s in series]
    of = (None if any(f is None for f in fractions)
          else np.concatenate([f[kk] for f, kk in zip(fractions, keep) if f is not None]))
    joined = ModeSeries(cat["times_ps"], first.n, cat["bend"], cat["twist"], cat["stretch"],
                        float(np.mean([s.length_A for s in series])), first.n_bp, first.helical_repeat,
                        f"{len(segs)} segments of {first.meta.get('md_dir', first.source)}", first.kind, of,
                        {**first.meta, "segments": names})
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    save_npz(out / "mode_series.npz", [joined], extra={"segments": names})
    integ = [np.load(s / "integrity.npz") for s in segs]
    keep = kept_frames([z["times_ps"] for z in integ], "pair frames", names)
    t = np.concatenate([z["times_ps"][kk] for z, kk in zip(integ, keep)])
    dist = np.concatenate([z["n1_n3_A"][kk].astype(float) for z, kk in zip(integ, keep)])
    summary = integrity_summary(dist, t, discard_ps=discard_ps)
    summary.pop("times_ps")
    step = max(1, len(t) // 500)          # the curve, at most ~500 points
    summary["open_fraction_time"] = summary["open_fraction_time"][::step]
    summary["open_fraction_times_ps"] = t[::step].tolist()
    if all((s / "steps.npz").is_file() for s in segs):     # the steps' stacking beside the pairs
        st = [np.load(s / "steps.npz") for s in segs]
        keep = kept_frames([z["times_ps"] for z in st], "step frames", names)
        ts = np.concatenate([z["times_ps"][kk] for z, kk in zip(st, keep)])
        rise = np.concatenate([z["q"][kk][:, :, 2].astype(float) for z, kk in zip(st, keep)])
        stacking = stacking_summary(rise, ts, discard_ps=discard_ps)
        step = max(1, len(ts) // 500)
        stacking["unstacked_fraction_time"] = stacking["unstacked_fraction_time"][::step]
        stacking["times_ps"] = stacking["times_ps"][::step]
        summary["stacking"] = stacking
    write_json(out / "integrity.json", {**summary, "segments": names})
    en = [np.load(s / "energies.npz") for s in segs]
    keep = kept_frames([z["times_ps"] for z in en], "energy frames", names)
    np.savez_compressed(out / "energies.npz",
                        **{k: np.concatenate([z[k][kk] for z, kk in zip(en, keep)]) for k in en[0].files})
    return summary


def main(argv=None) -> int:
    from dnarod.steps.analyse import run_step
    ap = argparse.ArgumentParser(prog="python3 -m dnarod.steps.segments", description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="step", required=True)
    p = sub.add_parser("reduce")
    p.add_argument("md_dir")
    p.add_argument("out")
    p = sub.add_parser("steps")
    p.add_argument("md_dir")
    p.add_argument("out")
    p = sub.add_parser("join")
    p.add_argument("segments", nargs="+")
    p.add_argument("-o", "--out", required=True)
    p.add_argument("--discard-ps", type=float, default=0.0)
    a = ap.parse_args(argv)

    def step():
        if a.step == "reduce":
            reduce_segment(a.md_dir, a.out)
        elif a.step == "steps":
            reduce_steps(a.md_dir, a.out)
        else:
            join_segments(a.segments, a.out, a.discard_ps)
    return run_step(a.step, step)


if __name__ == "__main__":
    sys.exit(main())
