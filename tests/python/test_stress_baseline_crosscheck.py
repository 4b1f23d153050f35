"""Cross-check of rodsim against the independent numpy/scipy re-implementation of
Eqs 11-14 (bench/baseline_numpy.py), and of that baseline against the exact
twisted-rod wave (Eq 24), so the agreement is between two codes of which one is
itself checked against an exact solution. Also the band-limited resampling the
work-precision benchmark uses to compare runs on different grids."""
import math
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest
from benchscripts import load_bench

ROOT = Path(__file__).resolve().parents[2]
baseline_numpy = load_bench("baseline_numpy.py")
workprecision = load_bench("workprecision.py")
stability = load_bench("stress/stability.py")

SCENES = ROOT / "bench" / "scenes"
FIELDS = ("gamma", "omega", "Gamma", "Omega")


def rodsim_run(rodsim, scene, out, sets):
    cmd = [str(rodsim), "run", str(scene), "-o", str(out), "--quiet"]
    for k, v in sets.items():
        cmd += ["--set", f"{k}={v}"]
    subprocess.run(cmd, check=True, capture_output=True)
    with h5py.File(out) as f:
        return np.concatenate([np.transpose(np.asarray(f["fields"][n]), (0, 2, 1)) for n in FIELDS], axis=1)


def size_of_motion(y, Gamma0, Omega0):
    rest = workprecision.rest_state((Gamma0, Omega0), y.shape[-1])
    return np.max(np.abs(y - rest))


def test_baseline_reproduces_exact_twisted_wave(rodsim, tmp_path):
    # Initial state from rodsim (frame 0), then the baseline alone vs Eq 24.
    t_end = 5.0
    rodsim_run(rodsim, SCENES / "p1_twisted_wave.toml", tmp_path / "p1.h5", {"output.t_end": 1e-6})
    t, y, _ = baseline_numpy.run(tmp_path / "p1.h5", "spectral", "DOP853", 1e-11, 1e-11, t_end, 2)
    L = 2 * math.pi
    s = L * np.arange(64) / 64
    exact = workprecision.twisted_wave_exact(s, t_end, L, mode=2, A=0.5, Gamma03=1.0, Omega03=1.0, D1=1.21)
    # The initial state itself must be the exact wave at t = 0 (rodsim's IC is checked too).
    exact0 = workprecision.twisted_wave_exact(s, 0.0, L, mode=2, A=0.5, Gamma03=1.0, Omega03=1.0, D1=1.21)
    assert np.max(np.abs(y[0] - exact0)) < 1e-13
    err = np.max(np.abs(y[-1] - exact)) / size_of_motion(exact, (0, 0, 1), (0, 0, 1))
    assert err < 1e-8, err


@pytest.mark.parametrize("space,N", [("spectral", 160), ("fd4", 316)])
def test_rodsim_agrees_with_independent_baseline_on_dna_scene(rodsim, tmp_path, space, N):
    # Same operator, integrator family (DOP853) and tolerance; different code,
    # language and error-control implementation: the difference must be at the
    # level of the tolerance, far below any physics error (a wrong sign or
    # factor in either code gives O(1e-2) or more after 50 time units).
    t_end, rtol = 50.0, 1e-11
    y_rod = rodsim_run(rodsim, ROOT / "workflows" / "scenes" / "dna158.toml", tmp_path / "p2.h5",
                       {"rod.points": N, "solver.space": space, "solver.rtol": rtol, "solver.atol": rtol,
                        "output.t_end": t_end, "output.frames": 2, "output.fields": '["internal"]'})
    t, y_np, _ = baseline_numpy.run(tmp_path / "p2.h5", space, "DOP853", rtol, rtol, t_end, 2)
    assert np.array_equal(y_np[0], y_rod[0])
    with h5py.File(tmp_path / "p2.h5") as f:
        G0, O0 = tuple(f.attrs["rod.Gamma0"]), tuple(f.attrs["rod.Omega0"])
    scale = size_of_motion(y_rod[-1], G0, O0)
    diff = np.max(np.abs(y_rod[-1] - y_np[-1])) / scale
    moved = np.max(np.abs(y_rod[-1] - y_rod[0])) / scale
    assert moved > 0.1, "the test needs a state that has changed substantially"
    assert diff < 1e-8, diff


def test_fourier_resample_is_exact_for_band_limited_data():
    L = 3.0

    def f(s):
        return np.array([np.cos(2 * np.pi * 3 * s / L) + 0.2 * np.sin(2 * np.pi * 7 * s / L), 1.0 + 0 * s])
    fine = f(L * np.arange(96) / 96)
    for N in (32, 48, 60, 128):
        got = workprecision.fourier_resample(fine, N)
        assert np.max(np.abs(got - f(L * np.arange(N) / N))) < 1e-13, N


@pytest.mark.parametrize("space", ["spectral", "fd4"])
def test_rodsim_agrees_with_baseline_on_random_smooth_state(rodsim, tmp_path, space):
    # Every component excited (the DNA scene leaves twist and extension at rest,
    # so it cannot see an error in D3, I3 or C3 terms): smooth random fields of
    # modes 1..4, an anisotropic material and a twisted, sheared intrinsic shape.
    N, L = 32, 2 * math.pi
    G0, O0 = (0.1, -0.05, 1.0), (0.2, 0.1, 0.7)
    rng = np.random.default_rng(3)
    s = L * np.arange(N) / N
    y0 = stability.rest_state(N, G0, O0)
    for m in range(1, 5):
        a, b = rng.standard_normal((2, 12, 1)) * 0.05 / m
        y0 += a * np.cos(m * s) + b * np.sin(m * s)
    ic = tmp_path / "rand.h5"
    stability.write_initial(ic, y0, L)
    scene = tmp_path / "rand.toml"
    stability.write_scene(scene, N, L, G0, O0, ic, {"space": space, "time": "dop853", "rtol": 1e-11,
                                                    "atol": 1e-11}, t_end=3.0)
    text = scene.read_text().replace("[solver]", "[material]\nC = [1.0, 0.8, 1.19]\nD = [1.21, 1.5, 2.02]\n"
                                                  "I = [1.0, 1.3, 2.0]\n\n[solver]")
    scene.write_text(text)
    y_rod = rodsim_run(rodsim, scene, tmp_path / "rand_out.h5", {})
    t, y_np, _ = baseline_numpy.run(tmp_path / "rand_out.h5", space, "DOP853", 1e-11, 1e-11, 3.0, 2)
    scale = size_of_motion(y_rod[-1], G0, O0)
    for r in range(12):  # every component moved
        assert np.max(np.abs(y_rod[-1][r] - y_rod[0][r])) > 1e-3 * scale, r
    diff = np.max(np.abs(y_rod[-1] - y_np[-1])) / scale
    assert diff < 1e-8, diff
