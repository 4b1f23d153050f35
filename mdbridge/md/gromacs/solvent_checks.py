"""The checks of a solvated build (build.json "solvent.checks", copied into checks.json).

- total charge zero: the sum of the charges in the run input grompp made (read back from
  the .tpr by MDAnalysis, not from dnarod's own bookkeeping), |Q| < 1e-3 e;
- ion counts: the cations and anions in conf.gro are those of the rule
  (solvent.py ion_counts) for the salt concentration and the water volume;
- no water inside the duplex: no water oxygen within WATER_RING_MIN_A of a base's ring
  atom (N1, C2, N3, C4, C5, C6) in conf.gro, minimum image;
- the DNA first and as in vacuum: [ molecules ] starts with the DNA's molecules, once each,
  followed by water and ions only; the DNA's .itp files are byte for byte those the vacuum
  build writes (their digests before solvation); conf.gro's first atoms are the DNA's, in
  the vacuum topology's order (residue numbers and names).
The junction's check is the vacuum build's (junction.py junction_parameters), on the same
run input.
"""
from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np

from .gro import Gro
from .solvent import WATER_MOLARITY_M, WATER_RING_MIN_A, ion_counts, waters_near_rings

AVOGADRO = 6.02214076e23

CHARGE_TOLERANCE_E = 1e-3


def file_digests(paths) -> dict[str, str]:
    """sha256 of each file, by name."""
    return {Path(p).name: hashlib.sha256(Path(p).read_bytes()).hexdigest() for p in paths}


def total_charge_check(tpr: Path) -> dict:
    """The run input's total charge, from the .tpr itself."""
    import warnings
    import MDAnalysis as mda
    with warnings.catch_warnings():     # a .tpr read for its topology only: no coordinates wanted
        warnings.simplefilter("ignore", UserWarning)
        q = float(mda.Universe(str(tpr)).atoms.charges.sum())
    return {"total_charge_e": round(q, 6), "tolerance_e": CHARGE_TOLERANCE_E, "source": "the run input (.tpr)",
            "ok": bool(abs(q) < CHARGE_TOLERANCE_E)}


def ion_count_check(g: Gro, record: dict, *, cation: str, anion: str, salt_mM: float) -> dict:
    """The ions in G against the rule for the record's water count and DNA charge, and the
    salt concentration they make in that water's volume."""
    ions = record["ions"]
    want = ion_counts(ions["n_water_for_salt"], salt_mM, ions["dna_charge_e"])
    have = {"n_cation": sum(1 for r in g.resname if r == cation), "n_anion": sum(1 for r in g.resname if r == anion)}
    volume_L = ions["n_water_for_salt"] / (WATER_MOLARITY_M * AVOGADRO)
    n_salt = min(have["n_cation"], have["n_anion"])
    return {"expected": {k: want[k] for k in ("n_cation", "n_anion", "n_salt_pairs")}, "found": have,
            "water_volume_nm3": round(volume_L * 1e24, 3), "salt_asked_mM": salt_mM,
            "salt_realised_mM": round(1e3 * n_salt / AVOGADRO / volume_L, 3) if volume_L > 0 else 0.0,
            "rule": want["rule"], "ok": have == {k: want[k] for k in ("n_cation", "n_anion")}}


def water_in_duplex_check(g: Gro, water_residue: str) -> dict:
    """Water oxygens within WATER_RING_MIN_A of a base ring atom in G."""
    idx, d = waters_near_rings(g.x, g.box, g.name, g.resname, water_residue)
    return {"criterion": f"no water oxygen within {WATER_RING_MIN_A} A of a base ring atom (N1 C2 N3 C4 C5 C6)",
            "n_water_oxygens_near_rings": int(len(idx)),
            "closest_A": None if len(d) == 0 else round(float(d.min()), 3),
            "atoms": [int(i) + 1 for i in idx[:20]], "ok": len(idx) == 0}


def molecules_section(top: Path) -> list[tuple[str, int]]:
    """[ molecules ] of a topology: (name, count) in order."""
    out, on = [], False
    for raw in Path(top).read_text().splitlines():
        ln = raw.split(";")[0].strip()
        if ln.startswith("["):
            on = ln.strip("[] ").lower() == "molecules"
        elif on and ln:
            t = ln.split()
            out.append((t[0], int(t[1])))
    return out


def dna_first_check(top: Path, conf: Gro, dna: Gro, dna_molecules: list[str], itp_digests: dict[str, str],
                    solvent_molecules: set[str], solvent_residues: set[str]) -> dict:
    """The DNA's own topology as in vacuum, its atoms first in the vacuum order (module doc)."""
    mols = molecules_section(top)
    head = mols[:len(dna_molecules)]
    rest = {name for name, _ in mols[len(dna_molecules):]}
    now = file_digests(Path(top).parent / name for name in itp_digests)
    n = dna.n_atoms
    same_atoms = (conf.n_atoms >= n and conf.name[:n] == dna.name and conf.resname[:n] == dna.resname
                  and bool(np.all(conf.resid[:n] == dna.resid)))
    after_dna = set(conf.resname[n:]) <= solvent_residues
    checks = {"molecules_dna_first": head == [(m, 1) for m in dna_molecules],
              "molecules_after_dna_are_solvent": rest <= solvent_molecules,
              "dna_itp_unchanged": now == itp_digests,
              "conf_dna_atoms_first_in_vacuum_order": same_atoms and after_dna}
    return {**checks, "molecules": [[m, c] for m, c in mols], "dna_itp_sha256": itp_digests, "n_dna_atoms": n,
            "ok": all(checks.values())}
