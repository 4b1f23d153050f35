"""DIR/checks.json: is the MD what the build promised, and did it stay a duplex?

- junction O3'-P lengths of both strands over the trajectory (min/max) next to
  the range of all interior O3'-P links: a broken ring closure shows at once;
- NVE energy drift from md.edr (via `gmx energy`; MDAnalysis's EDR reader needs
  pyedr, which Debian does not ship): linear-fit slope and largest excursion;
- fraction of intact Watson-Crick pairs per frame: N1(purine)-N3(pyrimidine)
  < 3.5 A, minimum image (mdbridge/md/integrity.py, the one definition); `integrity`:
  the open fraction over time, per pair and at the junction against the interior; every
  pair's N1-N3 and Watson-Crick H-bond distances per frame in DIR/integrity.npz;
- a --hold-pairs run's restraint energy per frame (`pair_hold`);
- base-pair frames at t = 0 re-analysed from the built structure vs the rod's
  (copied from build.json, where they were measured);
- smallest distance between the duplex and its side-wall images (the images
  displaced across the helix axis) over the trajectory: must exceed the cut-off.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from dna_models.errors import ExternalToolError

from dna_models.units import ANGSTROM_PER_NM as NM
from mdbridge.geometry.analysis_base import AnalysisBase, UniverseFrames
from mdbridge.md.builder.duplex import base_pairs
from dna_models.nucleotides import WATSON_CRICK_HBONDS
from mdbridge.md.integrity import (INTACT_CUTOFF_A, hbond_atoms, n1_n3_columns, hbond_table, integrity_summary,
                                   pair_distances)

from .energy import read_energies
from .junction import o3p_links
from mdbridge.jsonio import write_json


# THE drift of an NVE run, used everywhere (checks.json, report, bench/md_drift.py):
# the least-squares slope of the conserved energy against time over the window
# from DRIFT_FIT_FROM = 10 % of the run to its end, per atom, in kJ/mol/ns. The
# first 10 % hold the start-up transient of a start that is not in equilibrium with
# its velocities (constraints, stiff X-H vibrations); a fraction, not a fixed time,
# so that a 0.2-ps test run and a 600-ps production run are measured alike.
DRIFT_FIT_FROM = 0.1
DRIFT_TARGET_KJ_MOL_NS_ATOM = 0.1   # docs/md.md: ~600 kJ/mol (~5 K) over 600 ps of 10^4 atoms


def fit_drift(t, E, n_atoms: int) -> dict:
    """Drift of the energy series E(t) (kJ/mol, ps) by the one definition above."""
    t = np.asarray(t, float)
    E = np.asarray(E, float)
    late = t >= t[0] + DRIFT_FIT_FROM * (t[-1] - t[0])
    p = np.polyfit(t[late], E[late], 1)
    per_atom = float(p[0]) * 1000.0 / n_atoms
    return {"drift_kJ_mol_per_ps": float(p[0]),
            "drift_kJ_mol_per_ns_per_atom": per_atom,
            "drift_fit_from_ps": float(t[late][0]), "drift_fit_to_ps": float(t[-1]),
            "drift_definition": f"least-squares slope of the conserved energy from "
                                f"{100 * DRIFT_FIT_FROM:g} % of the run to its end, per atom",
            "drift_target_kJ_mol_per_ns_per_atom": DRIFT_TARGET_KJ_MOL_NS_ATOM,
            "drift_within_target": bool(abs(per_atom) <= DRIFT_TARGET_KJ_MOL_NS_ATOM),
            "fluctuation_rms_kJ_mol": float(np.std(E[late] - np.polyval(p, t[late])))}


def energy_drift(directory: Path, gmx: str, n_atoms: int, col: dict | None = None) -> dict:
    """The run's drift record; col: its energies when already read (read_energies)."""
    col = read_energies(directory, gmx) if col is None else col
    t = col["time"]
    E = col.get("Conserved En.", col.get("Total Energy"))
    if E is None:
        raise ExternalToolError(f"{Path(directory) / 'energy.xvg'}: no 'Conserved En.' or 'Total Energy' "
                                f"column (columns: {', '.join(k for k in col if k != 'time')})")
    out = {"times_ps": [float(t[0]), float(t[-1])], "n_frames": int(len(t))}
    if len(t) >= 4:
        out.update(fit_drift(t, E, n_atoms))
        out.update({
            "total_energy_start_kJ_mol": float(E[0]), "total_energy_end_kJ_mol": float(E[-1]),
            "max_abs_deviation_kJ_mol": float(np.abs(E - E[0]).max()),
            "kinetic_energy_start_kJ_mol": float(col["Kinetic En."][0]),
            "max_abs_deviation_over_kinetic_start": float(np.abs(E - E[0]).max()
                                                          / max(abs(col["Kinetic En."][0]), 1e-30)),
            "temperature_K": {"start": float(col["Temperature"][0]), "end": float(col["Temperature"][-1]),
                              "mean": float(col["Temperature"].mean())},
        })
    return out


def _transverse_whole(x, box, axis):
    """Coordinates made continuous across the side walls by following the atom
    order (consecutive atoms are bonded or close); the axis coordinate stays wrapped."""
    d = np.diff(x, axis=0)
    d -= box * np.round(d / box)
    y = np.concatenate([x[:1], x[:1] + np.cumsum(d, axis=0)])
    y[:, axis] = x[:, axis]
    return y


# Width of the slices along the helix axis in min_side_image_distance's branch and bound.
SLICE_A = 10.0


def min_side_image_distance(x_A, box_A, axis: int) -> float:
    """Smallest distance between any atom and any atom of an image displaced
    across the axis (by +-1 box edge in one or both transverse directions); exact.

    Branch and bound over slices of the duplex along the axis: the bounding boxes of two
    slices give a lower bound on any distance between their atoms, slice pairs are searched
    in order of that bound, and the search stops when the bound exceeds the closest pair
    found. On the 158-bp duplex (10,000 atoms, images ~100 A away) this visits a few slice
    pairs, where a whole-structure tree search took ~1 s a frame."""
    box = np.asarray(box_A, float)
    y = _transverse_whole(np.asarray(x_A, float), box, axis)
    y[:, axis] %= box[axis]
    perp = [k for k in range(3) if k != axis]
    n_slices = max(1, int(box[axis] // SLICE_A))
    index = np.minimum((y[:, axis] / box[axis] * n_slices).astype(int), n_slices - 1)
    slices = [y[index == m] for m in range(n_slices)]
    slices = [a for a in slices if len(a)]
    lo = np.array([a.min(axis=0) for a in slices])
    hi = np.array([a.max(axis=0) for a in slices])
    best = np.inf
    # the image shifted by -S pairs the same atoms with their roles swapped: four shifts cover all eight
    for signs in ((1, 0), (0, 1), (1, 1), (1, -1)):
        shift = np.zeros(3)
        shift[perp[0]], shift[perp[1]] = signs[0] * box[perp[0]], signs[1] * box[perp[1]]
        # lower bound between slice m's atoms and slice n's image: box-to-box gaps per direction
        gap = np.maximum(0.0, np.maximum(lo[None, :] + shift - hi[:, None], lo[:, None] - hi[None, :] - shift))
        ax = np.abs(0.5 * (lo[None, :, axis] + hi[None, :, axis]) - 0.5 * (lo[:, None, axis] + hi[:, None, axis]))
        ax = np.minimum(ax, box[axis] - ax)   # centre separation, minimum image along the axis
        half = 0.5 * (hi[:, axis] - lo[:, axis])
        gap[..., axis] = np.maximum(0.0, ax - half[:, None] - half[None, :])
        bound = np.linalg.norm(gap, axis=-1)
        for flat in np.argsort(bound, axis=None):
            m, n = np.unravel_index(flat, bound.shape)
            if bound[m, n] >= best:
                break
            d = slices[n][None, :, :] + shift - slices[m][:, None, :]
            d[..., axis] -= box[axis] * np.round(d[..., axis] / box[axis])
            best = min(best, float(np.sqrt((d * d).sum(axis=-1)).min()))
    return best


class DuplexFrameChecks(AnalysisBase):
    """Per frame of an MD of the closed duplex of N_BP base pairs (its helix along box axis
    AXIS), an analysis of the one loop (mdbridge/geometry/analysis_base.py): results.links,
    the O3'-P links of each frame (`o3p_links`; the box may in principle change, NVE keeps
    it fixed), side_image_A (T,), the smallest distance to a side-wall image, and
    hbond_distance_A (T, m), every Watson-Crick H-bond's distance (mdbridge/md/integrity.py
    hbond_atoms); `pair_distance_A` is its N1-N3 slot (T, n_bp)."""

    def __init__(self, universe, n_bp: int, axis: int, n_dna_atoms: int | None = None):
        super().__init__(UniverseFrames(universe))
        self.universe, self.n_bp, self.axis = universe, n_bp, axis
        # the duplex's atoms (the first ones; in water the solvent follows and fills the box)
        self._dna = slice(0, n_dna_atoms)
        dna = universe.atoms[self._dna]
        self._resid = dna.resids
        self._names = list(dna.names)
        # the DNA's residues only: a GRO file's residue numbers wrap at 100000, so in a large
        # water box solvent residues take the DNA's numbers again
        residue = {int(r.resid): r for r in dna.residues}
        self.pairs = [(residue[i], residue[j]) for i, j in base_pairs(n_bp)]
        self._hb = hbond_atoms(self.pairs)

    def _prepare(self):
        self.results.links = []
        self.results.side_image_A = np.empty(self.n_frames)
        self.results.hbond_distance_A = np.empty((self.n_frames, len(self._hb[0])))

    def _single_frame(self):
        u, r, k = self.universe, self.results, self._frame_index
        x = u.atoms.positions.astype(float)
        box = u.dimensions[:3].astype(float)
        r.side_image_A[k] = min_side_image_distance(x[self._dna], box, self.axis)
        r.hbond_distance_A[k] = pair_distances(self._hb[0].positions, self._hb[1].positions, u.dimensions)
        r.links.append(o3p_links(x[self._dna] / NM, self._resid, self._names, self.n_bp, box / NM))

    def _conclude(self):
        self.results.pair_distance_A = self.results.hbond_distance_A[:, n1_n3_columns(self._hb[2], self._hb[3])]


def _pair_hold_energy(directory: Path, col: dict, build: dict) -> dict | None:
    """The restraint energy of a --hold-pairs run per energy frame (near zero while the duplex
    is intact: the restraints are flat below the open rule; gromacs/pair_hold.py); col: the
    run's energies (read_energies)."""
    if not build.get("pair_hold"):
        return None
    name = build["pair_hold"]["energy_term"]
    if name not in col:
        raise ExternalToolError(f"{Path(directory) / 'md.edr'}: no {name!r} energy in a --hold-pairs run")
    E = np.asarray(col[name], float)
    return {"times_ps": [float(x) for x in col["time"]], "energy_kJ_mol": [float(x) for x in E],
            "mean_kJ_mol": float(E.mean()), "max_kJ_mol": float(E.max()),
            "fraction_of_frames_above_1_kJ_mol": float(np.mean(E > 1.0))}


def write_checks(directory: Path, *, gmx: str) -> dict:
    import MDAnalysis as mda
    d = Path(directory)
    build = json.loads((d / "build.json").read_text())
    n = int(build["n_bp"])
    axis = int(build["box"]["axis"])
    u = mda.Universe(str(d / "conf.gro"), str(d / "md.xtc"))
    # build.json "n_atoms" counts the DNA's atoms (in water, the first ones of conf.gro)
    per_frame = DuplexFrameChecks(u, n, axis, int(build["n_atoms"]) if build.get("solvent") else None).run()
    times, links, side = per_frame.times_ps, per_frame.results.links, per_frame.results.side_image_A
    dist = per_frame.results.pair_distance_A
    junction = {}
    for s in ("I", "II"):
        j = np.array([lk[s]["junction_A"] for lk in links])
        inner = np.array([lk[s]["interior_A"] for lk in links])
        junction[s] = {"junction_min_A": float(j.min()), "junction_max_A": float(j.max()),
                       "interior_min_A": float(inner.min()), "interior_max_A": float(inner.max())}
    energies = read_energies(d, gmx)                  # once, for the drift and the restraint energy
    intact = (dist < INTACT_CUTOFF_A).mean(axis=1)   # (T,) mdbridge/md/integrity.py
    # per pair and frame, as data: N1-N3 and every Watson-Crick H-bond (too large for JSON)
    np.savez_compressed(d / "integrity.npz", times_ps=np.asarray(times, float),
                        n1_n3_A=dist.astype(np.float32),
                        hbond_A=hbond_table(per_frame.pairs, per_frame.results.hbond_distance_A).astype(np.float32),
                        hbond_names=np.array([" ".join(f"{a}-{b}" for a, b in WATSON_CRICK_HBONDS[p]) for p in "AG"]))
    cutoff_A = float(build["md_settings"]["cutoff_nm"]) * NM
    checks = {
        "n_frames": len(times), "times_ps": [float(times[0]), float(times[-1])],
        "junction_O3P": junction,
        "junction_ok": all(v["junction_max_A"] <= v["interior_max_A"] + 0.05
                           and v["junction_min_A"] >= v["interior_min_A"] - 0.05
                           for v in junction.values()),
        "energy": energy_drift(d, gmx, u.atoms.n_atoms, energies),
        "watson_crick": {"criterion": f"N1(purine)-N3(pyrimidine) < {INTACT_CUTOFF_A} A, minimum image",
                         "times_ps": [float(t) for t in times],
                         "fraction_intact": [float(f) for f in intact],
                         "final_fraction_intact": float(intact[-1]),
                         "min_fraction_intact": float(intact.min())},
        "integrity": integrity_summary(dist, times),
        "pair_hold": _pair_hold_energy(d, energies, build),
        "frames_t0_vs_rod": build.get("frames_t0_vs_rod"),
        # which start every number of this run comes from (equilibrate.py)
        "protocol": build.get("protocol", "paper"),
        "equilibration": build.get("equilibration"),
        # in water: the build's checks of the solvent (solvent_checks.py) and the pressure setting
        "solvent": None if not build.get("solvent") else {
            "model": build["solvent"]["model"], "salt_mM": build["solvent"]["salt_mM"],
            "axial_tension_pN": build["md_settings"].get("axial_tension_pN"),
            "build_checks": build["solvent"].get("checks")},
        "side_image": {"min_distance_A": float(min(side)), "cutoff_A": cutoff_A,
                       "ok": bool(min(side) > cutoff_A),
                       "per_frame_A": [float(x) for x in side]},
    }
    write_json(d / "checks.json", checks)
    return checks
