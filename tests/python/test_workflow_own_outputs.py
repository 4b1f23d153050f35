"""A command's output is valid input to the next: each command of the toolkit run on
what another of its commands wrote (build-dna, dna-rod, rodsim, build-md,
rod-to-atoms, helical-params), and either right or refused with exit 2.

Truths: the rod scene's own numbers (a uniform rod's rise and twist, its period),
MDAnalysis's reading of the files, the builder's frames re-analysed with the
3DNA-exact geometry (mdbridge.geometry, checked against 3DNA in test_geometry_3dna.py)."""
import csv
import io

import numpy as np
import pytest

from dnarod.cli import main

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
SCENES = ROOT / "workflows" / "scenes"


def dnarod(argv, capsys):
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out, out.err


def steps_csv(text: str) -> np.ndarray:
    rows = list(csv.DictReader(io.StringIO(text)))
    return np.array([[float(r[k]) for k in ("shift", "slide", "rise", "tilt", "roll", "twist")]
                     for r in rows])


def test_build_dna_periodic_box_is_read_by_helical_params(tmp_path, capsys):
    """build-dna --periodic writes the box as CRYST1: MDAnalysis reads the period, and
    helical-params --periodic gives the closing step the rise of every other step (the
    uniform dna21 scene: 3.38 A, 360 x 2 / 21 deg). Without the box the closing step is
    refused, naming how to give it; --box gives it back."""
    import MDAnalysis as mda
    pdb = tmp_path / "dna21.pdb"
    code, out, _ = dnarod(["build-dna", "--scene", SCENES / "dna21.toml", "--periodic", "--seed", "1",
                           "-o", pdb], capsys)
    assert code == 0, out
    period = 21 * 3.38
    box = mda.Universe(str(pdb)).dimensions
    assert box is not None and box[1] == pytest.approx(period, abs=1e-3)
    assert min(box[0], box[2]) > 40.0      # the non-periodic edges: twice the extent + 10 A
    code, out, err = dnarod(["helical-params", pdb, "--periodic"], capsys)
    assert code == 0, err
    P = steps_csv(out)
    assert P.shape == (21, 6)
    np.testing.assert_allclose(P[:, 2], 3.38, atol=2e-3)
    np.testing.assert_allclose(P[:, 5], 360.0 * 2 / 21, atol=0.02)

    # control: the same file without its CRYST1 record
    bare = tmp_path / "bare.pdb"
    bare.write_text("".join(ln for ln in pdb.read_text().splitlines(True) if not ln.startswith("CRYST1")))
    code, out, err = dnarod(["helical-params", bare, "--periodic"], capsys)
    assert code == 2 and out == ""
    assert "closing step (base pair 21 -> 1) spans" in err and "CRYST1" in err and "--box" in err
    code, out, err = dnarod(["helical-params", bare, "--periodic", "--no-pbc"], capsys)
    assert code == 2 and "--no-pbc" in err
    code, out, err = dnarod(["helical-params", bare, "--periodic", "--box", 60, period, 60], capsys)
    assert code == 0, err
    np.testing.assert_allclose(steps_csv(out), P, atol=2e-4)
    # a linear duplex needs no box (the closing step is not asked for)
    code, out, err = dnarod(["helical-params", bare], capsys)
    assert code == 0 and steps_csv(out).shape == (20, 6)


# -- a sequence-dependent rod and its all-atom build without minimisation -----------------
N_BP = 40


@pytest.fixture(scope="module")
def seq_build(tmp_path_factory, rodsim, gmx):
    """`dnarod dna-rod --random 40`, its rodsim run and `build-md --protocol paper` of it
    (no minimisation, no equilibration: conf.gro holds the builder's atoms)."""
    import subprocess
    d = tmp_path_factory.mktemp("own40")
    assert main(["dna-rod", "--random", str(N_BP), "--seed", "1", "--t-end-ps", "5", "-o", str(d / "rod")]) == 0
    subprocess.run([str(rodsim), "run", str(d / "rod" / "scene.toml"), "-o", str(d / "rod.h5")],
                   check=True, capture_output=True)
    return d


@pytest.fixture(scope="module")
def built(seq_build, gmx):
    import contextlib
    import io as _io
    d = seq_build
    err = _io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main(["build-md", str(d / "rod" / "scene.toml"), "--rod", str(d / "rod.h5"), "--ps", "5",
                     "--protocol", "paper", "--seed", "1", "--threads", "1", "--gmx", str(gmx),
                     "-o", str(d / "md")])
    assert code == 0, err.getvalue()[-3000:]
    return d, err.getvalue()


def o3p_lengths_of(path, n_bp):
    """O3'(i)-P(i+1) lengths of a build-md structure, read with MDAnalysis, minimum image
    (independent of mdbridge's link code: the residues in file order, each strand a ring)."""
    import MDAnalysis as mda
    u = mda.Universe(str(path))
    box = u.dimensions[:3]
    out = []
    for first in (0, n_bp):
        for k in range(n_bp):
            a, b = u.residues[first + k], u.residues[first + (k + 1) % n_bp]
            v = b.atoms.select_atoms("name P").positions[0] - a.atoms.select_atoms("name O3'").positions[0]
            out.append(np.linalg.norm(v - box * np.round(v / box)))
    return np.array(out)


def test_build_md_links_in_range_and_reported(built):
    """The builder closes the links of the sequence-dependent rod to 1.5-1.8 A (conf.gro
    read independently), and build-md's summary gives them with their limits. Control: the
    same frames with rigidly placed nucleotides leave links far outside, and the check
    refuses them naming the number."""
    import json
    from dna_models.errors import InputError
    from mdbridge.md.builder import build_duplex
    from mdbridge.md.builder.backbone import check_structure_links
    from mdbridge.md.gromacs.rod import rod_initial_from_run
    from mdbridge.md.gromacs.rod import lab_rotation_to_axis, rotate_rod
    from mdbridge.rod.run import RodRun
    d, err = built
    links = o3p_lengths_of(d / "md" / "conf.gro", N_BP)
    assert 1.5 <= links.min() and links.max() <= 1.8, (links.min(), links.max())
    b = json.loads((d / "md" / "build.json").read_text())
    for v in b["junction_O3P_t0_A"].values():
        assert 1.5 <= v["interior_min"] <= v["interior_max"] <= 1.8 and 1.5 <= v["junction"] <= 1.8
    assert "O3'-P links as built" in err and "(limits 1.5-1.8 A" in err
    assert "vs the rod's t = 0 frames" in err and "(limit 0.1 A / 1.0 deg" in err

    run = RodRun.read(d / "rod.h5")
    rod, _ = rod_initial_from_run(run, N_BP)
    rod, _ = rotate_rod(rod, np.zeros((1, 1, 3)), lab_rotation_to_axis(run, axis=1))
    periodic = np.array([0.0, rod.closure_length_A, 0.0])     # the helix turned onto lab Y
    rigid = build_duplex(b["sequence"], rod.origins_A, rod.R, periodic_box=periodic)
    with pytest.raises(InputError, match=r"O3'-P link of residues \d+ -> \d+ is \d\.\d\d A"):
        check_structure_links(rigid)
    closed = build_duplex(b["sequence"], rod.origins_A, rod.R, periodic_box=periodic, close_backbone=True)
    d_closed = check_structure_links(closed)
    assert 1.5 <= d_closed.min() and d_closed.max() <= 1.8
    # only the 5' ends moved, and each by turning: every bond inside a nucleotide keeps its length
    same_res = closed.resids[closed.bonds[:, 0]] == closed.resids[closed.bonds[:, 1]]
    bl = [np.linalg.norm(s.coords[closed.bonds[same_res, 0]] - s.coords[closed.bonds[same_res, 1]], axis=1)
          for s in (rigid, closed)]
    np.testing.assert_allclose(bl[1], bl[0], atol=1e-9)
    moved = np.linalg.norm(closed.coords - rigid.coords, axis=1) > 1e-9
    assert set(closed.names[moved]) <= {"O5'", "P", "O1P", "O2P"}


def test_uniform_rod_build_unchanged_by_link_closure():
    """The paper's uniform rod already has every link in range: closing them is a no-op,
    so builds of the uniform scenes are bitwise what they were."""
    from mdbridge.md.builder import build_duplex
    from mdbridge.md.builder.scene import frames_from_scene
    fr = frames_from_scene(SCENES / "dna158.toml")
    seq = "ACGT" * 39 + "AC"
    a = build_duplex(seq, fr.origins, fr.R, periodic_box=fr.box)
    b = build_duplex(seq, fr.origins, fr.R, periodic_box=fr.box, close_backbone=True)
    assert np.array_equal(a.coords, b.coords)


def test_helical_params_reads_a_build_md_folder(built, capsys):
    """helical-params on the build-md folder (its conf.gro, the pairs of build.json) gives
    the rod's own t = 0 step parameters, closing step included, to the builder's precision
    (0.03 A, 0.3 deg; docs/builder.md)."""
    from mdbridge.geometry.steps import step_parameters_along
    from mdbridge.geometry.trajectory import BasePairTrajectory
    from mdbridge.rod.run import RodRun
    d, _ = built
    code, out, err = dnarod(["helical-params", d / "md", "--periodic"], capsys)
    assert code == 0, err
    assert "base pairs from" in err and "build.json" in err
    md = steps_csv(out)
    # the rod's frames at t = 0 and the closing frame: frame 0 one period vector on
    run = RodRun.read(d / "rod.h5")
    R, o = run.bp_frames(N_BP)
    period = np.asarray(BasePairTrajectory.from_rod(run, N_BP).period[0])
    rod_steps = step_parameters_along(np.concatenate([R[0], R[0][:1]]),
                                      np.concatenate([o[0], o[0][:1] + period]))
    err_ = np.abs(md - rod_steps)
    assert err_[:, :3].max() < 0.03 and err_[:, 3:].max() < 0.3, (err_[:, :3].max(), err_[:, 3:].max())
    # the same from conf.gro itself
    code, out2, _ = dnarod(["helical-params", d / "md" / "conf.gro", "--periodic"], capsys)
    assert code == 0 and out2 == out


def test_rod_to_atoms_like_its_build(built, rodsim, capsys, tmp_path):
    """rod-to-atoms --like puts the rod where build-md put the duplex (the rod's helix
    axis turned onto the box's Y; t = 0 is conf.gro's atoms, read with MDAnalysis), with
    links and contacts in their limits. Control: the rod of another sequence's scene,
    overlaid on this build, is refused naming the rms and the likely cause."""
    import json
    import MDAnalysis as mda
    d, _ = built
    xtc = tmp_path / "r.xtc"
    code, out, err = dnarod(["rod-to-atoms", d / "rod.h5", "--like", d / "md", "-o", xtc], capsys)
    assert code == 0, err
    u = mda.Universe(str(d / "md" / "conf.gro"), str(xtc))
    ref = mda.Universe(str(d / "md" / "conf.gro"))
    heavy = ~np.char.startswith(ref.atoms.names.astype(str), "H")
    u.trajectory[0]
    rms = np.sqrt(((u.atoms.positions[heavy] - ref.atoms.positions[heavy]) ** 2).sum(1).mean())
    assert rms < 0.01, rms
    chem = json.loads(xtc.with_suffix(".chemistry.json").read_text())
    assert 1.5 <= min(chem["O3P_min_A"]) and max(chem["O3P_max_A"]) <= 1.8
    assert min(c for c in chem["closest_nonbonded_heavy_A"] if c is not None) >= 1.5

    other = tmp_path / "other"
    assert main(["dna-rod", "--random", str(N_BP), "--seed", "2", "--t-end-ps", "5", "-o", str(other)]) == 0
    import subprocess
    subprocess.run([str(rodsim), "run", str(other / "scene.toml"), "-o", str(tmp_path / "o.h5")],
                   check=True, capture_output=True)
    capsys.readouterr()
    code, out, err = dnarod(["rod-to-atoms", tmp_path / "o.h5", "--like", d / "md", "-o", tmp_path / "o.xtc"],
                            capsys)
    assert code == 2 and "A rms from the build's own atoms (limit 1.0 A)" in err
    assert "not of the same scene" in err


def test_rod_to_atoms_coarse_box_read_by_mdanalysis(built, tmp_path, capsys):
    """The coarse PDB with --like carries the MD build's box in every model, where
    MDAnalysis reads it (a CRYST1 before MODEL 1 it does not)."""
    import json
    import MDAnalysis as mda
    d, _ = built
    pdb = tmp_path / "coarse.pdb"
    code, out, err = dnarod(["rod-to-atoms", d / "rod.h5", "--coarse", "--like", d / "md", "-o", pdb], capsys)
    assert code == 0, err
    box = json.loads((d / "md" / "build.json").read_text())["box"]["box_A"]
    u = mda.Universe(str(pdb))
    assert len(u.trajectory) > 1
    for ts in u.trajectory:
        assert ts.dimensions is not None
        np.testing.assert_allclose(ts.dimensions, [*box, 90, 90, 90], atol=1e-3)
