"""StepMaterials from a sequence and a parameter set.

* "paper": the paper's uniform DNA (Sec 2.1-2.2): every step the uniform helix
  of rise 3.38 A and twist 360 deg / 10.533 (158 bp in 15 turns, Sec 6), and
  the step stiffness that maps back to the solver's default material
  K* = diag(C*, D*) exactly (steps_to_rod.step_stiffness), at 300 K (the MD's
  temperature; the rod itself never needs kT). Mass and inertia per base pair
  (mass = "paper", the default): rho h and I h diag(1, 1, 2) (Sec 2.1, Eq 7);
  mass = "atoms": from the builder's all-atom templates (atomic_mass_inertia).
* "olson1998": Olson et al. 1998 PNAS 95:11163 Table 1, dimer-step means and
  6x6 force constants per step XY (dna_models/data/olson1998_steps.toml), at
  the 298 K of the crystal statistics; mass and inertia as for "paper" (they
  are geometry, not statistics).
* a per-step file (stepfile.read_steps), e.g. from the coarse-graining code;
  its sequence must match a given one.

Step i joins base pair i to base pair i + 1 (the last step of a closed DNA joins
base pair n_bp to base pair 1), so its dimer is sequence[i] sequence[i + 1].
"""
from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from dna_models.sequence import validate
from dna_models.units import AMU, ANGSTROM, Units

from .stepfile import StepMaterial, read_steps

DATA = Path(__file__).resolve().parents[3] / "dna_models" / "data"
OLSON_FILE = DATA / "olson1998_steps.toml"
PAPER_TEMPERATURE_K = 300.0


def olson1998_table(path: Path = OLSON_FILE) -> dict:
    """{step 'XY': (mean (6,), F (6, 6))} in the toolkit's order, plus 'temperature_K', 'source'."""
    with open(path, "rb") as f:
        d = tomllib.load(f)
    tab = {k: (np.array(v["mean"], dtype=float), np.array(v["force_constants"], dtype=float))
           for k, v in d["steps"].items()}
    return {"steps": tab, "temperature_K": float(d["temperature_K"]), "source": d["source"]}


def dimers(sequence: str, closed: bool) -> list[str]:
    s = sequence + sequence[0] if closed else sequence
    return [s[i:i + 2] for i in range(len(s) - 1)]


def paper_mass_inertia(n_bp: int, units=None):
    """Per base pair mass [amu] and inertia [amu A^2] of the paper's rod over one rise."""
    u = Units.paper() if units is None else units
    h = u.rise_A * ANGSTROM
    m = u.rho * h / AMU
    I = u.I * h / (AMU * ANGSTROM**2) * np.diag(u.I_ratios)
    return np.full(n_bp, m), np.broadcast_to(I, (n_bp, 3, 3)).copy()


# standard atomic weights (IUPAC 2013 conventional values), amu
ATOMIC_MASS_AMU = {"H": 1.008, "C": 12.011, "N": 14.007, "O": 15.999, "P": 30.974}
MASS_MODELS = ("paper", "atoms")


def atomic_mass_inertia(sequence: str):
    """Per base pair mass [amu] and inertia [amu A^2, about the base-pair origin, in
    base-pair axes] of the all-atom B-DNA templates the builder uses (mdbridge.md.builder:
    heavy atoms + CHARMM27 hydrogens, each nucleotide with its 5' phosphate; no
    counterions), both bases placed on the ideal pair (zero base-pair parameters)."""
    from dna_models.templates import nucleotide_template
    from mdbridge.geometry import base_frames_from_pair
    R_I, o_I, R_II, o_II = base_frames_from_pair(np.zeros(6), np.eye(3), np.zeros(3))
    partner = {"A": "T", "C": "G", "G": "C", "T": "A"}
    cache = {}
    for b in set(sequence):
        xyz, m = [], []
        for base, R, o in ((b, R_I, o_I), (partner[b], R_II, o_II)):
            t = nucleotide_template(base, hydrogens=True)
            xyz.append(t.coords @ R.T + o)
            m.append([ATOMIC_MASS_AMU[e] for e in t.elements])
        r, w = np.concatenate(xyz), np.concatenate(m)
        I = np.einsum("a,ab->", w, r * r) * np.eye(3) - np.einsum("a,ai,aj->ij", w, r, r)
        cache[b] = (w.sum(), I)
    return (np.array([cache[b][0] for b in sequence]), np.array([cache[b][1] for b in sequence]))


def _mass_inertia(sequence, mass, units):
    if mass == "paper":
        return paper_mass_inertia(len(sequence), units)
    if mass == "atoms":
        return atomic_mass_inertia(sequence)
    raise InputError(f"mass model {mass!r}: allowed {', '.join(MASS_MODELS)}")


def paper_steps(sequence: str, closed: bool = True, units=None, mass: str = "paper") -> StepMaterial:
    from .steps_to_rod import step_stiffness
    u = Units.paper() if units is None else units
    seq = validate(sequence)
    n = len(seq) if closed else len(seq) - 1
    tw = 360.0 / u.bp_per_turn_paper
    p = np.tile([0.0, 0.0, u.rise_A, 0.0, 0.0, tw], (n, 1))
    K = np.diag(list(u.C_star) + list(u.D_star))
    F = step_stiffness(np.broadcast_to(K, (n, 6, 6)), p, PAPER_TEMPERATURE_K, u.rise_A, u)
    m, I = _mass_inertia(seq, mass, u)
    return StepMaterial(sequence=seq, closed=closed, step_params=p, stiffness=F,
                        temperature_K=PAPER_TEMPERATURE_K, mass=m, inertia=I,
                        source="paper Sec 2.1-2.2 (uniform; dna_models/data/dna_elastic_constants.toml), "
                               f"twist 360/{u.bp_per_turn_paper:.6g} deg, rise {u.rise_A} A; "
                               f"mass and inertia: {_MASS_SOURCE[mass]}").validate()


_MASS_SOURCE = {"paper": "paper Sec 2.1", "atoms": "all-atom B-DNA templates (no counterions)"}


def olson1998_steps(sequence: str, closed: bool = True, units=None, mass: str = "paper") -> StepMaterial:
    seq = validate(sequence)
    t = olson1998_table()
    ds = dimers(seq, closed)
    p = np.array([t["steps"][d][0] for d in ds])
    F = np.array([t["steps"][d][1] for d in ds])
    m, I = _mass_inertia(seq, mass, units)
    return StepMaterial(sequence=seq, closed=closed, step_params=p, stiffness=F,
                        temperature_K=t["temperature_K"], mass=m, inertia=I,
                        source=t["source"] + f"; mass and inertia: {_MASS_SOURCE[mass]}").validate()


def step_material(sequence: str | None, params: str, closed: bool = True, mass: str = "paper") -> StepMaterial:
    """A StepMaterial for `sequence` under `params` ("paper", "olson1998" or a path to a
    per-step file; with a file, sequence may be None or must equal the file's)."""
    if params == "paper":
        return paper_steps(_need(sequence, params), closed, mass=mass)
    if params == "olson1998":
        return olson1998_steps(_need(sequence, params), closed, mass=mass)
    if not Path(params).is_file():
        raise InputError(f"parameter set {params!r}: not 'paper', 'olson1998' or an existing per-step file")
    if mass != "paper":
        raise InputError(f"parameter set {params!r} is a per-step file: it carries its own mass and inertia "
                         f"(mass model {mass!r} applies to 'paper' and 'olson1998' only)")
    sm = read_steps(params)
    if sequence is not None and validate(sequence) != sm.sequence:
        raise InputError(f"step file '{params}': its sequence ({sm.n_bp} bp, {sm.sequence[:12]}...) differs "
                         f"from the given one ({len(sequence)} bp, {sequence[:12]}...)")
    if sm.closed != closed:
        raise InputError(f"step file '{params}': dataset 'closed' is {sm.closed}, needed {closed}")
    return sm


def _need(sequence, params):
    if sequence is None:
        raise InputError(f"parameter set {params!r} needs a sequence")
    return sequence
