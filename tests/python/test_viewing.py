"""`dnarod rod-to-atoms` (mdbridge/md/backmap.py): rod runs as molecules for viewers.

Against independent truths: the toolkit's 3DNA-exact frame analysis (mdbridge/geometry,
validated against 3DNA's printed numbers) re-derives the rod's base-pair frames from
the written atoms; MDAnalysis reads the output with the MD build's topology; PyMOL
(Debian's, headless) loads and renders the coarse and all-atom files. Uses the tiny
comparison's rod run and MD build (conftest `tiny_run`).
"""
import json
import subprocess
import sys

import numpy as np
import pytest

# Debian's /usr/bin/pymol runs `python3 -m pymol` with the first python3 on PATH, which may
# not be Debian's; run the module with Debian's Python directly.
PYMOL = [sys.executable, "-m", "pymol"]


@pytest.fixture(scope="module")
def tiny_paths(tiny_run):
    # the kicked (headline) run: the tiny comparison also has an unkicked A_v = 0 run,
    # whose rod does not move
    from dnarod.report.report import fmt_av
    out = tiny_run[0]
    head = fmt_av(json.loads((out / "results.json").read_text())["headline_A_v_A_per_ps"])
    rod = out / "rod" / f"Av{head}" / "rod.h5"
    md = next(iter(sorted((out / "md").glob(f"Av{head}_seed*"))))
    return rod, md


def rod_to_atoms(dnarod, *args):
    """Run rod-to-atoms --like; the tiny headline rod (21 bp kicked at 5 A/ps) bends its
    frames beyond what rigid nucleotides hold together, so the command writes the files
    and refuses on its link and contact limits (exit 2, mdbridge/md/backmap.py) -- but
    never on its t = 0 check: the rod is the build's own."""
    p = subprocess.run([str(dnarod), "rod-to-atoms", *map(str, args)], capture_output=True, text=True)
    assert p.returncode in (0, 2), p.stderr[-3000:]
    if p.returncode == 2:
        assert "fails its checks" in p.stderr and "from the build's own atoms" not in p.stderr, p.stderr
    return p


@pytest.fixture(scope="module")
def atoms(tiny_paths, dnarod, tmp_path_factory):
    rod, md = tiny_paths
    xtc = tmp_path_factory.mktemp("r2a") / "rod_atoms.xtc"
    rod_to_atoms(dnarod, rod, "--like", md, "-o", xtc)
    return xtc


def _rod_frames(rod, n_bp):
    from mdbridge.rod.run import RodRun
    run = RodRun.read(rod)
    R, o = run.bp_frames(n_bp)
    return R, o, run.time * run.attrs["tau_ps"]


def test_reads_with_the_md_topology(atoms, tiny_paths):
    import MDAnalysis as mda
    rod, md = tiny_paths
    u_md = mda.Universe(str(md / "conf.gro"))
    u = mda.Universe(str(md / "conf.gro"), str(atoms))
    n_bp = json.loads((md / "build.json").read_text())["n_bp"]
    R, o, t = _rod_frames(rod, n_bp)
    assert u.atoms.n_atoms == u_md.atoms.n_atoms
    assert len(u.trajectory) == len(t)
    assert list(u.atoms.names) == list(u_md.atoms.names)
    # frame 0 is the rod's t = 0 state, on which the MD was built: the rod's atoms lie on
    # the MD build's (which pdb2gmx and, with --minimize, the minimisation moved a little)
    u.trajectory[0]
    assert np.sqrt(((u.atoms.positions - u_md.atoms.positions) ** 2).sum(1).mean()) < 0.5
    np.testing.assert_allclose([ts.time for ts in u.trajectory], t, atol=1e-3)
    # the first-frame structure files go with it
    assert atoms.with_suffix(".gro").is_file() and atoms.with_suffix(".pdb").is_file()


def test_reanalysed_frames_equal_the_rod_frames(atoms, tiny_paths):
    """3DNA-exact base-pair frames fitted to OUT's atoms equal the rod's frames at every
    written time to 0.01 A and 0.1 deg (the XTC is written at 1e-4 nm)."""
    import MDAnalysis as mda
    from mdbridge.geometry.rotations import rotation_log
    from mdbridge.geometry.structure import BasePairFrames
    rod, md = tiny_paths
    n_bp = json.loads((md / "build.json").read_text())["n_bp"]
    R, o, t = _rod_frames(rod, n_bp)
    u = mda.Universe(str(md / "conf.gro"), str(atoms))
    bpf = BasePairFrames(u).run()
    assert bpf.n_bp == n_bp
    # pairs are found from the atoms; strand I of the build is residues 1..n_bp in order
    R_fit, o_fit = bpf.results.R, bpf.results.origins
    box = u.dimensions[:3]
    # in the MD's coordinates: build-md shifted the rod's frames into the box
    d = o_fit - (o + json.loads((md / "build.json").read_text())["box"]["shift_A"])
    d -= box * np.round(d / box)
    assert np.abs(d).max() < 0.01, np.abs(d).max()
    ang = np.degrees(np.linalg.norm(rotation_log(np.einsum("tnji,tnjk->tnik", R, R_fit)), axis=-1))
    assert ang.max() < 0.1, ang.max()
    # the rod moved: the check compares frames that differ from the first one
    assert np.abs(o[-1] - o[0]).max() > 0.05


def test_chemistry_report(atoms):
    rep = json.loads(atoms.with_suffix(".chemistry.json").read_text())
    n = len(rep["times_ps"])
    assert len(rep["O3P_min_A"]) == n and len(rep["closest_nonbonded_heavy_A"]) == n
    # at t = 0 the frames are the MD build's own: its O3'-P links are chemical (~1.6 A)
    assert 1.4 < rep["O3P_min_A"][0] <= rep["O3P_max_A"][0] < 1.8


def test_relaxation_restores_links(tiny_paths, dnarod, tmp_path):
    """A short restrained minimisation per frame brings the O3'-P links of the most
    strained frame closer to the CHARMM27 bond length (1.61 A) than the rigid back-map."""
    rod, md = tiny_paths
    rigid, relaxed = tmp_path / "rigid.xtc", tmp_path / "relaxed.xtc"
    for out, extra in ((rigid, []), (relaxed, ["--relax-steps", "200"])):
        rod_to_atoms(dnarod, rod, "--like", md, "-o", out, "--every", "25", *extra)
    a = json.loads(rigid.with_suffix(".chemistry.json").read_text())
    b = json.loads(relaxed.with_suffix(".chemistry.json").read_text())

    def dev(r):
        return np.maximum(np.abs(np.array(r["O3P_max_A"]) - 1.61), np.abs(np.array(r["O3P_min_A"]) - 1.61))
    k = int(np.argmax(dev(a)))
    assert dev(a)[k] > 0.05, "the rigid back-map was not strained: the check cannot fail"
    assert dev(b)[k] < 0.5 * dev(a)[k]


def test_coarse_pdb(tiny_paths, dnarod, tmp_path):
    import MDAnalysis as mda
    rod, md = tiny_paths
    n_bp = json.loads((md / "build.json").read_text())["n_bp"]
    pdb = tmp_path / "coarse.pdb"
    p = subprocess.run([str(dnarod), "rod-to-atoms", str(rod), "--coarse", "--bp", str(n_bp),
                        "-o", str(pdb)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    R, o, t = _rod_frames(rod, n_bp)
    u = mda.Universe(str(pdb))
    assert u.atoms.n_atoms == 2 * n_bp and len(u.trajectory) == len(t)
    u.trajectory[-1]
    beads = u.select_atoms("name C").positions
    tips = u.select_atoms("name D1").positions
    np.testing.assert_allclose(beads, o[-1], atol=1e-3)
    np.testing.assert_allclose((tips - beads) / 5.0, R[-1][:, :, 0], atol=1e-3)
    # bonds: the centreline chain (n_bp - 1) and one spoke per base pair
    assert len(u.bonds) == (n_bp - 1) + n_bp


def _pymol_png(tmp_path, script: str) -> np.ndarray:
    pml = tmp_path / "render.pml"
    png = tmp_path / "render.png"
    pml.write_text(script + f"\nset ray_opaque_background, 1\npng {png}, width=400, height=300, dpi=72, ray=1\n")
    p = subprocess.run([*PYMOL, "-cq", str(pml)], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr
    assert "Error" not in p.stdout + p.stderr, p.stdout + p.stderr
    import matplotlib.image as mpimg
    return mpimg.imread(png)


def test_pymol_renders_coarse_and_atoms(atoms, tiny_paths, dnarod, tmp_path):
    import importlib.util
    if importlib.util.find_spec("pymol") is None:
        pytest.fail("PyMOL not importable by Debian's Python: scripts/setup.sh installs pymol")
    rod, md = tiny_paths
    pdb = tmp_path / "coarse.pdb"
    subprocess.run([str(dnarod), "rod-to-atoms", str(rod), "--coarse", "--bp", "21", "-o", str(pdb)],
                   check=True, capture_output=True)
    img = _pymol_png(tmp_path, f"load {pdb}, rod\nshow sticks\nload {md / 'conf.gro'}, md\n"
                               f"load_traj {atoms}, md\ncount_states md\norient")
    assert img.shape[:2] == (300, 400)
    assert np.std(img[..., :3]) > 0.02, "PyMOL rendered a blank picture"


def test_bad_inputs_are_named(tiny_paths, dnarod, tmp_path):
    rod, md = tiny_paths
    cases = [
        ([str(tmp_path / "nope.h5"), "--coarse", "--bp", "21", "-o", str(tmp_path / "x.pdb")], "no such rod run"),
        ([str(rod), "--like", str(tmp_path), "-o", str(tmp_path / "x.xtc")], "build.json missing"),
        ([str(rod), "--like", str(md), "-o", str(tmp_path / "x.mp4")], "allowed trajectory formats"),
        ([str(rod), "--coarse", "--bp", "20", "-o", str(tmp_path / "x.pdb")], "multiple of n_bp"),
    ]
    for args, words in cases:
        p = subprocess.run([str(dnarod), "rod-to-atoms", *args], capture_output=True, text=True)
        assert p.returncode == 2 and words in p.stderr, (args, p.stderr)
