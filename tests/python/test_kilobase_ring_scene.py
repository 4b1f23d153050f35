"""The shipped kilobase ring, workflows/scenes/dna10k_water.toml: a 10.5-kbp closed ring of an Olson
1998 sequence (random, seed 1) on 10-bp coarse segments, overdamped in water at 300 K (no
self-contact yet: docs/thermal.md), from its closed rest state (`dnarod dna-rod --ring`;
docs/dna-rod.md, "A closed ring").

The shipped files are checked for what they are (the seeded sequence's coarse material, closed, the
rest energy in frame 0, the output contract); that the rest state is a minimum is checked on a
1050-bp ring made afresh by the same command (seconds), against perturbations that must raise its
energy, with the closed circle it starts from as the control that must fail."""
import json
import os
import subprocess
import tomllib
from pathlib import Path

import h5py
import numpy as np
import pytest

from dna_models.units import Units
from mdbridge.geometry.compiled import rodcore_module
from mdbridge.geometry.rotations import rotation_log
from mdbridge.rod.material.composition import magnus_holonomy
from mdbridge.rod.material.dna_rod import DnaRodRequest, dna_rod
from mdbridge.rod.material.ring import planar_ring
from mdbridge.rod.material.ring_rest import close_in_solver_frames, discretisation_floor, statics

ROOT = Path(os.environ.get("DNAROD_ROOT", Path(__file__).resolve().parents[2]))
SCENE = ROOT / "workflows" / "scenes" / "dna10k_water.toml"
FOLDER = ROOT / "workflows" / "scenes" / "dna10k_water"
DT = tomllib.loads(SCENE.read_text())["solver"]["dt"]     # the scene's 100-ps step


def read_grid_material_arrays(path):
    with h5py.File(path) as f:
        return {k: f[k][()] for k in ("K", "I", "rho", "Gamma0", "Omega0")}


def run(exe, *args):
    return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True, check=True)


def frame0(scene, x):
    """The solver's frame 0 of strains x (N, 6) in SCENE (a dict): end_to_end, end_rotation."""
    rc = rodcore_module()
    s = {k: v for k, v in scene.items() if k in ("rod", "material")}
    s["output"] = {"t_end": 1e-6, "frames": 2, "fields": ["internal", "centerline", "directors"]}
    z = np.zeros((x.shape[0], 3))
    frames = []
    sim = rc.Simulation(s, initial={"gamma": z, "omega": z, "Gamma": x[:, :3].copy(), "Omega": x[:, 3:].copy()})
    sim.add_observer(lambda fr: frames.append(fr))
    sim.step_to(0.0)
    return frames[0]


# -- the shipped files ---------------------------------------------------------------
def test_the_shipped_scene_loads_as_the_brownian_ring(rodsim):
    # no [contact] yet: the overdamped ring with contact does not keep its Lk (docs/thermal.md)
    p = run(rodsim, "check", SCENE)
    assert "brownian" in p.stdout and "[contact]" not in p.stdout and "material.h5" in p.stdout, p.stdout
    for name in ("material.h5", "rest.h5", "rest.json"):
        assert (FOLDER / name).stat().st_size < 2_000_000      # committed, small


def test_its_material_is_the_seeded_olson_sequence_in_coarse_segments():
    """material.h5 is `dna-rod --random 10500 --seed 1 --params olson1998 --bp-per-point 10`'s grid
    material, made afresh here by the same functions, to round-off; the sequence is the seeded one."""
    from dna_models.sequence import random_sequence
    from mdbridge.rod.material.coarse import coarse_material
    from mdbridge.rod.material.parameter_sets import step_material
    from mdbridge.rod.material.steps_to_rod import grid_material, rod_material
    info = json.loads((FOLDER / "rest.json").read_text())
    seq = random_sequence(10500, seed=1)
    assert info["sequence"] == seq and info["bp_per_point"] == 10 and info["points"] == 1050
    rm, turns = coarse_material(rod_material(step_material(seq, "olson1998", closed=True), units=Units.paper()), 10)
    g = grid_material(rm, rm.n_bp, "trig")
    shipped = read_grid_material_arrays(FOLDER / "material.h5")
    with h5py.File(FOLDER / "material.h5") as f:
        assert f.attrs["sequence"] == seq and int(f.attrs["turns_dropped"]) == int(turns.sum()) == 1050
    for name in ("K", "I", "rho", "Gamma0", "Omega0"):
        assert np.allclose(shipped[name], g[name], rtol=1e-12, atol=1e-14), name
    # a coarse segment turns ~343 deg; the rod keeps the principal -17 deg, one whole turn per segment dropped
    assert -25 < np.degrees(np.mean(g["Omega0"][:, 2]) * rm.h) < -10


def test_the_shipped_rest_state_is_closed_at_the_relaxed_linking_number():
    info = json.loads((FOLDER / "rest.json").read_text())
    with h5py.File(FOLDER / "rest.h5") as f:
        x = np.concatenate([f["fields/Gamma"][()], f["fields/Omega"][()]], axis=1)
    scene = {"rod": {"length": info["length"], "points": info["points"]},
             "material": {"material_file": str(FOLDER / "material.h5")}}
    fr = frame0(scene, x)
    assert np.linalg.norm(fr["end_to_end"]) < 1e-9 * info["length"] and fr["end_rotation"] < 1e-12
    R, r = magnus_holonomy(x, info["length"])
    assert np.linalg.norm(rotation_log(R)) < 1e-12 and np.linalg.norm(r) < 1e-9 * info["length"]
    assert info["Lk"] == round(info["Lk0"]) and info["Lk_DNA"] == info["Lk"] + info["turns_dropped"]
    assert abs(info["Tw"] + info["Wr"] - info["Lk"]) < 0.03      # the discrete twist's second-order error
    assert info["contact_energy_kT"] == 0.0
    # the residual at the grid's floor (fd4 against spectral d/ds), the closed circle's well above it
    assert info["statics_residual"] < 2 * info["statics_residual_floor"] < 0.2 * info["statics_residual_start"]
    assert info["energy_kT"] < info["energy_start_kT"]


def test_the_shipped_scene_starts_at_the_rest_energy_and_keeps_the_contract(rodsim, tmp_path):
    """`rodsim run` as shipped with the contract's --set keys: from rest (sample_initial = false)
    frame 0's energy is rest.json's; the file says solver.time = "brownian", has kT and tau_ps,
    and Lk, Tw, Wr per frame with Lk the rest state's; with the thermal state (the default) frame 0
    is hotter by about the equipartition (6 N - 6) kT / 2 (control)."""
    info = json.loads((FOLDER / "rest.json").read_text())
    out = tmp_path / "ring.h5"
    run(rodsim, "run", SCENE, "-o", out, "-q", "--set", "thermal.sample_initial=false", "--set",
           f"output.t_end={DT!r}", "--set", "output.frames=2")
    with h5py.File(out) as f:
        E = f["energy"][()]
        assert abs(E[0] - info["energy"]) < 1e-9 * info["energy"]
        assert f.attrs["solver.time"] in ("brownian", b"brownian")
        assert f.attrs["kT"] > 0 and f.attrs["tau_ps"] > 0
        assert len(E) == 2 and E[1] > E[0]               # the noise of one step warms it
        for k in ("Lk", "Tw", "Wr"):
            assert f[f"topology/{k}"].shape == (2,)
        assert np.all(f["topology/Lk"][()] == info["Lk"])
        kT = f.attrs["kT"]
    run(rodsim, "run", SCENE, "-o", tmp_path / "hot.h5", "-q", "--set", f"output.t_end={DT!r}", "--set",
        "output.frames=2")
    with h5py.File(tmp_path / "hot.h5") as f:
        hot = f["energy"][0] - info["energy"]
    dof = 6 * info["points"] - 6
    assert abs(hot / (dof * kT / 2) - 1) < 0.1, hot / (dof * kT / 2)


# -- the rest state is a minimum (a 1050-bp ring by the same command) ---------------------
@pytest.fixture(scope="module")
def small_ring(tmp_path_factory):
    from dna_models.sequence import random_sequence
    out = tmp_path_factory.mktemp("ring1k")
    info = dna_rod(DnaRodRequest(sequence=random_sequence(1050, seed=1), output=str(out), params="olson1998",
                                 bp_per_point=10, ring=True, contact_diameter_nm=11.6, t_end_ps=1000.0, seed=1))
    with h5py.File(out / "rest.h5") as f:
        x = np.concatenate([f["fields/Gamma"][()], f["fields/Omega"][()]], axis=1)
    g = read_grid_material_arrays(out / "material.h5")
    scene = {"rod": {"length": info["length"], "points": info["points"]},
             "material": {"material_file": str(out / "material.h5")}, "contact": {"diameter_nm": 11.6}}
    return info, x, g, scene, out


def test_a_small_ring_by_the_same_command_is_closed_and_at_rest_in_the_solver(small_ring):
    info, x, g, scene, out = small_ring
    fr = frame0(scene, x)
    assert np.linalg.norm(fr["end_to_end"]) < 1e-10 * info["length"] and fr["end_rotation"] < 1e-12
    assert info["Lk"] == -5 == round(info["Lk0"])
    E, res = statics(scene, x)
    assert E == pytest.approx(info["energy"], rel=1e-12) and res == pytest.approx(info["statics_residual"])
    # the statics residual is the grid's: as large as fd4 and spectral d/ds disagree on the state; the
    # closed circle's is ten times that (control)
    floor = discretisation_floor(scene, x)
    circle = close_in_solver_frames(planar_ring(g, info["length"], info["Lk"]), g, info["length"])
    assert res < 2 * floor and statics(scene, circle)[1] > 10 * floor
    # at kT = 0 the scene's own overdamped rod keeps it, closed, at its Lk, over 1 ns
    dt = tomllib.loads((out / "scene.toml").read_text())["solver"]["dt"]
    cold = rodcore_module().run(str(out / "scene.toml"), set=["thermal.temperature_K=0",
                                                              f"output.t_end={10 * dt!r}", "output.frames=2"])
    assert abs(cold["energy"][-1] / cold["energy"][0] - 1) < 1e-3, cold["energy"]
    assert list(cold["topology"]["Lk"]) == [info["Lk"]] * 2


def _closed_perturbations(x, g, L, amplitude, n, seed):
    """n closed states near x: smooth random strain changes (the lowest 8 Fourier modes of every
    strain, each component scaled by its point's K^-1/2: equal energy per component), closed in
    the solver's frames."""
    rng = np.random.default_rng(seed)
    N = x.shape[0]
    s = np.arange(N) / N
    Kinv_half = np.linalg.cholesky(np.linalg.inv(g["K"]))
    for _ in range(n):
        p = np.zeros((N, 6))
        for k in range(1, 9):
            p += np.cos(2 * np.pi * k * s)[:, None] * rng.normal(size=6) + np.sin(2 * np.pi * k * s)[:, None] \
                * rng.normal(size=6)
        p = np.einsum("jab,jb->ja", Kinv_half, p)
        p *= amplitude / np.sqrt(np.mean(np.sum(p * p, axis=1)))
        yield p


def test_the_rest_state_is_a_minimum_and_the_closed_circle_is_not(small_ring):
    """E(closed(x +- a p)) > E(x) for both signs of 6 random smooth perturbations p at the rest state;
    control: at the closed circle it started from, one sign lowers the energy for every p (its
    gradient along the closed states is first order)."""
    info, x, g, scene, _ = small_ring
    L = info["length"]
    E0 = statics(scene, x)[0]
    circle = close_in_solver_frames(planar_ring(g, L, info["Lk"]), g, L)
    Ec = statics(scene, circle)[0]
    assert Ec > E0
    for p in _closed_perturbations(x, g, L, 1e-4, 6, seed=3):
        for y0, Ey0, is_min in ((x, E0, True), (circle, Ec, False)):
            Ep = [statics(scene, close_in_solver_frames(y0 + sgn * p, g, L))[0] for sgn in (1, -1)]
            if is_min:
                assert min(Ep) > Ey0, (Ep, Ey0)
            else:
                assert min(Ep) < Ey0, (Ep, Ey0)


def test_ring_options_that_do_not_fit_are_refused(tmp_path, capsys):
    """--ring has no box, kick or base-pair grid, and a contact diameter needs --ring: exit 2 naming the option."""
    from dnarod.cli import main
    for extra, named in ((["--ring", "--kick", "1"], "--kick"), (["--ring", "--box-A", "30"], "--box-A"),
                         (["--contact-diameter-nm", "5"], "--contact-diameter-nm")):
        assert main(["dna-rod", "--random", "100", "--bp-per-point", "10", *extra, "-o", str(tmp_path / "r")]) == 2
        assert named in capsys.readouterr().err
