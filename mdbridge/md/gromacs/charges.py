"""Electrostatics variants, applied to the per-strand .itp files pdb2gmx wrote.

"paper" (default): the force field's full charges, -1 e per nucleotide, 1 nm
  cut-off, vacuum (paper Sec 6.2). In vacuum the unscreened phosphate
  repulsion opens base pairs within picoseconds (measured, GROMACS 2022.5: ~30 %
  in 4 ps at 300 K for 158 bp; docs/md.md) - measure it in checks.json.
"neutral-phosphates": +0.5 e on each non-bridging phosphate oxygen (O1P,
  O2P), so every nucleotide is neutral, as if a counterion sat on each
  phosphate. It kept a 158-bp duplex paired (~81 % at 20
  ps); for the 21-bp scene over 20 ps it did not (docs/md.md). Cost to
  fidelity: the backbone-backbone electrostatic repulsion, part of DNA's
  bending/stretching response, is gone; the phosphate's interactions with
  everything else change; the force field is no longer CHARMM27/AMBER as
  published, so elastic properties measured from the MD change too.
"""
from __future__ import annotations

from pathlib import Path

from dna_models.errors import InputError

from ..forcefields import REGISTRY

ELECTROSTATICS = ("paper", "neutral-phosphates")
# +0.5 e on each non-bridging phosphate oxygen, as each registered force field names it
NEUTRALISING_ATOMS = {o: 0.5 for ff in REGISTRY.values() for o in ff.phosphate_oxygens}


def apply_electrostatics(itp: Path, mode: str) -> dict:
    """Rewrite the [ atoms ] charges of ITP for MODE; returns {resnr: new residue charge}."""
    if mode not in ELECTROSTATICS:
        raise InputError(f"--electrostatics {mode!r}: allowed {', '.join(ELECTROSTATICS)}")
    if mode == "paper":
        return {}
    itp = Path(itp)
    out, section = [], None
    qres: dict[int, float] = {}
    for raw in itp.read_text().splitlines():
        s = raw.strip()
        if s.startswith("["):
            section = s.strip("[] ").lower()
        elif section == "atoms" and s and not s.startswith(";") and not s.startswith("#"):
            t = raw.split(";")[0].split()
            q = float(t[6]) + NEUTRALISING_ATOMS.get(t[4], 0.0)
            t[6] = f"{q:.4f}"
            qres[int(t[2])] = qres.get(int(t[2]), 0.0) + q
            raw = "{:>6s} {:>10s} {:>6s} {:>6s} {:>6s} {:>6s} {:>10s} {:>10s}".format(*t[:8]) \
                + ("   " + " ".join(t[8:]) if len(t) > 8 else "")
        out.append(raw)
    itp.write_text("\n".join(out) + "\n")
    return {r: round(q, 4) for r, q in qres.items()}
