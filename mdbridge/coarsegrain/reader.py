"""From an MD trajectory (anything MDAnalysis reads) to a StepEnsemble, plus what the
atoms give besides the step parameters: base-pair integrity, mass and inertia per
base pair, and the kinetic temperature.

Base-pair frames and step parameters are mdbridge.geometry's (3DNA-exact, minimum
images across the box); integrity is mdbridge.md.integrity's N1-N3 test.
"""
from __future__ import annotations

import warnings

import numpy as np

from dna_models.errors import InputError
from mdbridge.geometry.analysis_base import AnalysisBase, UniverseFrames
from mdbridge.geometry.pbc import minimum_image
from mdbridge.geometry.structure import BasePairFrames, _canonical_atom_name

from .ensemble import StepEnsemble
from .mass import frame_inertia, pair_atom_indices

MAX_OPEN_FRACTION = 0.05  # the opening rule of the sensitivity: a base pair counts as opened if
                          # N1-N3 > 3.5 A in more than this fraction of the frames used
INERTIA_FRAMES = 50       # frames (evenly spaced) the mass/inertia average is taken over


def is_ligated(bpf: BasePairFrames) -> bool:
    """True when strand I's last O3' and its first P are within 4 A (minimum image; bonded
    1.6 A, up to ~2.6 A in rebuilt models) in a periodic box: the duplex is closed."""
    box = bpf.universe.dimensions
    if box is None or np.any(np.asarray(box[:3]) < 10.0):
        return False
    first, last = bpf.pairs[0][0], bpf.pairs[-1][0]
    o3 = [a for a in last.atoms if _canonical_atom_name(a.name) == "O3'"]
    p = [a for a in first.atoms if _canonical_atom_name(a.name) == "P"]
    if not (o3 and p):
        return False
    d = np.linalg.norm(minimum_image(p[0].position - o3[0].position, np.asarray(box, float)))
    return bool(d < 4.0)


def open_pairs(universe, pairs, start, stop, step, max_fraction=MAX_OPEN_FRACTION, progress=None):
    """(opened (n_bp,) bool, fraction of frames open (n_bp,), N1-N3 distances (T, n_bp))."""
    from mdbridge.md.integrity import INTACT_CUTOFF_A, bp_intact_fraction
    _, _, dist = bp_intact_fraction(universe, pairs, start, stop, step, progress=progress)
    frac = np.mean(dist > INTACT_CUTOFF_A, axis=0)
    return frac > max_fraction, frac, dist


def steps_of_pairs(opened: np.ndarray, closed: bool) -> np.ndarray:
    """Steps (..., n_steps) touching an opened base pair, of opened (..., n_bp): per pair, or
    per frame and pair."""
    n = opened.shape[-1]
    k = np.arange(n if closed else n - 1)
    return opened[..., k] | opened[..., (k + 1) % n]


class PairMassInertia(AnalysisBase):
    """Per base pair and frame: full inertia about the base-pair origin and slice inertia
    (amu A^2), in the base-pair frames of `bpf` (a BasePairFrames that has run); an
    analysis of the one loop (mdbridge/geometry/analysis_base.py), run over some of the
    frames bpf analysed: run(frames=bpf.results.frame[positions])."""

    def __init__(self, bpf: BasePairFrames):
        super().__init__(UniverseFrames(bpf.universe))
        self.bpf = bpf
        self.groups = pair_atom_indices(bpf.pairs)
        # where each trajectory frame sits in bpf.results
        self._position = {int(f): k for k, f in enumerate(bpf.results.frame)}

    def _prepare(self):
        n = len(self.groups)
        self._full = np.zeros((self.n_frames, n, 3, 3))
        self._slice = np.zeros_like(self._full)

    def _single_frame(self):
        u, r = self.bpf.universe, self.bpf.results
        i_res, k = self._position[self._frame], self._frame_index
        box = None if (u.dimensions is None or r.box is None) else np.asarray(u.dimensions, float)
        pos = u.atoms.positions.astype(float)
        masses = u.atoms.masses
        for i, g in enumerate(self.groups):
            _, self._full[k, i], self._slice[k, i] = frame_inertia(pos[g], masses[g], r.origins[i_res, i],
                                                                   r.R[i_res, i], box)

    def _conclude(self):
        self.results.inertia = self._full
        self.results.slice_inertia = self._slice


def mass_inertia(bpf: BasePairFrames, frame_index: np.ndarray):
    """Per base pair: mass (amu), full inertia about the bp origin (amu A^2), slice
    inertia (amu A^2), each averaged over the frames (positions into bpf.results)
    and the standard error of the inertia over those frames; hydrogens present?"""
    u = bpf.universe
    per_frame = PairMassInertia(bpf).run(frames=np.asarray(bpf.results.frame)[frame_index])
    groups, masses = per_frame.groups, u.atoms.masses
    mass = np.array([masses[g].sum() for g in groups])
    full, sl = per_frame.results.inertia, per_frame.results.slice_inertia
    try:
        el = np.array([str(e).strip().upper() for e in u.atoms.elements])
    except Exception:  # noqa: BLE001 - no element column
        el = np.array([str(name).strip()[:1].upper() for name in u.atoms.names])
    has_h = bool(np.any(el[np.concatenate(groups)] == "H"))
    k = max(1, len(frame_index))
    return {"mass": mass, "inertia": full.mean(axis=0), "slice_inertia": sl.mean(axis=0),
            "slice_inertia_err": sl.std(axis=0, ddof=1) / np.sqrt(k) if k > 1 else np.zeros_like(sl[0]),
            "hydrogens": has_h, "frames": int(len(frame_index))}


def read_ensemble(universe, pairs=None, pair_numbering="resid", closed=None, start=None, stop=None,
                  step=None, max_open_fraction=MAX_OPEN_FRACTION, source="trajectory", progress=None,
                  leave_out_open_frames: bool = False):
    """StepEnsemble of the duplex in `universe` (every step; the steps touching a base pair
    the opening rule counts as opened marked `opened`, for the rule's sensitivity), and a
    dict of extras (open fractions, mass/inertia, sequence, pairs). progress, if given, is
    called as progress(stage, done, total, "frames") while the frames are read ("frames
    read") and read again for the base-pair check ("pairs checked")."""
    def stage(name):
        return None if progress is None else (lambda done, total: progress(name, done, total, "frames"))
    bpf = BasePairFrames(universe, pairs=pairs, pair_numbering=pair_numbering)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bpf.run(start, stop, step, progress=stage("frames read"))
    if closed is None:
        closed = is_ligated(bpf)
    if closed and bpf.results.box is None:
        raise InputError(f"{source}: a closed (ligated) duplex needs the periodic box in every frame")
    q = bpf.step_parameters(periodic=closed)
    with warnings.catch_warnings():   # "Reader has no dt information" for PDB models
        warnings.simplefilter("ignore")
        opened, frac, dist = open_pairs(universe, bpf.pairs, start, stop, step, max_open_fraction,
                                        progress=stage("pairs checked"))
    opened_steps = steps_of_pairs(opened, closed)
    from mdbridge.md.integrity import INTACT_CUTOFF_A
    # with leave_out_open_frames, each step's local estimates leave out the frames where it
    # touches an open pair (estimator.py, docs/intact.md); off by default for now: on the
    # tiny workflow's frayed 40-ps MD it moved the coarse-grained rod (one replicate of five
    # failed), which is not understood yet
    open_frames = steps_of_pairs(dist > INTACT_CUTOFF_A, closed) if leave_out_open_frames else None
    T = q.shape[0]
    fi = np.unique(np.linspace(0, T - 1, min(T, INERTIA_FRAMES)).astype(int))
    mi = mass_inertia(bpf, fi)
    ens = StepEnsemble(q=q, sequence=bpf.sequence, closed=bool(closed),
                       times_ps=np.asarray(bpf.results.time, float), opened=opened_steps,
                       open_frames=open_frames, source=source)
    extras = {"open_fraction": frac, "opened_pairs": np.flatnonzero(opened), "mass_inertia": mi,
              "pairs": [(f"{a.resname}{a.resid}", f"{b.resname}{b.resid}") for a, b in bpf.pairs],
              "bpf": bpf}
    return ens, extras


def _material_file(path, run) -> dict | None:
    """The grid material file a rod run names (attribute `material.material_file`, written by
    `dnarod dna-rod`): its sequence, rho (N,) and I (N, 3, 3) in rod units; None without one."""
    import h5py
    from pathlib import Path
    name = run.attrs.get("material.material_file")
    if name is None or str(name) == "":
        return None
    mpath = Path(str(name))
    if not mpath.is_file():
        raise InputError(f"{path}: its material file '{mpath}' (attribute 'material.material_file') does not "
                         "exist; the base pairs of a sequence rod come from it")
    with h5py.File(mpath, "r") as f:
        if "sequence" not in f.attrs or "rho" not in f or "I" not in f:
            raise InputError(f"{mpath}: a material file without the attribute 'sequence' or the datasets "
                             "'rho', 'I' (allowed: the dnarod-material/1 file of `dnarod dna-rod`)")
        sequence = str(f.attrs["sequence"])
        rho, inertia = np.asarray(f["rho"], float), np.asarray(f["I"], float)
    if len(rho) % len(sequence):
        raise InputError(f"{mpath}: {len(rho)} grid points are not a multiple of its {len(sequence)} base pairs")
    return {"sequence": sequence, "rho": rho, "I": inertia}


def read_rod_ensemble(path, start=None, stop=None, step=None):
    """StepEnsemble of the base pairs a rod run carries (a `rodsim run` file of a DNA scene:
    `initial.bp` base pairs at s_i = i L / n_bp, mdbridge.rod.run.RodRun.trajectory), closed
    (rodsim's rods are periodic), and extras: the rod's temperature (attribute
    `temperature_K`) and, for a uniform material, each base pair's mass and inertia (rho and
    I over one rise, the convention of mdbridge.rod.material.steps_to_rod).

    The closing step (last base pair to the first, one period on) is excluded: the rod's
    frames are reconstructed from s = 0, and a thermal rod's holonomy drifts (docs/thermal.md),
    so the frame at s = L is not the first frame carried one period on (on a 42-bp Langevin
    rod at 300 K that step's twist variance was 20x the others')."""
    from mdbridge.geometry.steps import step_parameters_along
    from mdbridge.rod.run import RodRun
    from dna_models.units import AMU, ANGSTROM
    run = RodRun.read(path)
    run.require("time", "s", "centerline", "directors", "fields/Gamma")
    material = None if "initial.bp" in run.attrs else _material_file(path, run)
    if "initial.bp" in run.attrs:
        n_bp = int(run.attrs["initial.bp"])
        sequence = str(run.attrs.get("initial.sequence", "A" * n_bp))
    elif material is not None:
        sequence = material["sequence"]
        n_bp = len(sequence)
    else:
        raise InputError(f"{path}: a rod file without the attribute 'initial.bp' nor a material file with a "
                         "sequence: not a DNA scene, so its base pairs are unknown (a DNA scene's kind, e.g. "
                         "dna_planar, or the material file of `dnarod dna-rod` records them)")
    u = run.units()
    traj = run.trajectory(n_bp, u)
    sl = slice(start, stop, step)
    R, o, P = traj.R[sl], traj.origins[sl], traj.period[sl]
    R_ext = np.concatenate([R, R[:, :1]], axis=1)
    o_ext = np.concatenate([o, o[:, :1] + P[:, None, :]], axis=1)
    q = step_parameters_along(R_ext, o_ext)
    source = str(path)
    closing = np.zeros(n_bp, dtype=bool)
    closing[-1] = True
    ens = StepEnsemble(q=q, sequence=sequence, closed=True,
                       times_ps=traj.times_ps[sl], excluded=closing, source=source)
    extras = {"open_fraction": np.zeros(n_bp), "opened_pairs": np.array([], dtype=int),
              "temperature_K": run.attrs.get("temperature_K"), "n_bp": n_bp}
    h_m = float(run.L) / n_bp * u.ell_A * ANGSTROM
    if material is not None:
        # the grid material per base pair: base pair i sits on grid point i m (docs/dna-rod.md,
        # "On the grid"), its mass and inertia the density and inertia there over one rise
        at_bp = slice(None, None, len(material["rho"]) // n_bp)
        mass = material["rho"][at_bp] * u.rho * h_m / AMU
        inertia = material["I"][at_bp] * u.I * h_m / (AMU * ANGSTROM ** 2)
    elif "material.rho" in run.attrs and "material.I" in run.attrs:
        mass = np.full(n_bp, float(run.attrs["material.rho"]) * u.rho * h_m / AMU)
        inertia = np.tile(np.diag(np.asarray(run.attrs["material.I"], float)) * u.I * h_m / (AMU * ANGSTROM ** 2),
                          (n_bp, 1, 1))
    else:
        return ens, extras
    extras["mass_inertia"] = {"mass": mass, "inertia": inertia, "slice_inertia": inertia,
                              "slice_inertia_err": np.zeros((n_bp, 3, 3)), "hydrogens": True, "frames": 0}
    return ens, extras


def is_steps_file(path) -> bool:
    """A segment's steps.npz (workflows/steps/segments.py reduce): an npz with 'q' and 'columns'."""
    import zipfile
    from pathlib import Path
    p = Path(path)
    if p.suffix != ".npz" or not p.is_file() or not zipfile.is_zipfile(p):
        return False
    with zipfile.ZipFile(p) as z:
        return {"q.npy", "columns.npy"} <= set(z.namelist())


def read_steps_ensemble(run_dir, files, max_open_fraction=MAX_OPEN_FRACTION, leave_out_open_frames=False):
    """StepEnsemble of a long MD kept as its segments' step parameters (steps.npz FILES, in
    time order; mdbridge/md/segments.py read_steps) once its trajectory is gone, and the
    extras read_ensemble gives: the open pairs from the same frames' N1-N3, each base pair's
    mass and inertia (averaged over each segment's frames when it was reduced), the pairs,
    and the run's temperature (RUN_DIR/build.json, the thermostat's reference)."""
    import json
    from pathlib import Path
    from mdbridge.md.integrity import INTACT_CUTOFF_A
    from mdbridge.md.segments import read_steps
    d = Path(run_dir)
    if not (d / "build.json").is_file():
        raise InputError(f"{d}: with steps files the structure is the run's input folder, with its build.json")
    build = json.loads((d / "build.json").read_text())
    r = read_steps(files)
    if r["sequence"] != build["sequence"]:
        raise InputError(f"{files[0]}: its sequence is not the one of {d / 'build.json'}")
    dist = r["n1_n3_A"]
    frac = np.mean(dist > INTACT_CUTOFF_A, axis=0)
    opened = frac > max_open_fraction
    ens = StepEnsemble(q=r["q"], sequence=r["sequence"], closed=True, times_ps=r["times_ps"],
                       opened=steps_of_pairs(opened, True),
                       open_frames=steps_of_pairs(dist > INTACT_CUTOFF_A, True) if leave_out_open_frames else None,
                       source=f"{d} + {len(files)} steps file(s)")
    extras = {"open_fraction": frac, "opened_pairs": np.flatnonzero(opened), "mass_inertia": r["mass_inertia"],
              "pairs": r["pairs"], "temperature_K": float(build["temperature_K"]),
              "temperature_source": f"{d / 'build.json'} (the thermostat's reference)"}
    return ens, extras
