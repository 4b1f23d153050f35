"""Water and ions around the built periodic duplex: `gmx solvate`, then `gmx genion`.

The DNA's own topology is left exactly as the vacuum build has it (topology.py,
charges.py, posres.py): the water model's and the ions' .itp files of the force field
are included after the strands, and the solvent's molecules come after the DNA in
[ molecules ] and in the coordinates, so the DNA's atoms are first, in the vacuum
build's order (checked: solvent_checks.py).

Ion counts (`ion_counts`), one rule: the salt pairs come from the concentration C and
the volume of the water that `gmx solvate` put in the box,

    N_salt = round(N_water C / [H2O]),  [H2O] = WATER_MOLARITY_M (pure water at 300 K),

i.e. C moles of salt per litre of that water; the neutralising counterions come on top
(N_cation = N_salt + max(0, -Q), N_anion = N_salt + max(0, Q), Q the DNA's charge in
e). genion then replaces N_cation + N_anion waters by ions at random (its -seed is the
build's), at least 0.6 nm from each other (genion's -rmin default).

Water inside the duplex: solvate keeps water out of the solute by van der Waals radii
(vdwradii.dat, scaled by 0.57), which on the built duplex leaves water oxygens ~1.9 A
from base ring atoms (measured, 21 bp). Every water whose oxygen lies within
WATER_RING_MIN_A of a base's ring atom is removed before the ions are placed;
solvent_checks.py measures the same distance again on the final conf.gro.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from dna_models.errors import DnarodError, InputError

from ..forcefields import WATER_MODELS, ForceField, forcefield as registered
from .gmx import run_gmx
from .gro import Gro, read_gro, write_gro

VACUUM = "vacuum"
SOLVENTS = (VACUUM,) + WATER_MODELS
# pure water at 300 K (the build's temperature): 996.5 g/L / 18.015 g/mol
WATER_MOLARITY_M = 996.5 / 18.015
RING_ATOMS = ("N1", "C2", "N3", "C4", "C5", "C6")   # the six-membered ring every base has
WATER_RING_MIN_A = 2.5
ION_COUNT_RULE = ("N_salt = round(N_water C / [H2O]) with [H2O] = 996.5 g/L / 18.015 g/mol = 55.32 mol/L and "
                  "N_water the waters gmx solvate placed (less those removed from the duplex); N_cation = N_salt "
                  "+ max(0, -Q), N_anion = N_salt + max(0, Q), Q the DNA's charge")


@dataclass(frozen=True)
class Solvent:
    """The solvent of a build: a water model of the force field and the salt (NaCl-type,
    the force field's cation and anion) concentration on top of the counterions."""
    model: str
    salt_mM: float = 0.0

    def check(self, ff: ForceField) -> None:
        """InputError (in the command's spelling) for a model the force field does not
        have or a salt concentration that is negative or not finite."""
        if not (math.isfinite(self.salt_mM) and self.salt_mM >= 0):
            raise InputError(f"--salt-mM {self.salt_mM}: must be a finite concentration >= 0 mM")
        if self.model not in ff.water_models:
            raise InputError(f"--solvent {self.model!r}: not a water model of {ff.name}; allowed: "
                             f"{', '.join((VACUUM,) + tuple(ff.water_models))}")

    def as_dict(self) -> dict:
        return asdict(self)


def solvent_of(model: str | None, salt_mM: float, ff_name: str) -> Solvent | None:
    """The build's Solvent from the command's --solvent and --salt-mM (None: vacuum),
    checked before any work: a salt without water, or a bad value, is an InputError."""
    if model is None or model == VACUUM:
        if salt_mM:
            raise InputError(f"--salt-mM {salt_mM}: salt needs water; add --solvent "
                             f"{' or '.join(WATER_MODELS)}")
        return None
    solvent = Solvent(model, float(salt_mM))
    solvent.check(registered(ff_name))
    return solvent


def check_medium(solvent: Solvent | None, *, axial_tension_pN: float | None, thermostat: bool,
                 axial_pressure: bool) -> None:
    """The choices that go with the medium, checked before any work (InputError): a tension is
    held by the water's barostat (so it needs water, and a thermostat: C-rescale draws its
    noise at the thermostat's temperature); the vacuum's axis-only barostat is not for water."""
    if axial_tension_pN is not None:
        if solvent is None:
            raise InputError("--axial-tension-pN: a tension is held by the water's barostat; add --solvent "
                             f"{' or '.join(WATER_MODELS)}")
        if not math.isfinite(axial_tension_pN):
            raise InputError(f"--axial-tension-pN {axial_tension_pN}: must be finite")
        if not thermostat:
            raise InputError("--axial-tension-pN needs --thermostat: the C-rescale barostat draws its noise at the "
                             "thermostat's temperature")
    if solvent is not None and axial_pressure:
        raise InputError("--axial-pressure finds the vacuum duplex's zero-tension length; in water use "
                         "--axial-tension-pN 0 --thermostat")


def salt_pairs(n_water: int, salt_mM: float) -> int:
    """N_salt = round(N_water C / [H2O]) (module doc)."""
    return int(round(n_water * salt_mM * 1e-3 / WATER_MOLARITY_M))


def ion_counts(n_water: int, salt_mM: float, charge_e: float) -> dict:
    """Cations and anions that neutralise CHARGE_E and add salt at SALT_MM in N_WATER
    waters (module doc); the charge must be an integer within 1e-3 e."""
    q = int(round(charge_e))
    if abs(charge_e - q) > 1e-3:
        raise DnarodError(f"the DNA's charge {charge_e:.4f} e is not an integer: cannot neutralise it with ions")
    n = salt_pairs(n_water, salt_mM)
    return {"n_salt_pairs": n, "n_cation": n + max(0, -q), "n_anion": n + max(0, q), "dna_charge_e": q,
            "n_water_for_salt": int(n_water), "rule": ION_COUNT_RULE}


def ring_atoms(names, resnames, water_residue: str, ion_residues=()) -> np.ndarray:
    """Indices of the base ring atoms (RING_ATOMS) of the DNA's residues."""
    skip = {water_residue, *ion_residues}
    return np.array([i for i, (n, r) in enumerate(zip(names, resnames)) if r not in skip and n in RING_ATOMS],
                    dtype=int)


def waters_near_rings(x_nm, box_nm, names, resnames, water_residue: str, cut_A: float = WATER_RING_MIN_A):
    """(indices of the water oxygens within CUT_A of a base ring atom, their distances in A),
    minimum image in the orthorhombic box. A water oxygen is the first atom of its molecule."""
    from scipy.spatial import cKDTree
    box = np.asarray(box_nm, float)
    x = np.mod(np.asarray(x_nm, float), box)
    ring = ring_atoms(names, resnames, water_residue)
    ow = np.array([i for i, (n, r) in enumerate(zip(names, resnames)) if r == water_residue and n == "OW"], dtype=int)
    if len(ring) == 0 or len(ow) == 0:
        return ow[:0], np.zeros(0)
    d, _ = cKDTree(x[ring], boxsize=box).query(x[ow], distance_upper_bound=cut_A / 10.0)
    near = np.isfinite(d)
    return ow[near], d[near] * 10.0


def _remove_residues(g: Gro, first_atoms: np.ndarray, size: int) -> Gro:
    drop = np.zeros(g.n_atoms, bool)
    for i in first_atoms:
        drop[i:i + size] = True
    keep = ~drop
    return Gro(g.title, g.resid[keep], [r for r, k in zip(g.resname, keep) if k],
               [n for n, k in zip(g.name, keep) if k], g.x[keep], None if g.v is None else g.v[keep], g.box)


def _include_solvent(top: Path, ff: ForceField, solvent: Solvent, n_water: int) -> None:
    """The water model's and the ions' .itp after the DNA's includes; the waters after the
    DNA in [ molecules ]."""
    lines = top.read_text().splitlines()
    last = max(k for k, ln in enumerate(lines) if ln.startswith("#include"))
    lines[last + 1:last + 1] = ["", f"; dnarod: water ({solvent.model}) and ions of {ff.name} (gromacs/solvent.py)",
                                f'#include "{ff.name}.ff/{ff.water(solvent.model).itp}"',
                                f'#include "{ff.name}.ff/{ff.ions_itp}"']
    lines.append(f"{ff.water(solvent.model).residue:<20s}{n_water}")
    top.write_text("\n".join(lines) + "\n")


def solvate(outdir: Path, gmx: str, dna: Gro, *, ff: ForceField, solvent: Solvent, charge_e: float,
            ions_mdp: str, seed: int) -> tuple[Gro, dict]:
    """Fill DNA's box with water, remove the waters inside the duplex, and replace waters by
    the ions of `ion_counts`; updates OUTDIR/topol.top. IONS_MDP: an mdp that grompp accepts
    for the charged, solvated system (only genion reads its run input: the vacuum one serves).
    Returns the solvated structure (the DNA's atoms first, unchanged) and build.json's record."""
    d = Path(outdir)
    water = ff.water(solvent.model)
    write_gro(d / "solute.gro", Gro("dnarod: the duplex before solvation", dna.resid, dna.resname, dna.name,
                                    dna.x, None, dna.box))
    run_gmx(gmx, ["solvate", "-cp", "solute.gro", "-cs", water.coordinates, "-o", "solvated_raw.gro"], d,
            log_name="gmx_solvate.log")
    raw = read_gro(d / "solvated_raw.gro")
    n_dna = dna.n_atoms
    if raw.name[:n_dna] != dna.name or (raw.n_atoms - n_dna) % len(water.atoms) \
            or any(r != water.residue for r in raw.resname[n_dna:]):
        raise DnarodError(f"{d / 'solvated_raw.gro'}: gmx solvate did not keep the duplex first, followed by "
                          f"{water.residue} only")
    raw.x[:n_dna] = dna.x          # the duplex whole, as built (solvate may put atoms into the box)
    inside, _ = waters_near_rings(raw.x, raw.box, raw.name, raw.resname, water.residue)
    g = _remove_residues(raw, inside, len(water.atoms))
    n_water = (g.n_atoms - n_dna) // len(water.atoms)
    g.resid[n_dna:] = np.repeat(dna.resid.max() + 1 + np.arange(n_water), len(water.atoms))
    write_gro(d / "solvated.gro", g)
    _include_solvent(d / "topol.top", ff, solvent, n_water)
    ions = ion_counts(n_water, solvent.salt_mM, charge_e)
    rec = {"model": solvent.model, "salt_mM": solvent.salt_mM, "water_itp": f"{ff.name}.ff/{water.itp}",
           "ions_itp": f"{ff.name}.ff/{ff.ions_itp}", "cation": ff.cation.molecule, "anion": ff.anion.molecule,
           "n_water_solvate": (raw.n_atoms - n_dna) // len(water.atoms),
           "n_water_removed_inside_duplex": int(len(inside)),
           "removal_rule": f"water oxygen within {WATER_RING_MIN_A} A of a base ring atom ({', '.join(RING_ATOMS)})",
           "ions": ions}
    if ions["n_cation"] + ions["n_anion"] == 0:
        rec["n_water"] = n_water
        return g, rec
    (d / "ions.mdp").write_text(ions_mdp)
    run_gmx(gmx, ["grompp", "-f", "ions.mdp", "-c", "solvated.gro", "-p", "topol.top", "-o", "ions.tpr",
                  "-po", "ions_out.mdp", "-maxwarn", "0"], d, log_name="gmx_grompp_ions.log")
    run_gmx(gmx, ["genion", "-s", "ions.tpr", "-o", "ionised.gro", "-p", "topol.top", "-pname", ff.cation.molecule,
                  "-nname", ff.anion.molecule, "-np", str(ions["n_cation"]), "-nn", str(ions["n_anion"]),
                  "-seed", str(seed % (2**31 - 1) + 1)], d, stdin=f"{water.residue}\n", log_name="gmx_genion.log")
    for p in ("ions.tpr", "ions_out.mdp", "ions.mdp", *(q.name for q in d.glob("#topol.top.*#"))):
        (d / p).unlink(missing_ok=True)     # genion's backup of the topology it edited too
    out = read_gro(d / "ionised.gro")
    out.x[:n_dna] = dna.x
    rec["n_water"] = n_water - ions["n_cation"] - ions["n_anion"]
    return out, rec
