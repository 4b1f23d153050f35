"""Topology of the periodic duplex: pdb2gmx with ring closure, and .itp parsing.

pdb2gmx closes a chain into a ring when the last residue's O3' lies within
`-lb` (a hidden option, nm) of the first residue's P. It measures that
distance WITHOUT periodicity, so with whole (unwrapped) input coordinates and
`-lb` larger than the box every strand comes out cyclic: no termini, -1 e per
nucleotide. Each strand must therefore start with a residue that carries
P/O1P/O2P (the builder writes every nucleotide with its 5' phosphate).
"""
from __future__ import annotations

import shutil
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from dna_models.errors import ExternalToolError, InputError

from ..forcefields import NAMES as FORCEFIELDS, ForceField, forcefield as registered
from .gmx import gmx_top_dir, run_gmx

__all__ = ["FORCEFIELDS", "Molecule", "parse_itp", "write_pdb2gmx_input", "run_pdb2gmx", "read_pdb_chains"]


@dataclass
class Molecule:
    """One [ moleculetype ] of a pdb2gmx .itp: atoms and bonded terms (1-based atom nr)."""
    name: str
    resnr: np.ndarray
    resname: list
    atomname: list
    charge: np.ndarray
    mass: np.ndarray
    terms: dict = field(default_factory=dict)   # kind -> list of tuples of atom nr

    @property
    def residues(self) -> list[int]:
        seen: list[int] = []
        for r in self.resnr:
            if not seen or seen[-1] != r:
                seen.append(int(r))
        return seen


def _term_kind(section: str, funct: int) -> str:
    if section == "dihedrals":
        # CHARMM: 9 = proper (multiple terms), 2 = harmonic improper.
        # AMBER in GROMACS: 9 = proper, 4 = periodic improper.
        return "proper_dihedrals" if funct in (1, 3, 9) else "improper_dihedrals"
    return section


_NATOMS = {"bonds": 2, "pairs": 2, "angles": 3, "dihedrals": 4, "cmap": 5}


def parse_itp(path: Path) -> Molecule:
    """The first moleculetype in an .itp (pdb2gmx output); conditional blocks are skipped."""
    path = Path(path)
    section = None
    name = None
    resnr, resname, atomname, charge, mass = [], [], [], [], []
    terms: dict[str, list] = {}
    skip = 0
    for raw in path.read_text().splitlines():
        ln = raw.split(";")[0].strip()
        if not ln:
            continue
        if ln.startswith("#if"):
            skip += 1
            continue
        if ln.startswith("#endif"):
            skip -= 1
            continue
        if skip or ln.startswith("#"):
            continue
        if ln.startswith("["):
            section = ln.strip("[] ").lower()
            continue
        t = ln.split()
        if section == "moleculetype" and name is None:
            name = t[0]
        elif section == "atoms":
            resnr.append(int(t[2]))
            resname.append(t[3])
            atomname.append(t[4])
            charge.append(float(t[6]))
            mass.append(float(t[7]))
        elif section in _NATOMS:
            n = _NATOMS[section]
            atoms = tuple(int(a) for a in t[:n])
            funct = int(t[n]) if len(t) > n else 1
            terms.setdefault(_term_kind(section, funct), []).append(atoms)
    if name is None or not atomname:
        raise InputError(f"{path}: no [ moleculetype ] with [ atoms ] found")
    return Molecule(name, np.array(resnr), resname, atomname, np.array(charge),
                    np.array(mass), terms)


def write_pdb2gmx_input(path: Path, chains: list[dict], forcefield: str) -> None:
    """PDB for pdb2gmx: one chain per strand, 5'->3', heavy atoms, names for FORCEFIELD.

    chains: [{'id': 'A', 'residues': [(resid, resname, [(atomname, xyz_A), ...]), ...]}, ...]
    with whole (unwrapped) coordinates in Angstrom."""
    ff = registered(forcefield)
    phosphate = set(ff.phosphate)
    out = []
    serial = 0
    for ch in chains:
        for k, (resid, resname, atoms) in enumerate(ch["residues"]):
            names = [a for a, _ in atoms]
            if k == 0 and not phosphate <= {ff.rtp_name(a) for a in names}:
                raise InputError(f"strand {ch['id']}: first residue {resname}{resid} has no "
                                 "5' phosphate (P, O1P/OP1, O2P/OP2); ring closure across the "
                                 "periodic boundary needs it")
            for name, xyz in atoms:
                if name.startswith("H") or (name[0].isdigit() and "H" in name):
                    continue    # pdb2gmx -ignh rebuilds hydrogens from the rtp
                name = ff.rtp_name(name)
                serial += 1
                fname = f" {name:<3s}" if len(name) < 4 else f"{name:<4s}"
                out.append(f"ATOM  {serial % 100000:5d} {fname} {resname:>3s} {ch['id']}"
                           f"{resid % 10000:4d}    {xyz[0]:8.3f}{xyz[1]:8.3f}{xyz[2]:8.3f}"
                           f"  1.00  0.00          {name[0]:>2s}")
        out.append("TER")
    out.append("END")
    Path(path).write_text("\n".join(out) + "\n")


def _local_ff_middle_residues(gmx: str, workdir: Path, ff: ForceField) -> None:
    """A private copy of FF whose dna.r2b maps every DNA residue to its middle
    (phosphate-carrying) building block: pdb2gmx would otherwise give the first and
    last residue the 5'/3' terminal forms (amber's DA5 has no phosphate), which cannot
    be ring-closed. pdb2gmx reads a force field in the working directory before the
    shared one."""
    src = gmx_top_dir(gmx) / f"{ff.name}.ff"
    if not src.is_dir():
        raise ExternalToolError(f"{ff.name}.ff not found in {src.parent} (the force-field "
                                "directory of this gmx)")
    dst = workdir / f"{ff.name}.ff"
    if dst.exists():
        shutil.rmtree(dst)
    shutil.copytree(src, dst)
    lines = ["; dnarod: every DNA residue uses its middle building block (cyclic strands)"]
    for b in ("A", "G", "C", "T"):
        r = ff.residue_names[b]
        lines.append(f"{r}    {r}\t{r}\t{r}\t{r}")
    (dst / "dna.r2b").write_text("\n".join(lines) + "\n")


def pdb2gmx_timeout_s(pdb: Path) -> float:
    """The wall time pdb2gmx gets before it is taken to wait for input: 600 s and 0.2 s per
    atom of the PDB (a 336-bp ring took 17 min of wall time on a machine whose cores were
    busy with other runs)."""
    atoms = sum(1 for line in Path(pdb).read_text().splitlines() if line.startswith(("ATOM", "HETATM")))
    return 600.0 + 0.2 * atoms


def run_pdb2gmx(gmx: str, pdb: Path, workdir: Path, forcefield: str, *, lb_nm: float) -> dict:
    """Run pdb2gmx (vacuum, hydrogens rebuilt, one moleculetype per strand, ring closure
    with -lb LB_NM). Returns {'gro', 'top', 'itps': [...], 'stdout'}."""
    workdir = Path(workdir)
    ff = registered(forcefield)
    args = ["pdb2gmx", "-f", str(Path(pdb).resolve()), "-o", "pdb2gmx.gro", "-p", "topol.top", "-i", "posre.itp",
            "-ff", forcefield, "-water", "none", "-ignh", "-chainsep", "id", "-merge", "no",
            "-lb", f"{lb_nm:.3f}", *ff.pdb2gmx_options]
    if ff.middle_residues_only:
        _local_ff_middle_residues(gmx, workdir, ff)
    # With -ter pdb2gmx asks for each terminus it finds, and spins forever on a closed
    # stdin. Closed rings have no termini; should closure fail, the registry's answers
    # pick "None" for each terminus, pdb2gmx finishes, and the junction check reports
    # the failure.
    proc = run_gmx(gmx, args, workdir, stdin=ff.terminus_answers, log_name="gmx_pdb2gmx.log",
                   timeout_s=pdb2gmx_timeout_s(pdb))
    itps = sorted(workdir.glob("topol_*.itp"))
    if not itps:   # a single chain goes straight into topol.top
        raise ExternalToolError(f"pdb2gmx in {workdir} wrote no per-strand .itp files; "
                                "expected two strands (chains A and B)")
    return {"gro": workdir / "pdb2gmx.gro", "top": workdir / "topol.top", "itps": itps,
            "stdout": proc.stdout}


def read_pdb_chains(path: Path) -> list[dict]:
    """ATOM/HETATM records of a PDB as the `chains` structure of write_pdb2gmx_input,
    in file order (each chain's residues 5'->3' as written)."""
    path = Path(path)
    chains: list[dict] = []
    for ln in path.read_text().splitlines():
        if not ln.startswith(("ATOM", "HETATM")):
            continue
        try:
            name = ln[12:16].strip()
            resname = ln[17:20].strip()
            cid = ln[21]
            resid = int(ln[22:26])
            xyz = (float(ln[30:38]), float(ln[38:46]), float(ln[46:54]))
        except ValueError:
            raise InputError(f"{path}: malformed ATOM record: {ln!r}")
        if not chains or chains[-1]["id"] != cid:
            chains.append({"id": cid, "residues": []})
        res = chains[-1]["residues"]
        if not res or res[-1][0] != resid:
            res.append((resid, resname, []))
        res[-1][2].append((name, xyz))
    return chains
