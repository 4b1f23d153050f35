"""The force-field registry (mdbridge/md/forcefields.py) against the GROMACS force-field folders
it describes: bond constants (ffnabonded.itp / ffbonded.itp, through the atom types dna.rtp
gives the O3'-P atoms), residue and atom names (dna.rtp), water models (watermodels.dat and
the model's .itp) and ions (ions.itp). A registry with a planted wrong fact must fail."""
from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import pytest

from dna_models.nucleotides import bdna_nucleotide
from mdbridge.md import forcefields as ffs
from mdbridge.md.gromacs.gmx import gmx_top_dir


@pytest.fixture(scope="module")
def top(gmx) -> Path:
    return gmx_top_dir(gmx)


def _sections(text: str) -> list[tuple[str, list[list[str]]]]:
    """[ section ] blocks of a GROMACS file, in order, each with its split data lines
    (comments dropped, #ifdef'd lines kept)."""
    out: list[tuple[str, list[list[str]]]] = []
    for raw in text.splitlines():
        ln = raw.split(";")[0].strip()
        if not ln or ln.startswith("#"):
            continue
        m = re.match(r"\[\s*(\S+)\s*\]", ln)
        if m:
            out.append((m.group(1), []))
        elif out:
            out[-1][1].append(ln.split())
    return out


def _rtp_atoms(folder: Path, resname: str) -> dict[str, str]:
    """atom name -> atom type of residue RESNAME of dna.rtp."""
    secs = _sections((folder / "dna.rtp").read_text())
    for k, (name, _) in enumerate(secs):
        if name == resname:
            assert secs[k + 1][0] == "atoms"
            return {t[0]: t[1] for t in secs[k + 1][1]}
    raise AssertionError(f"{folder}/dna.rtp: no residue {resname}")


def _bonded(folder: Path, kind: str, types: tuple[str, ...]) -> list[float]:
    """The parameters of the bond or angle between atom TYPES in the folder's bonded files."""
    n = len(types)
    for f in sorted(folder.glob("*bonded.itp")):
        for sec, rows in _sections(f.read_text()):
            if sec != kind:
                continue
            for t in rows:
                if tuple(t[:n]) in (types, types[::-1]):
                    return [float(x) for x in t[n + 1:]]
    raise AssertionError(f"{folder}: no {kind} {'-'.join(types)}")


def _molecules(path: Path) -> dict[str, list[str]]:
    """moleculetype -> its first [ atoms ] row of an .itp."""
    out, current = {}, None
    for sec, rows in _sections(path.read_text()):
        if sec == "moleculetype":
            current = rows[0][0]
        elif sec == "atoms" and current and rows:
            out.setdefault(current, rows[0])
    return out


def check(ff: ffs.ForceField, top: Path) -> None:
    """Every fact of FF against its GROMACS folder in TOP; an AssertionError on the first wrong one."""
    folder = top / f"{ff.name}.ff"
    assert folder.is_dir(), folder
    for base, resname in ff.residue_names.items():
        rtp = _rtp_atoms(folder, resname)
        heavy = {ff.rtp_name(a) for a in bdna_nucleotide(base)}
        assert heavy <= set(rtp), f"{ff.name} {resname}: builder atoms not in dna.rtp: {heavy - set(rtp)}"
        assert set(ff.phosphate) <= set(rtp), f"{ff.name} {resname}: phosphate {ff.phosphate}"
    # the O3'(i)-P(i+1) bond and the two angles, through the atom types of dna.rtp's DA
    t = _rtp_atoms(folder, ff.residue_names["A"])
    o3, p, c3, o5 = t["O3'"], t["P"], t["C3'"], t["O5'"]
    b0, kb = _bonded(folder, "bondtypes", (o3, p))[:2]
    assert (b0, kb) == (ff.o3_p.length_nm, ff.o3_p.k_kJ_mol_nm2), f"{ff.name} O3'-P {b0} {kb}"
    assert _bonded(folder, "angletypes", (c3, o3, p))[0] == ff.angle_c3_o3_p_deg, f"{ff.name} C3'-O3'-P"
    assert _bonded(folder, "angletypes", (o3, p, o5))[0] == ff.angle_o3_p_o5_deg, f"{ff.name} O3'-P-O5'"
    # water models: listed in watermodels.dat, with the registered residue and atoms
    listed = [ln.split()[0] for ln in (folder / "watermodels.dat").read_text().splitlines() if ln.strip()]
    assert ff.default_water in ff.water_models
    for w in ff.water_models.values():
        assert w.name in listed, f"{ff.name}: water {w.name} not in watermodels.dat"
        secs = [rows for sec, rows in _sections((folder / f"{w.name}.itp").read_text()) if sec in
                ("moleculetype", "atoms")]
        assert secs[0][0][0] == w.residue
        assert tuple(r[4] for r in secs[1][:len(w.atoms)]) == w.atoms and all(r[3] == w.residue for r in secs[1])
        assert (top / w.coordinates).is_file(), f"{ff.name}: no water box {w.coordinates} for {w.name}"
    assert (folder / ff.ions_itp).is_file()
    # ions: molecule, residue, atom name, type and charge as ions.itp has them
    mols = _molecules(folder / "ions.itp")
    for ion in (ff.cation, ff.anion):
        row = mols.get(ion.molecule)
        assert row is not None, f"{ff.name}: no ion {ion.molecule}"
        assert (row[1], row[3], row[4], float(row[6])) == (ion.atomtype, ion.residue, ion.atom, ion.charge_e), \
            f"{ff.name} ion {ion.molecule}: ions.itp has {row}"


@pytest.mark.parametrize("name", ffs.NAMES)
def test_registry_matches_the_gromacs_folder(name, top):
    check(ffs.forcefield(name), top)


@pytest.mark.parametrize("plant", [
    {"o3_p": ffs.Bond(0.160, 225000.0)},
    {"angle_o3_p_o5_deg": 104.0},
    {"renames": ffs.AMBER99SB_ILDN.renames},
    {"cation": ffs.Ion("NA", "NA", "NA", "Na", 1.0)},
    {"water_models": {"tip3p": ffs.WaterModel("tip3p", atoms=("OW", "HW", "HW"))}},
])
def test_control_a_wrong_fact_fails(plant, top):
    # charmm27 with one fact planted wrong (amber's ion type, a bond constant off by 0.4 %, ...)
    wrong = dataclasses.replace(ffs.CHARMM27, **plant)
    with pytest.raises(AssertionError):
        check(wrong, top)


def test_an_unknown_force_field_names_the_allowed_ones():
    from dna_models.errors import InputError
    with pytest.raises(InputError, match="charmm27, amber99sb-ildn"):
        ffs.forcefield("oplsaa")
    with pytest.raises(InputError, match="tip3p"):
        ffs.CHARMM27.water("tip4p")


def test_the_builder_writes_the_registered_names():
    # pdb2gmx input for amber spells the thymine methyl C7, charmm27 C5M; both O1P/O2P
    from mdbridge.md.gromacs.topology import write_pdb2gmx_input
    import tempfile
    t = bdna_nucleotide("T")
    chains = [{"id": "A", "residues": [(1, "DT", [(a, x) for a, x in t.items()])]}]
    with tempfile.TemporaryDirectory() as d:
        for ff in ffs.REGISTRY.values():
            out = Path(d) / f"{ff.name}.pdb"
            write_pdb2gmx_input(out, chains, ff.name)
            names = {ln[12:16].strip() for ln in out.read_text().splitlines() if ln.startswith("ATOM")}
            assert {ff.rtp_name(a) for a in t} == names
            assert ("C7" in names) == (ff.name == "amber99sb-ildn")
