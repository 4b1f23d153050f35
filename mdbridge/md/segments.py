"""The segments of one long MD, carried over sessions, put together in time.

A run stopped between checkpoints wrote frames past its last checkpoint; the next segment
continues from that checkpoint, so its frames are the run's (workflows/steps/segments.py
reduces each segment; docs/intact.md). `kept_frames` is the one rule for every per-frame
record of the segments (mode amplitudes, pair distances, energies, step parameters), and
`read_steps` joins the segments' step parameters (steps.npz) with their pair distances
(integrity.npz, the same folder) for the coarse-graining.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from dna_models.errors import InputError


def kept_frames(times: list[np.ndarray], what: str, names: list[str]) -> list[np.ndarray]:
    """Per segment, the frames to keep: a segment's frames from the next segment's start on
    are left out (a run stopped between checkpoints wrote frames past its last checkpoint;
    the next segment continues from that checkpoint, and its frames are the run's). Then the
    segments must follow one another, one frame apart."""
    keep = [np.ones(len(t), dtype=bool) for t in times]
    for i in range(len(times) - 1):
        keep[i] = times[i] < times[i + 1][0] - 1e-6
    for (a, ka, na), (b, nb) in zip(zip(times, keep, names), zip(times[1:], names[1:])):
        dt = float(np.median(np.diff(a)))
        end = a[ka][-1] if ka.any() else -np.inf
        if not (0 < b[0] - end <= 1.5 * dt):
            raise InputError(f"{nb}: its {what} start at {b[0]:g} ps, {na}'s end at {end:g} ps: "
                             f"segments must follow one another (one frame, {dt:g} ps, apart)")
    return keep


def read_steps(files) -> dict:
    """The step parameters of segments' steps.npz FILES (in time order) joined in time, and
    the N1-N3 distance of every pair at the same frames from each one's integrity.npz:
    {"times_ps" (T,), "q" (T, n_steps, 6) float, "n1_n3_A" (T, n_bp), "sequence", "pairs",
    "mass_inertia"} (the segments' mass and inertia, weighted by their frames)."""
    files = [Path(f) for f in files]
    steps, integ = [], []
    for f in files:
        i = f.parent / "integrity.npz"
        if not i.is_file():
            raise InputError(f"{f}: no integrity.npz beside it (segments reduce writes both): the open pairs "
                             "of its frames are unknown")
        z = np.load(f)
        if not {"q", "times_ps", "mi_mass", "pairs"} <= set(z.files):
            raise InputError(f"{f}: not a steps file (no 'q', 'times_ps', 'mi_mass', 'pairs'; allowed: the "
                             "steps.npz of `python3 -m dnarod.steps.segments reduce`)")
        steps.append(z)
        integ.append(np.load(i))
    names = [str(f) for f in files]
    seqs = {str(z["sequence"]) for z in steps}
    if len(seqs) != 1:
        raise InputError(f"{', '.join(names)}: segments of different sequences")
    keep = kept_frames([z["times_ps"] for z in steps], "step frames", names)
    t = np.concatenate([z["times_ps"][k] for z, k in zip(steps, keep)])
    q = np.concatenate([z["q"][k].astype(float) for z, k in zip(steps, keep)])
    keep = kept_frames([z["times_ps"] for z in integ], "pair frames", names)
    ti = np.concatenate([z["times_ps"][k] for z, k in zip(integ, keep)])
    di = np.concatenate([z["n1_n3_A"][k].astype(float) for z, k in zip(integ, keep)])
    at = np.searchsorted(ti, t)
    if np.any(at >= len(ti)) or np.any(np.abs(ti[np.minimum(at, len(ti) - 1)] - t) > 1e-6):
        raise InputError(f"{', '.join(names)}: the step frames are not all among integrity.npz's frames")
    w = np.array([float(z["mi_frames"]) for z in steps])
    w /= w.sum()
    mi = {k: sum(wi * z[f"mi_{k}"] for wi, z in zip(w, steps)) for k in ("mass", "inertia", "slice_inertia")}
    mi["slice_inertia_err"] = np.sqrt(sum((wi * z["mi_slice_inertia_err"]) ** 2 for wi, z in zip(w, steps)))
    mi["hydrogens"] = all(bool(z["mi_hydrogens"]) for z in steps)
    mi["frames"] = int(sum(int(z["mi_frames"]) for z in steps))
    return {"times_ps": t, "q": q, "n1_n3_A": di[at], "sequence": seqs.pop(),
            "pairs": [tuple(p) for p in steps[0]["pairs"]], "mass_inertia": mi}
