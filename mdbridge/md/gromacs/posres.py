"""Position restraints on base heavy atoms, for the restrained minimisation.

The rod fixes where each base pair is; the backbone of a duplex built from
rigid nucleotide templates can clash at steps that are bent or sheared. Holding
the base heavy atoms (which define the base-pair frames) while steepest descent
relaxes everything else removes the clashes without moving the frames much.
"""
from __future__ import annotations

from pathlib import Path

from ..forcefields import REGISTRY
from .topology import Molecule

# the phosphate as each registered force field's dna.rtp names it, and the sugar
BACKBONE_SUGAR = {*(a for ff in REGISTRY.values() for a in ff.phosphate),
                  "O5'", "C5'", "C4'", "O4'", "C3'", "O3'", "C2'", "C1'"}
DEFINE = "POSRES_BASES"


def is_base_heavy_atom(name: str) -> bool:
    return not name.startswith("H") and name not in BACKBONE_SUGAR


def add_base_restraints(itp: Path, mol: Molecule, k_kj_mol_nm2: float = 100000.0) -> int:
    """Write posre_bases_<molecule>.itp and include it in ITP under #ifdef POSRES_BASES.
    Returns the number of restrained atoms."""
    itp = Path(itp)
    idx = [i + 1 for i, n in enumerate(mol.atomname) if is_base_heavy_atom(n)]
    name = f"posre_bases_{mol.name}.itp"
    lines = [f"; base heavy atoms of {mol.name}, restrained in em.mdp (define = -D{DEFINE})",
             "[ position_restraints ]", ";  ai  funct  fcx  fcy  fcz"]
    lines += [f"{i:6d}     1  {k_kj_mol_nm2:g}  {k_kj_mol_nm2:g}  {k_kj_mol_nm2:g}" for i in idx]
    (itp.parent / name).write_text("\n".join(lines) + "\n")
    text = itp.read_text()
    if name not in text:
        text += f"\n; base heavy atoms (dnarod restrained minimisation)\n#ifdef {DEFINE}\n" \
                f"#include \"{name}\"\n#endif\n"
        itp.write_text(text)
    return len(idx)
