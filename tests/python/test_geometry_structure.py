"""BasePairFrames on synthetic duplexes with known parameters (independent
truth: the parameters the duplex was built from), periodic/wrapped systems,
residue/atom name variants, clear errors, and the helical-params command."""
import subprocess
import sys
import warnings

import numpy as np
import pytest

import MDAnalysis

from dna_models.errors import InputError  # noqa: E402
from mdbridge.geometry.structure import BasePairFrames, base_of_resname  # noqa: E402
from mdbridge.geometry.synthetic import duplex_universe  # noqa: E402

F32 = 1e-4   # positions are float32 in MDAnalysis: parameters to ~2e-5


def _params(rng, T, n, noise=0.5):
    p = np.tile([0, 0, 3.38, 0, 0, 36.0], (T, n - 1, 1)) + rng.normal(0, noise, (T, n - 1, 6))
    bp = np.concatenate([rng.normal(0, 0.2, (T, n, 3)), rng.normal(0, 5, (T, n, 3))], -1)
    return p, bp


def test_trajectory_recovers_known_parameters():
    rng = np.random.default_rng(1)
    p, bp = _params(rng, 7, 12)
    b = BasePairFrames(duplex_universe("CGCGAATTCGCG", p, bp)).run()
    assert b.results.R.shape == (7, 12, 3, 3)
    assert np.abs(b.step_parameters() - p).max() < F32
    assert np.abs(b.results.bp_parameters - bp).max() < F32
    # start/stop/step selects frames
    b2 = BasePairFrames(duplex_universe("CGCGAATTCGCG", p, bp)).run(1, 7, 2)
    assert list(b2.results.frame) == [1, 3, 5]
    assert np.abs(b2.step_parameters() - p[1:7:2]).max() < F32


def test_wrapped_periodic_duplex():
    """A closed (ligated) helix of 20 bp, two full turns, in a box whose z length
    is 20 rises: atoms wrapped into the box give the same parameters as the whole
    molecule, and the closing step 20 -> 1 equals the others."""
    n, rise, twist = 20, 3.38, 36.0
    L = n * rise
    p = np.tile([0.1, -0.2, rise, 0, 0, twist], (1, n - 1, 1))
    box = np.array([40.0, 40.0, L, 90, 90, 90])
    u = duplex_universe("ACGTTGCAAC" * 2, p, box=box)
    whole = BasePairFrames(u, pbc=False).run()
    X = u.atoms.positions.copy()
    X[:, 2] += 7.0 * L / 3  # move and wrap: molecules now cut across the z walls
    u.atoms.positions = X - np.floor(X / box[:3]) * box[:3]
    wrapped = BasePairFrames(u).run()
    assert wrapped.results.box.shape == (1, 6)
    steps = wrapped.step_parameters(periodic=True)
    assert steps.shape == (1, n, 6)
    assert np.abs(steps[:, :-1] - whole.step_parameters()).max() < F32
    assert np.abs(steps - p[0, 0]).max() < F32
    assert np.abs(wrapped.results.bp_parameters).max() < F32
    # without the box the wrapped atoms give nonsense: the test can fail
    broken = BasePairFrames(u, pairs=[(i + 1, 2 * n - i) for i in range(n)], pbc=False)
    with np.errstate(all="ignore"):
        assert np.abs(broken.run().step_parameters() - p).max() > 1.0


def test_residue_name_variants():
    assert [base_of_resname(r) for r in ("DA", "DA5", "DT3", "A", "ADE", "CYT", "GUA", "THY", "DG")] == \
        list("AATAACGTG")
    assert base_of_resname("ALA") is None and base_of_resname("HOH") is None


def test_atom_name_variants_star_and_op1():
    rng = np.random.default_rng(2)
    p, bp = _params(rng, 1, 6)
    u = duplex_universe("GATTCA", p, bp)
    ref = BasePairFrames(u).run().step_parameters()
    names = [n.replace("'", "*") for n in u.atoms.names]
    u.atoms.names = names
    u.residues.resnames = [{"DA": "ADE", "DC": "CYT", "DG": "GUA", "DT": "THY"}[r] for r in u.residues.resnames]
    assert np.array_equal(BasePairFrames(u).run().step_parameters(), ref)


def test_missing_ring_atom_is_named():
    rng = np.random.default_rng(3)
    p, bp = _params(rng, 1, 4)
    u = duplex_universe("GATC", p, bp)
    names = list(u.atoms.names)
    k = [i for i, a in enumerate(u.atoms) if a.resid == 2 and a.name == "C8"][0]
    names[k] = "XX"
    u.atoms.names = names
    with pytest.raises(InputError, match=r"residue DA2.*ring atom C8 missing"):
        BasePairFrames(u)


def test_unpaired_strands_error():
    rng = np.random.default_rng(4)
    p, bp = _params(rng, 1, 6)
    u = duplex_universe("GATTCA", p, bp)
    # pull strand II 20 A away: nothing pairs
    sel = u.select_atoms("segid B")
    sel.positions = sel.positions + np.array([20.0, 0, 0])
    with pytest.raises(InputError, match="no Watson-Crick base pairs found.*unpaired strands"):
        BasePairFrames(u)


def test_explicit_pairs_and_bad_pairs():
    rng = np.random.default_rng(5)
    p, bp = _params(rng, 1, 5)
    u = duplex_universe("GATTC", p, bp)
    pairs = [(i, 11 - i) for i in range(1, 6)]
    b = BasePairFrames(u, pairs=pairs).run()
    assert np.abs(b.step_parameters() - p).max() < F32
    with pytest.raises(InputError, match="no nucleotide with resid 99"):
        BasePairFrames(u, pairs=[(1, 99)])


def test_no_dna():
    u = MDAnalysis.Universe.empty(1, trajectory=True)
    u.add_TopologyAttr("name", ["CA"])
    u.add_TopologyAttr("resname", ["ALA"])
    with pytest.raises(InputError, match="no DNA nucleotides found"):
        BasePairFrames(u)


def _dnarod(*args):
    """`dnarod helical-params` through the installed toolkit, run from outside the checkout."""
    return subprocess.run([sys.executable, "-m", "dnarod.cli", "helical-params", *args],
                          capture_output=True, text=True, cwd="/")


def test_command_on_355d_equals_3dna(refdata, tmp_path):
    from mdbridge.geometry.x3dna import read_bp_step_par
    out = tmp_path / "steps.csv"
    r = _dnarod(str(refdata / "355d" / "355d.pdb"), "--csv", str(out))
    assert r.returncode == 0, r.stderr
    lines = out.read_text().splitlines()
    assert lines[0] == "frame,step,shift,slide,rise,tilt,roll,twist"
    table = np.array([[float(x) for x in ln.split(",")] for ln in lines[1:]])
    assert list(table[:, 1]) == list(range(1, 12)) and np.all(table[:, 0] == 0)
    _, _, ref = read_bp_step_par(refdata / "355d" / "bp_step.par")
    assert np.abs(table[:, 2:] - ref).max() < 0.0005 + 0.00005 + 2e-4


def test_command_trajectory_with_bpfile_to_stdout(refdata):
    d = refdata / "md_sample_3dna"
    r = _dnarod(str(d / "sample_md0.pdb.gz"), "--pairs", str(d / "bpfile.dat"))
    assert r.returncode == 0, r.stderr
    rows = r.stdout.splitlines()[1:]
    assert len(rows) == 21 * 11
    assert rows[-1].startswith("20,11,")


def test_command_errors_exit_2(tmp_path):
    r = _dnarod(str(tmp_path / "nothing.pdb"))
    assert r.returncode == 2 and "nothing.pdb: file not found" in r.stderr
    bad = tmp_path / "pairs.txt"
    bad.write_text("1 x\n")
    pdb = tmp_path / "w.pdb"
    pdb.write_text("ATOM      1  O   HOH A   1       0.000   0.000   0.000  1.00  0.00           O\nEND\n")
    r = _dnarod(str(pdb), "--pairs", str(bad))
    assert r.returncode == 2 and "pairs.txt, line 1" in r.stderr


def _dna_only_pdb(refdata, tmp_path):
    src = refdata / "355d" / "355d.pdb"
    out = tmp_path / "dna.pdb"
    out.write_text("".join(ln for ln in open(src) if ln.startswith("ATOM") and ln[17:20].strip() in
                           ("DA", "DC", "DG", "DT")) + "END\n")
    return out


def test_gro_and_xtc_without_chain_ids(refdata, tmp_path):
    """GRO + XTC (no chain/segment ids: strands split at O3'-P breaks). GRO and
    XTC store 0.01 A, which moves angles by up to ~0.3 deg."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        u = MDAnalysis.Universe(str(_dna_only_pdb(refdata, tmp_path)))
        ref = BasePairFrames(u).run().step_parameters()
        u.atoms.write(str(tmp_path / "dna.gro"))
        with MDAnalysis.Writer(str(tmp_path / "dna.xtc"), u.atoms.n_atoms) as w:
            for _ in range(3):
                w.write(u.atoms)
        v = MDAnalysis.Universe(str(tmp_path / "dna.gro"), str(tmp_path / "dna.xtc"))
    assert len(set(v.atoms.segids)) == 1
    b = BasePairFrames(v).run()
    assert b.sequence == "CGCGAATTCGCG" and b.results.R.shape[0] == 3
    err = np.abs(b.step_parameters() - ref)
    assert err[..., :3].max() < 0.02 and err[..., 3:].max() < 0.4


def test_gromacs_tpr(refdata, tmp_path):
    """TPR + GRO from GROMACS pdb2gmx/grompp (charmm27) of 355D's DNA."""
    import shutil
    gmx = shutil.which("gmx")
    if gmx is None:
        pytest.fail("GROMACS (gmx) not on PATH: scripts/setup.sh installs it")
    pdb = _dna_only_pdb(refdata, tmp_path)

    def run(args, stdin=""):
        r = subprocess.run([gmx, "-quiet"] + args, input=stdin, capture_output=True, text=True,
                           cwd=tmp_path, timeout=300)
        assert r.returncode == 0, r.stderr[-2000:]

    # termini: 5' and 3' for both strands (DNA, not protein)
    run(["pdb2gmx", "-f", str(pdb), "-o", "conf.gro", "-p", "topol.top", "-ff", "charmm27",
         "-water", "none", "-ignh", "-ter"], "2\n4\n2\n4\n")
    run(["editconf", "-f", "conf.gro", "-o", "box.gro", "-box", "8", "8", "8", "-noc"])
    (tmp_path / "m.mdp").write_text("integrator = md\nnsteps = 0\ncutoff-scheme = Verlet\npbc = xyz\n")
    run(["grompp", "-f", "m.mdp", "-c", "box.gro", "-p", "topol.top", "-o", "topol.tpr", "-maxwarn", "5"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = BasePairFrames(MDAnalysis.Universe(str(pdb))).run().step_parameters()
        v = MDAnalysis.Universe(str(tmp_path / "topol.tpr"), str(tmp_path / "box.gro"))
    b = BasePairFrames(v).run()
    assert b.sequence == "CGCGAATTCGCG"
    err = np.abs(b.step_parameters() - ref)
    assert err[..., :3].max() < 0.02 and err[..., 3:].max() < 0.4
