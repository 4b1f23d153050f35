"""No silent bad numbers: each numerical check of rodsim, provoked
on purpose, stops the run with exit status 3 and a message that says what
happened, where (t, and s where there is a place) and what to try; the
frames written before it stay readable in OUT.h5 with complete = 0 and the
error recorded. The provocations are chosen so that the failure is certain
from first principles (overflow of 1e200**2, a step-size floor above the step
the tolerance needs, an RK4 step beyond the imaginary-axis stability limit,
an amplitude that drives Gamma3 through zero, a drift bound below round-off)."""
import math
import re
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "workflows" / "scenes"


def run(rodsim, *args):
    return subprocess.run([str(rodsim), *map(str, args)], capture_output=True, text=True, timeout=300)


def stopped_run(rodsim, out, *args):
    """Run that must stop with a numerical error; returns (message, frames)."""
    p = run(rodsim, "run", *args, "-o", out)
    assert p.returncode == 3, p.stderr
    assert p.stderr.startswith("rodsim: error: "), p.stderr
    m = re.search(r"(\d+) frame\(s\) written so far are in (\S+) \(attribute complete = 0\)", p.stderr)
    assert m and m.group(2) == str(out), p.stderr
    n = int(m.group(1))
    assert not Path(str(out) + ".partial").exists()
    with h5py.File(out, "r") as f:
        assert f.attrs["complete"] == 0
        assert f.attrs["error"] in p.stderr
        assert f["time"].shape == (n,)
        for name in ("gamma", "omega", "Gamma", "Omega"):
            assert f[f"fields/{name}"].shape[0] == n
            assert np.all(np.isfinite(f[f"fields/{name}"][...])), "a written frame holds non-finite numbers"
    return p.stderr, n


def write_ic(path, N, L, spike):
    """Straight untwisted rod at rest with gamma1 = `spike` at one point."""
    y = np.zeros((4, N, 3))
    y[2, :, 2] = 1.0  # Gamma = (0, 0, 1)
    y[0, N // 3, 0] = spike
    with h5py.File(path, "w") as f:
        f["s"] = np.arange(N) * L / N
        for k, name in enumerate(("gamma", "omega", "Gamma", "Omega")):
            f[f"fields/{name}"] = y[k]


def write_scene(path, ic, time="rk4", dt=0.01, extra=""):
    path.write_text(f'[rod]\nlength = {2 * math.pi!r}\npoints = 16\nOmega0 = [0.0, 0.0, 0.0]\n'
                    f'[initial]\nkind = "file"\npath = "{ic.name}"\n'
                    f'[solver]\ntime = "{time}"\ndt = {dt}\ndt_min = {min(dt, 1e-12)}\n'
                    f'[output]\nt_end = 1.0\nframes = 11\n{extra}')


def test_overflow_to_inf_nan_stops_and_names_field_s_and_t(rodsim, tmp_path):
    # gamma1 = 1e150: the energy (1e300) is finite, the first step overflows.
    write_ic(tmp_path / "ic.h5", 16, 2 * math.pi, 1e150)
    write_scene(tmp_path / "s.toml", tmp_path / "ic.h5", extra="fields = [\"internal\"]\n")
    msg, n = stopped_run(rodsim, tmp_path / "o.h5", tmp_path / "s.toml")
    assert "non-finite value (NaN/Inf) in " in msg
    assert re.search(r"in (gamma|omega|Gamma|Omega)[123] at s = [-0-9.e]+, t = [0-9.e-]+", msg), msg
    assert "reduce solver.dt" in msg
    assert n == 1  # the t = 0 frame, written before the blow-up


def test_overflow_in_an_adaptive_step_stops(rodsim, tmp_path):
    write_ic(tmp_path / "ic.h5", 16, 2 * math.pi, 1e150)
    write_scene(tmp_path / "s.toml", tmp_path / "ic.h5", time="dop853", dt=0.01,
                extra="fields = [\"internal\"]\n")
    msg, n = stopped_run(rodsim, tmp_path / "o.h5", tmp_path / "s.toml")
    assert "non-finite numbers (NaN/Inf) in a step at t = " in msg
    assert "reduce dt or rtol/atol" in msg
    assert n == 1


def test_initial_energy_overflow_is_named(rodsim, tmp_path):
    # gamma1 = 1e200: |gamma|^2 = 1e400 overflows, so E(t = 0) = inf.
    write_ic(tmp_path / "ic.h5", 16, 2 * math.pi, 1e200)
    write_scene(tmp_path / "s.toml", tmp_path / "ic.h5", extra="fields = [\"internal\"]\n")
    msg, n = stopped_run(rodsim, tmp_path / "o.h5", tmp_path / "s.toml")
    assert "energy is not finite" in msg and "t = 0" in msg and "initial fields" in msg
    assert n == 0


def test_step_size_underflow_stops(rodsim, tmp_path):
    # The 1e-12 tolerance needs steps far below the floor dt_min = dt = 0.5.
    msg, n = stopped_run(rodsim, tmp_path / "o.h5", SCENES / "twisted_wave.toml",
                         "--set", "solver.dt=0.5", "--set", "solver.dt_min=0.5", "--set", "solver.rtol=1e-12",
                         "--set", "solver.atol=1e-12")
    assert "step size underflow at t = " in msg and "< solver.dt_min = 0.5" in msg
    assert "increase rod.points" in msg or "loosen rtol/atol" in msg
    assert n >= 1


def linearised_rk4_limit(C, D, I, Gamma0, Omega0, wavenumbers):
    """RK4 step limit 2.8 / max |eigenvalue| of Eqs 11-14 linearised about the
    uniform rest state (Gamma = Gamma0, Omega = Omega0, gamma = omega = 0),
    written out by hand here (not read off the solver): on a Fourier mode
    d/ds -> i k and, to first order in (gamma, omega, dGamma, dOmega),
      d gamma/dt = C ik dG + Omega0 x C dG
      d omega/dt = I^-1 [D ik dO + Omega0 x D dO + Gamma0 x C dG]
      d Gamma/dt = ik gamma + Omega0 x gamma - omega x Gamma0
      d Omega/dt = ik omega - omega x Omega0."""
    C, D, I = np.diag(C), np.diag(D), np.diag(I)
    Iinv = np.linalg.inv(I)

    def cross(a):  # matrix of a x .
        return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]], dtype=float)

    G0, O0 = cross(Gamma0), cross(Omega0)
    radius = 0.0
    for k in wavenumbers:
        M = np.zeros((12, 12), dtype=complex)
        M[0:3, 6:9] = 1j * k * C + O0 @ C
        M[3:6, 9:12] = Iinv @ (1j * k * D + O0 @ D)
        M[3:6, 6:9] = Iinv @ (G0 @ C)
        M[6:9, 0:3] = 1j * k * np.eye(3) + O0
        M[6:9, 3:6] = G0          # - omega x Gamma0 = Gamma0 x omega
        M[9:12, 3:6] = 1j * k * np.eye(3) + O0
        radius = max(radius, np.abs(np.linalg.eigvals(M)).max())
    return 2.8 / radius


def test_fixed_step_beyond_cfl_stops_before_the_first_step(rodsim, tmp_path):
    msg, n = stopped_run(rodsim, tmp_path / "o.h5", SCENES / "twisted_wave.toml",
                         "--set", "solver.time=rk4", "--set", "solver.dt=1.0")
    m = re.search(r"solver.dt = 1 exceeds the RK4 stability limit ([0-9.e-]+)", msg)
    assert m, msg
    # The exact limit for the scene's uniform twisted rod: spectral, N = 32,
    # L = 2 pi: the resolved modes are k = 0..15 (Nyquist zeroed).
    exact = linearised_rk4_limit([1.0, 1.0, 1.19], [1.21, 1.21, 2.0207], [1.0, 1.0, 2.0],
                                 [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], range(16))
    assert float(m.group(1)) == pytest.approx(exact, rel=1e-5)
    # and it is not the wave-speed estimate 2.8 / (1.1 x 15) it replaced
    assert abs(float(m.group(1)) - 2.8 / (1.1 * 15)) > 1e-3
    assert "use solver.dt <=" in msg
    assert n == 0


def test_fold_stops_with_place_and_time(rodsim, tmp_path):
    msg, n = stopped_run(rodsim, tmp_path / "o.h5", SCENES / "untwisted_wave.toml",
                         "--set", "initial.epsilon=3.0", "--set", "output.t_end=10")
    assert re.search(r"the rod folded \(Gamma3 = -?[0-9.e-]+ <= 0\) at s = [0-9.e-]+, t = [0-9.e-]+", msg), msg
    assert "lower the amplitude" in msg and "checks.stop_on_fold = false" in msg
    assert n >= 1


def test_energy_drift_beyond_the_bound_stops(rodsim, tmp_path):
    msg, n = stopped_run(rodsim, tmp_path / "o.h5", SCENES / "twisted_wave.toml",
                         "--set", "checks.max_energy_drift=1e-15", "--set", "solver.rtol=1e-4",
                         "--set", "solver.atol=1e-4")
    assert re.search(r"relative energy drift [0-9.e-]+ at t = [0-9.e-]+ exceeds checks.max_energy_drift = 1e-15",
                     msg), msg
    assert "tighten solver.rtol/atol" in msg
    assert n >= 1


def test_director_norm_bound_stops(rodsim, tmp_path):
    # Quaternion directors are unit to round-off (~1e-16), never to 1e-300.
    msg, n = stopped_run(rodsim, tmp_path / "o.h5", SCENES / "twisted_wave.toml",
                         "--set", "checks.max_director_norm_error=1e-300")
    assert re.search(r"director norm error [0-9.e-]+ at t = [0-9.e-]+ exceeds checks.max_director_norm_error", msg)
    assert n == 0 or n >= 1  # the count is checked against the file in stopped_run
