"""A periodic, ligated duplex through atoms: closed ring detection, the closing step,
minimum images of wrapped atoms, wrapping m-step windows.

Truth by symmetry: a ring of 20 identical base pairs (two turns in the box) whose
frames are perturbed independently and identically in every frame. Every step,
including the closing one across the box, then has the same statistics, and the
mean is the ideal step (0, 0, 3.38 A, 0, 0, 36 deg) up to O(perturbation^2).
"""
import json
import warnings

import numpy as np
import pytest

from mdbridge.md.builder.duplex import build_duplex
from mdbridge.md.builder.frames import ideal_frames
from mdbridge.geometry.rotations import rotation_exp
from dnarod.cli import main


def _ring_trajectory(tmp_path, n_bp=20, T=400, seed=0):
    import MDAnalysis as mda
    from MDAnalysis.coordinates.memory import MemoryReader
    from mdbridge.md.pdbio import write_pdb
    rng = np.random.default_rng(seed)
    seq = "".join(rng.choice(list("ACGT"), n_bp))
    R0, o0 = ideal_frames(n_bp, 3.38, 36.0)
    box = np.array([70.0, 70.0, n_bp * 3.38])
    pos = []
    for _ in range(T):
        dR = rotation_exp(rng.normal(0, np.radians(2.5), (n_bp, 3)))
        o = o0 + rng.normal(0, 0.15, (n_bp, 3))
        s = build_duplex(seq, o, R0 @ dR, periodic_box=box)
        pos.append(np.mod(s.coords, box))            # wrapped, as GROMACS writes them
    write_pdb(tmp_path / "ring.pdb", build_duplex(seq, o0, R0, periodic_box=box))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        u = mda.Universe(str(tmp_path / "ring.pdb"))
    u.load_new(np.array(pos, np.float32), format=MemoryReader,
               dimensions=np.tile(np.r_[box, 90, 90, 90], (T, 1)).astype(np.float32))
    with mda.Writer(str(tmp_path / "ring.trr"), n_atoms=u.atoms.n_atoms) as w:
        for _ in u.trajectory:
            w.write(u.atoms)
    return seq, tmp_path / "ring.pdb", tmp_path / "ring.trr"


@pytest.fixture(scope="module")
def ring(tmp_path_factory):
    tmp_path = tmp_path_factory.mktemp("ring")
    seq, pdb, trr = _ring_trajectory(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rc = main(["coarse-grain", str(pdb), str(trr), "--temperature", "300", "--discard", "0",
                   "--tension", "0", "-o", str(tmp_path / "cg")])
    assert rc == 0
    return seq, tmp_path


def test_closed_ring_closing_step_like_the_others(ring):
    seq, tmp_path = ring
    p = json.loads((tmp_path / "cg" / "params.json").read_text())
    assert p["closed"] and len(p["steps"]) == 20
    assert p["steps"][-1]["dimer"] == seq[-1] + seq[0]
    assert max(b["m"] for b in p["by_length"]) == 5          # n_bp / 4
    assert p["box_constraint"]["corrected"]
    means = np.array([s["mean"] for s in p["steps"]])
    errs = np.array([s["mean_err"] for s in p["steps"]])
    ideal = np.array([0, 0, 3.38, 0, 0, 36.0])
    assert np.all(np.abs(means - ideal) < 4 * errs + np.array([.02, .02, .03, .1, .1, .1]))
    K = np.array([np.diagonal(s["stiffness"]) for s in p["steps"]])
    Ke = np.array([np.diagonal(s["stiffness_err"]) for s in p["steps"]])
    others = K[:-1].mean(axis=0)
    assert np.all(np.abs(K[-1] - others) < 4 * Ke[-1]), (K[-1], others, Ke[-1])
    # every m-step window wraps: n_windows == n_steps
    assert all(b["n_windows"] == 20 for b in p["by_length"])


def test_steps_and_material_files(ring):
    """With the per-step file module (engineer seq's mdbridge.rod.material, shared format
    "dnarod-steps/1"): steps.h5 carries params.json's per-step numbers and masses, and
    material.h5 is a rod material file with one point per base pair."""
    import h5py
    from mdbridge.rod.material.stepfile import read_steps
    seq, tmp_path = ring
    p = json.loads((tmp_path / "cg" / "params.json").read_text())
    sm = read_steps(tmp_path / "cg" / "steps.h5")
    assert sm.sequence == seq and sm.closed and sm.temperature_K == 300.0
    assert np.allclose(sm.step_params, [s["mean"] for s in p["steps"]])
    assert np.allclose(sm.stiffness, [s["stiffness"] for s in p["steps"]])
    assert np.allclose(sm.mass, p["mass_inertia"]["mass_amu"])
    with h5py.File(tmp_path / "cg" / "material.h5", "r") as f:
        assert f.attrs["format"] == "dnarod-material/1"
        assert f["K"].shape == (20, 6, 6) and f["rho"].shape == (20,)
