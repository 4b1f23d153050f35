"""Holding the Watson-Crick pairs closed with the same force field: flat-bottomed restraints.

In the full-charge vacuum setting (the paper's) the duplex frays: pairs open and the broken
steps enter every analysis as non-rod motion (docs/intact.md). `build-md
--hold-pairs` adds, for every Watson-Crick hydrogen bond of every pair (donor-acceptor
heavy atoms, dna_models.nucleotides.WATSON_CRICK_HBONDS), GROMACS's flat-bottomed
"restraint potential" (bonds type 10):

    V(r) = 0                               r <= up1
         = k (r - up1)^2 / 2               up1 < r <= up2
         = k (up2 - up1) (2 r - up2 - up1) / 2   r > up2 (a constant pull)

It exerts no force while a pair is closed (an intact pair's N1-N3 is ~2.97 +- 0.12 A, its
flat bottom ends at 3.4 A), and on N1-N3 it acts below the 3.5-A open rule of
mdbridge/md/integrity.py, so a held pair never counts as open (PairHold). The restraints go into topol.top's
[ intermolecular_interactions ] (the two strands are separate molecules): an interaction
type that generates no exclusions, so every non-bonded pair of the force field is kept
(tests/python/test_md_pair_hold.py compares the run input's exclusions with and without).
GROMACS reports their energy as "Restraint Pot." in md.edr; checks.json has it per frame.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path

from dna_models.errors import DnarodError, InputError
from dna_models.nucleotides import PURINES, WATSON_CRICK_HBONDS
from dna_models.units import ANGSTROM_PER_NM as NM
from mdbridge.geometry.structure import dna_base
from mdbridge.md.integrity import INTACT_CUTOFF_A

from .topology import Molecule

SECTION = "[ intermolecular_interactions ]"
ENERGY_TERM = "Restraint Pot."     # gmx energy's name of the bonds-type-10 energy


@dataclass(frozen=True)
class PairHold:
    """The flat-bottomed restraint on each Watson-Crick H-bond distance (A, kJ/mol/nm^2).

    up1_A, on N1-N3, lies below the open rule (INTACT_CUTOFF_A), so a held pair never counts
    as open; other_up1_A, on the other H-bonds, lies beyond their thermal range, so they
    only keep an opening pair from turning about N1-N3. Both flat bottoms were set from the
    distances of a held 158-bp full-charge run (docs/intact.md, "Holding the pairs"): intact
    N1-N3 2.97 +- 0.12 A, the others 2.91-3.01 +- 0.16-0.19 A (99th percentiles 3.32-3.48 A);
    a flat bottom at 3.3 A on every bond was touched by 1-9 % of the frames of intact pairs.
    Past up + width_A the pull is constant."""
    up1_A: float = 3.4
    other_up1_A: float = 3.8
    width_A: float = 0.5
    k_kJ_mol_nm2: float = 40000.0

    def __post_init__(self):
        if not (0 < self.up1_A < INTACT_CUTOFF_A):
            raise InputError(f"pair hold: up1 {self.up1_A} A must lie in (0, {INTACT_CUTOFF_A}) A, "
                             "below the open-pair rule, so that a held pair never counts as open")
        if not (self.other_up1_A > 0 and self.width_A > 0):
            raise InputError(f"pair hold: other_up1 {self.other_up1_A} A and width {self.width_A} A "
                             "must be > 0")
        if not self.k_kJ_mol_nm2 > 0:
            raise InputError(f"pair hold: k {self.k_kJ_mol_nm2} kJ/mol/nm^2 must be > 0")

    def up1_of(self, purine_atom: str, pyrimidine_atom: str) -> float:
        return self.up1_A if (purine_atom, pyrimidine_atom) == ("N1", "N3") else self.other_up1_A

    def as_dict(self) -> dict:
        return {**asdict(self), "gromacs": "bonds type 10 (restraint potential), low 0, up2 = up1 + width",
                "section": SECTION, "energy_term": ENERGY_TERM}


def hbond_atom_pairs(mols: list[Molecule], n_bp: int) -> list[tuple[int, int, int, str, str]]:
    """[(global atom nr i, global atom nr j (1-based, topol.top order), pair index (0-based),
    name i, name j)] of every Watson-Crick H-bond. mols: strand I then strand II, one copy
    each, residues 5'->3'; pair k = strand I residue k with strand II residue n - 1 - k."""
    residues: list[dict[str, int]] = []      # per residue over both strands: name -> global nr
    resnames: list[str] = []
    offset = 0
    for m in mols:
        last = None
        for i, (r, name) in enumerate(zip(m.resnr, m.atomname)):
            if r != last:
                residues.append({})
                resnames.append(m.resname[i])
                last = r
            residues[-1][name] = offset + i + 1
        offset += len(m.atomname)
    if len(residues) != 2 * n_bp:
        raise DnarodError(f"pair hold: the topology has {len(residues)} residues, expected 2 x {n_bp}")
    out = []
    for k in range(n_bp):
        a, b = k, 2 * n_bp - 1 - k
        if dna_base(resnames[a], f"pair {k}") not in PURINES:
            a, b = b, a                      # the purine first, as the table is keyed
        pu, py = dna_base(resnames[a], f"pair {k}"), dna_base(resnames[b], f"pair {k}")
        if {pu, py} not in ({"A", "T"}, {"G", "C"}):
            raise InputError(f"pair {k}: {resnames[a]}-{resnames[b]} is not a Watson-Crick pair")
        for na, nb in WATSON_CRICK_HBONDS[pu]:
            try:
                out.append((residues[a][na], residues[b][nb], k, na, nb))
            except KeyError as e:
                raise DnarodError(f"pair hold: atom {e.args[0]} missing in residue "
                                  f"{resnames[a] if e.args[0] == na else resnames[b]} of pair {k}")
    return out


def add_pair_hold(top: Path, mols: list[Molecule], n_bp: int, hold: PairHold) -> dict:
    """Append the restraints to TOP (after [ molecules ], as GROMACS requires) and return
    build.json's record of them."""
    top = Path(top)
    text = top.read_text()
    if SECTION in text:
        raise DnarodError(f"{top}: already has {SECTION}")
    bonds = hbond_atom_pairs(mols, n_bp)
    lines = ["", "; dnarod build-md --hold-pairs: flat-bottomed restraints on the Watson-Crick",
             "; H-bond distances (mdbridge/md/gromacs/pair_hold.py); no exclusions", SECTION,
             "[ bonds ]", ";   ai     aj  type  low    up1    up2    kdr   ; pair, atoms"]
    for i, j, k, na, nb in bonds:
        up1 = hold.up1_of(na, nb)
        lines.append(f"{i:6d} {j:6d}  10  0.0  {up1 / NM:.4f} {(up1 + hold.width_A) / NM:.4f} "
                     f"{hold.k_kJ_mol_nm2:g}  ; {k} {na}-{nb}")
    top.write_text(text.rstrip("\n") + "\n" + "\n".join(lines) + "\n")
    return {**hold.as_dict(), "n_restraints": len(bonds), "n_pairs": n_bp}
