"""The run input as GROMACS itself resolved it: `gmx dump -s run.tpr`, parsed.

pdb2gmx's .itp lists bonded terms by atom, and grompp resolves their parameters from the
atom types; only the .tpr holds what mdrun will compute: every atom's type, charge and
mass, the exclusions, and every interaction with its parameters. The ligation junction is
checked here (junction.py `junction_parameters`), not in the .itp.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from dna_models.errors import ExternalToolError

from .gmx import run_gmx

_FUNCTYPE = re.compile(r"^\s*functype\[(\d+)\]=(.*)$")
_ATOM = re.compile(r"^\s*atom\[\s*(\d+)\]=\{type=\s*(\d+),.*?m=\s*(\S+), q=\s*(\S+),.*?resind=\s*(\d+)")
_NAME = re.compile(r'^\s*atom\[(\d+)\]=\{name="([^"]+)"\}')
_RESIDUE = re.compile(r'^\s*residue\[(\d+)\]=\{name="([^"]+)"')
_EXCL = re.compile(r"^\s*excls\[(\d+)\]\[num=\d+\]=\{(.*)$")
_IATOM = re.compile(r"^\s*\d+ type=(\d+) \((\w+)\)\s+([\d ]+)$")


@dataclass
class MolType:
    """One moltype of a dump: per atom (0-based) type, mass, charge, residue index and name;
    residue names; exclusions (atom -> set of atoms); interactions as (kind, functype, atoms)."""
    name: str
    type: list = field(default_factory=list)
    mass: list = field(default_factory=list)
    charge: list = field(default_factory=list)
    resind: list = field(default_factory=list)
    atomname: list = field(default_factory=list)
    resname: list = field(default_factory=list)
    excls: dict = field(default_factory=dict)
    interactions: list = field(default_factory=list)


@dataclass
class Dump:
    functypes: dict                  # functype index -> its parameters as gmx dump prints them
    moltypes: list


def read_dump(text: str) -> Dump:
    """Parse `gmx dump -s` output (GROMACS 2022)."""
    functypes: dict[int, str] = {}
    mols: list[MolType] = []
    excl_atom, excl_buf = None, ""
    for line in text.splitlines():
        if excl_atom is not None:            # an exclusion list continues over lines
            excl_buf += line
            if "}" in line:
                mols[-1].excls[excl_atom] = {int(x) for x in excl_buf.split("}")[0].replace(",", " ").split()}
                excl_atom = None
            continue
        m = _FUNCTYPE.match(line)
        if m:
            functypes[int(m.group(1))] = m.group(2).strip()
            continue
        s = line.strip()
        if s.startswith("moltype (") and s.endswith("):"):
            mols.append(MolType(name=""))
            continue
        if not mols:
            continue
        mol = mols[-1]
        if s.startswith("name=") and not mol.name:
            mol.name = s.split("=", 1)[1].strip().strip('"')
        elif (m := _ATOM.match(line)):
            mol.type.append(int(m.group(2)))
            mol.mass.append(float(m.group(3)))
            mol.charge.append(float(m.group(4)))
            mol.resind.append(int(m.group(5)))
        elif (m := _NAME.match(line)):
            mol.atomname.append(m.group(2))
        elif (m := _RESIDUE.match(line)):
            mol.resname.append(m.group(2))
        elif (m := _EXCL.match(line)):
            excl_atom, excl_buf = int(m.group(1)), m.group(2)
            if "}" in excl_buf:
                mol.excls[excl_atom] = {int(x) for x in excl_buf.split("}")[0].replace(",", " ").split()}
                excl_atom = None
        elif (m := _IATOM.match(line)):
            mol.interactions.append((m.group(2), int(m.group(1)), tuple(int(x) for x in m.group(3).split())))
    if not functypes or not mols:
        raise ExternalToolError("gmx dump: no functype table or no moltype found")
    return Dump(functypes, mols)


def dump_tpr(gmx: str, tpr: Path) -> Dump:
    """`gmx dump -s TPR`, parsed. Its ~20 lines per atom are not kept (gmx_dump.log is
    removed once read)."""
    tpr = Path(tpr)
    proc = run_gmx(gmx, ["dump", "-s", tpr.name], tpr.parent, log_name="gmx_dump.log")
    (tpr.parent / "gmx_dump.log").unlink(missing_ok=True)
    return read_dump(proc.stdout)
