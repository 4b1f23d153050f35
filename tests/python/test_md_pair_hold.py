"""The intact-duplex option and the ligation junction, on real GROMACS run inputs.

- `--hold-pairs` (mdbridge/md/gromacs/pair_hold.py): one flat-bottomed restraint per
  Watson-Crick H-bond, placed on the right atoms, which leaves every other part of the run
  input (atoms, exclusions, bonded and non-bonded terms) exactly as without it, and is flat
  (zero energy, zero force) while a pair is closed.
- The junction: in the .tpr that mdrun reads, the ligation step equals, term by term with
  resolved parameters, every interior step with the same two bases (junction.py), with
  controls that a changed charge and a different dinucleotide are seen.
"""
import copy
import re
import subprocess

import numpy as np
import pytest

from dna_models.errors import InputError
from dna_models.nucleotides import WATSON_CRICK_HBONDS
from mdbridge.md.gromacs.gro import read_gro
from mdbridge.md.gromacs.junction import junction_parameters, step_signature
from mdbridge.md.gromacs.pair_hold import PairHold, hbond_atom_pairs
from mdbridge.md.gromacs.topology import parse_itp
from mdbridge.md.gromacs.tpr_dump import dump_tpr

# strand I's last -> first step (C -> G) also occurs inside (TCGA), on both strands
SEQ = "GTTGCAGGCATCGATCCGAAC"


def _make_seq(tmp, gmx, **kw):
    from mdbridge.md.builder import build_duplex
    from mdbridge.md.gromacs.box import plan_box
    from mdbridge.md.gromacs.inputs import build_inputs
    from mdbridge.md.gromacs.mdp import MdSettings
    from test_gromacs_build import table1_rod
    rod = table1_rod(21, 2)
    st = build_duplex(SEQ, rod.origins_A, rod.R, periodic_box=(0, rod.closure_length_A, 0))
    box = plan_box(rod.origins_A[None], rod.origins_A, rod.closure_length_A, rod_run_ps=1.0)
    return rod, build_inputs(tmp, st, rod, box, sequence=SEQ, temperature_K=0.0, seed=3,
                             settings=MdSettings(nsteps=20), gmx=gmx, **kw)


@pytest.fixture(scope="module")
def builds(gmx, tmp_path_factory):
    plain, held = tmp_path_factory.mktemp("plain"), tmp_path_factory.mktemp("held")
    return (plain, _make_seq(plain, gmx)[1]), (held, _make_seq(held, gmx, hold_pairs=PairHold())[1])


def _tpr_dump_text(d, gmx):
    subprocess.run([gmx, "grompp", "-f", "md.mdp", "-c", "conf.gro", "-p", "topol.top", "-o", "t.tpr",
                    "-po", "t.mdp", "-maxwarn", "0"], cwd=d, check=True, capture_output=True)
    return subprocess.run([gmx, "dump", "-s", "t.tpr"], cwd=d, check=True, capture_output=True,
                          text=True).stdout


def test_one_restraint_per_watson_crick_hbond_on_the_right_atoms(builds):
    (_, plain), (d, info) = builds
    assert plain["pair_hold"] is None
    rec = info["pair_hold"]
    # 21 pairs: G-C pairs have three H-bonds, A-T two (the sequence's own composition)
    n_gc = sum(b in "GC" for b in SEQ)
    assert rec["n_restraints"] == 3 * n_gc + 2 * (21 - n_gc)
    mols = [parse_itp(p) for p in sorted(d.glob("topol_DNA_chain_*.itp"))]
    g = read_gro(d / "conf.gro")
    x = g.x * 10.0
    for i, j, k, na, nb in hbond_atom_pairs(mols, 21):
        assert (g.name[i - 1], g.name[j - 1]) == (na, nb)
        # the two atoms belong to pair k: strand I residue k + 1 and strand II residue 42 - k
        assert {g.resid[i - 1], g.resid[j - 1]} == {k + 1, 42 - k}
        # and at t = 0 (the built B-DNA) they are H-bonded: inside the flat bottom
        assert 2.5 < np.linalg.norm(x[i - 1] - x[j - 1]) < PairHold().up1_of(na, nb)
    assert all(len(v) in (2, 3) for v in WATSON_CRICK_HBONDS.values())


def test_the_restraints_change_nothing_else_in_the_run_input(builds, gmx):
    """Every atom, exclusion and interaction of the two strands is identical with and without
    the restraints: bonds of type 10 in [ intermolecular_interactions ] add no exclusion."""
    (plain, _), (held, _) = builds

    def body(text):
        text = re.sub(r"ld-seed\s*=.*", "", text)
        text = re.sub(r"buffer size = \d+", "", text)
        head, _, rest = text.partition("bIntermolecularInteractions")
        inter, _, mol = rest.partition("moltype (0):")
        return head, "moltype (0):" + mol, inter
    a, b = body(_tpr_dump_text(plain, gmx)), body(_tpr_dump_text(held, gmx))
    assert a[0].split("\n")[-50:] == b[0].split("\n")[-50:]
    assert a[1] == b[1]                       # the molecules: atoms, exclusions, every term
    assert "RESTRAINTPOT" in b[2] and "RESTRAINTPOT" not in a[2]
    # control: the comparison sees a change of the molecules (one charge)
    assert body(_tpr_dump_text(plain, gmx).replace("q=-7.80000e-01", "q=-7.70000e-01", 1))[1] != a[1]


def test_restraint_is_flat_while_closed_and_acts_below_the_open_rule(builds, gmx):
    """A zero-step run on the built B-DNA: GROMACS's own restraint energy is exactly zero."""
    _, (d, info) = builds
    subprocess.run([gmx, "grompp", "-f", "md.mdp", "-c", "conf.gro", "-p", "topol.top", "-o", "z.tpr",
                    "-po", "z.mdp", "-maxwarn", "0"], cwd=d, check=True, capture_output=True)
    subprocess.run([gmx, "mdrun", "-s", "z.tpr", "-deffnm", "z", "-nsteps", "0", "-nt", "1"], cwd=d,
                   check=True, capture_output=True)
    out = subprocess.run([gmx, "energy", "-f", "z.edr", "-o", "z.xvg"], cwd=d, input="Restraint-Pot.\n\n",
                         capture_output=True, text=True, check=True)
    rows = [ln.split() for ln in (d / "z.xvg").read_text().splitlines() if ln and ln[0] not in "#@"]
    assert rows and float(rows[0][1]) == 0.0, out.stdout[-500:]
    with pytest.raises(InputError, match="open-pair rule"):
        PairHold(up1_A=3.6)
    with pytest.raises(InputError, match="width"):
        PairHold(width_A=0.0)
    assert PairHold().up1_of("N1", "N3") < 3.5 < PairHold().up1_of("N6", "O4")


def test_junction_equals_interior_steps_with_the_same_bases_in_the_run_input(builds, gmx):
    (d, info), _ = builds
    rep = info["junction_run_input"]
    assert [r["ok"] for r in rep] == [True, True]
    assert all(r["interior_steps_compared"] >= 1 and r["n_interactions"] >= 19 for r in rep)
    dump = dump_tpr(gmx, _tpr_path(d, gmx))
    assert [r["ok"] for r in junction_parameters(dump)] == [True, True]
    # control 1: one changed partial charge on the junction's first residue is seen
    bad = copy.deepcopy(dump)
    mol = bad.moltypes[0]
    i = next(k for k, (r, n) in enumerate(zip(mol.resind, mol.atomname)) if r == 0 and n == "C4'")
    mol.charge[i] += 0.01
    same = [a for a in range(20) if (mol.resname[a], mol.resname[a + 1]) == (mol.resname[20], mol.resname[0])]
    assert junction_parameters(bad)[0]["differs_from_steps"] == {"atoms": same}
    # control 2: a step with other bases is not equal to the junction (the comparison has content)
    m = dump.moltypes[0]
    j = step_signature(m, 20)
    other = next(a for a in range(20) if (m.resname[a], m.resname[a + 1]) != j["resnames"])
    assert step_signature(m, other)["atoms"] != j["atoms"]


def _tpr_path(d, gmx):
    subprocess.run([gmx, "grompp", "-f", "md.mdp", "-c", "conf.gro", "-p", "topol.top", "-o", "j.tpr",
                    "-po", "j.mdp", "-maxwarn", "0"], cwd=d, check=True, capture_output=True)
    return d / "j.tpr"
