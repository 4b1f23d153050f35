"""The rodcore Python module: scene in (dict, TOML text, path), numpy arrays
out, initial fields from numpy or an HDF5 file, errors as Python exceptions.

The independent truth for the numbers is the exact twisted-rod wave (paper
Eq 24 in the form checked in docs/numerics.md, "Eq 24 as implemented"), written out here in
numpy from the formula, not taken from the solver.
"""
import math
import threading
import time

import h5py
import numpy as np
import pytest

import rodcore

D1, G03, O03 = 1.21, 1.0, 1.0


def exact_wave(s, t, A=0.3, L=2 * math.pi, mode=1, sigma=-1, branch=+1):
    """Eq 24 (docs/numerics.md form), kappa_p = k + Omega03 (sigma = -1), w from Eq 26."""
    k = 2 * math.pi * mode / L
    kappa = k + O03 if sigma == -1 else k - O03
    w = 0.5 * (math.sqrt(kappa**2 * (math.sqrt(D1) + 1) ** 2 + G03**2)
               + branch * math.sqrt(kappa**2 * (math.sqrt(D1) - 1) ** 2 + G03**2))
    a_w = w * G03 * A / (w**2 - D1 * kappa**2)
    th = w * t - k * s
    c, sn = np.cos(th), np.sin(th)
    z = np.zeros_like(s)
    return {
        "Gamma": np.stack([A * c, sigma * A * sn, G03 + z], axis=1),
        "gamma": np.stack([-kappa * A / w * c, -sigma * kappa * A / w * sn, z], axis=1),
        "omega": np.stack([sigma * a_w * c, a_w * sn, z], axis=1),
        "Omega": np.stack([-sigma * kappa * a_w / w * c, -kappa * a_w / w * sn, O03 + z], axis=1),
    }, w


def wave_scene(N=32, t_end=1.0, frames=3, fields=("internal", "energy")):
    return {
        "rod": {"length": 2 * math.pi, "points": N, "Gamma0": [0.0, 0.0, G03], "Omega0": [0.0, 0.0, O03]},
        "material": {"C": [1.0, 1.0, 1.19], "D": [D1, D1, 2.0207], "I": [1.0, 1.0, 2.0]},
        "solver": {"space": "spectral", "time": "dop853", "rtol": 1e-12, "atol": 1e-12},
        "output": {"t_end": t_end, "frames": frames, "fields": list(fields)},
    }


def test_tiny_scene_shapes_and_grids():
    N, T = 16, 4
    sc = wave_scene(N=N, frames=T, fields=["internal", "energy", "energy_parts", "centerline", "directors"])
    sc["initial"] = {"kind": "twisted_wave", "A": 0.3}
    out = rodcore.run(sc)
    assert out["time"].shape == (T,)
    np.testing.assert_allclose(out["time"], np.linspace(0, 1.0, T), rtol=0, atol=1e-14)
    np.testing.assert_allclose(out["s"], np.arange(N) * 2 * math.pi / N, rtol=0, atol=1e-14)
    assert set(out["fields"]) == {"gamma", "omega", "Gamma", "Omega"}
    for v in out["fields"].values():
        assert v.shape == (T, N, 3)
    assert out["energy"].shape == (T,)
    assert set(out["energy_parts"]) == {"kinetic_translational", "kinetic_rotational", "shear",
                                        "extension", "bend", "twist"}
    # the parts add up to the total (Appendix A), independently summed here
    total = sum(out["energy_parts"].values())
    np.testing.assert_allclose(total, out["energy"], rtol=1e-12)
    assert out["centerline"].shape == (T, N, 3)
    assert out["directors"].shape == (T, N, 3, 3)
    # directors [t][i][xyz][k]: columns are d_k, an orthonormal frame
    R = out["directors"]
    np.testing.assert_allclose(np.einsum("tiak,tial->tikl", R, R), np.broadcast_to(np.eye(3), (T, N, 3, 3)),
                               atol=1e-12)
    s = out["summary"]
    assert s["steps"] > 0 and s["rhs_evaluations"] >= s["steps"] and s["method"] == "spectral+dop853"
    assert out["scales"]["tau_ps"] == pytest.approx(0.94, abs=0.01)
    assert "[solver]" in out["scene"]


def test_only_requested_outputs_are_returned():
    out = rodcore.run({"rod": {"length": 1.0, "points": 8}, "output": {"t_end": 0.1, "fields": ["energy"]}})
    assert "fields" not in out and "centerline" not in out and "directors" not in out
    assert out["energy"].shape == (2,)


def test_file_initial_condition_round_trip_and_exact_solution(tmp_path):
    """ICs made in numpy, written with h5py, run as kind = "file": t = 0 comes
    back exactly and the last frame matches the exact wave."""
    N, L = 32, 2 * math.pi
    s = np.arange(N) * L / N
    f0, w = exact_wave(s, 0.0)
    with h5py.File(tmp_path / "ic.h5", "w") as f:
        f["s"] = s
        for name, v in f0.items():
            f[f"fields/{name}"] = v
    period = 2 * math.pi / w
    scene_text = f"""
[rod]
length = {L!r}
points = {N}
Omega0 = [0.0, 0.0, {O03!r}]
[material]
D = [{D1}, {D1}, 2.0207]
[initial]
kind = "file"
path = "ic.h5"
[solver]
rtol = 1e-12
atol = 1e-12
[output]
t_end = {period!r}
frames = 3
"""
    (tmp_path / "scene.toml").write_text(scene_text)
    out = rodcore.run(tmp_path / "scene.toml")
    for name in f0:
        np.testing.assert_array_equal(out["fields"][name][0], f0[name])  # bit-exact round trip
    for k, t in enumerate(out["time"]):
        ft, _ = exact_wave(s, t)
        for name in ft:
            np.testing.assert_allclose(out["fields"][name][k], ft[name], rtol=0, atol=1e-9, err_msg=name)
    # the same arrays given directly as initial= give the same run
    out2 = rodcore.run(wave_scene(N=N, t_end=period, frames=3), initial=f0)
    for name in f0:
        np.testing.assert_array_equal(out2["fields"][name], out["fields"][name])


def test_scene_as_toml_text_and_overrides():
    text = "[rod]\nlength = 2.0\npoints = 8\n[output]\nt_end = 0.5\nframes = 3\n"
    out = rodcore.run(text, set=["output.frames=5"])
    assert out["time"].shape == (5,)
    resolved = rodcore.resolve(text)
    assert "rtol = 1e-10" in resolved and 'kind = "rest"' in resolved


def test_output_file_matches_returned_arrays(tmp_path):
    sc = wave_scene(N=16, frames=3, fields=["internal", "energy", "centerline"])
    sc["initial"] = {"kind": "twisted_wave", "A": 0.3}
    out = rodcore.run(sc, output=tmp_path / "run.h5")
    with h5py.File(tmp_path / "run.h5", "r") as f:
        assert f.attrs["complete"] == 1
        np.testing.assert_array_equal(f["time"][:], out["time"])
        np.testing.assert_array_equal(f["s"][:], out["s"])
        for name in ("gamma", "omega", "Gamma", "Omega"):
            np.testing.assert_array_equal(f[f"fields/{name}"][:], out["fields"][name])
        np.testing.assert_array_equal(f["energy"][:], out["energy"])
        np.testing.assert_array_equal(f["centerline"][:], out["centerline"])
        assert f.attrs["summary.steps"] == out["summary"]["steps"]


def test_input_errors_are_value_errors_with_the_key():
    with pytest.raises(ValueError, match=r"solver\.rtoll.*did you mean solver\.rtol\?"):
        rodcore.run({"rod": {"length": 1.0, "points": 8}, "solver": {"rtoll": 1e-8}})
    with pytest.raises(rodcore.InputError,
                       match=r"rod\.points: found 3; solver\.space = \"spectral\" needs at least 4"):
        rodcore.run({"rod": {"length": 1.0, "points": 3}})
    with pytest.raises(ValueError, match=r"initial\['Omega'\] has 7 points"):
        rodcore.run({"rod": {"length": 1.0}}, initial={"gamma": np.zeros((8, 3)), "omega": np.zeros((8, 3)),
                                                       "Gamma": np.zeros((8, 3)), "Omega": np.zeros((7, 3))})
    with pytest.raises(ValueError, match="rod.points = 16 but the initial arrays have N = 8"):
        rodcore.run({"rod": {"length": 1.0, "points": 16}}, initial={n: np.zeros((8, 3)) for n in
                                                                     ("gamma", "omega", "Gamma", "Omega")})
    with pytest.raises(ValueError, match="does not exist"):
        rodcore.run("no/such/scene.toml")
    with pytest.raises(ValueError, match="not valid TOML"):
        rodcore.run("[rod\nlength = 1")


def test_numerical_errors_are_floating_point_errors():
    sc = wave_scene(N=16, t_end=2.0, frames=11)
    sc["initial"] = {"kind": "twisted_wave", "A": 0.5}
    sc["solver"].update(rtol=1e-3, atol=1e-3)
    sc["checks"] = {"max_energy_drift": 1e-14}
    with pytest.raises(FloatingPointError, match="energy drift"):
        rodcore.run(sc)
    with pytest.raises(rodcore.NumericalError):
        rodcore.run(sc)


def test_gil_is_released_while_integrating():
    sc = wave_scene(N=128, t_end=6.0, frames=2, fields=["energy"])
    sc["initial"] = {"kind": "twisted_wave", "A": 0.3}
    sc["solver"].update(time="rk4", dt=0.002)
    ticks, done = [], []

    def work():
        rodcore.run(sc)
        done.append(time.perf_counter())

    start = time.perf_counter()
    th = threading.Thread(target=work)
    th.start()
    while th.is_alive():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    th.join()
    duration = done[0] - start
    assert duration > 0.05, "the run is too short to tell"
    gaps = np.diff([start] + ticks + [done[0]])
    # with the GIL held, this thread would stall for the whole run
    assert gaps.max() < 0.5 * duration, (gaps.max(), duration)


def test_kinds_and_analytic():
    kinds = {k["name"]: k for k in rodcore.kinds()}
    assert {"rest", "twisted_wave", "file"} <= set(kinds)
    assert any(p["name"] == "A" for p in kinds["twisted_wave"]["numbers"])
    # analytic.* reproduces the formula written out above (Eqs 24, 26)
    s = np.linspace(0, 2 * math.pi, 9)
    ex, w = exact_wave(s, 0.7, A=0.3)
    wave = rodcore.analytic.TwistedWave(A=0.3, k=1.0, Gamma03=G03, Omega03=O03, D1=D1)
    assert wave.w() == pytest.approx(w, rel=1e-14)
    assert rodcore.analytic.dispersion(wave.kappa(), D1, G03, 1) == pytest.approx(w, rel=1e-14)
    got = wave.fields(s, 0.7)
    for name in ex:
        np.testing.assert_allclose(got[name], ex[name], atol=1e-14)
