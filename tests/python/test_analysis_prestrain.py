"""The pre-strained rod of workflows/steps/prestrain.py (the rod at the MD's rest length),
run by rodsim and measured by the workflow's analysis, against a linearisation built here.

Independent truth: the rod equations (paper Eqs 11-14, rho = I1 = C1 = 1) linearised about
the straight rod held at Gamma3 = G under the axial force T = C3 (G - 1), planar polarisation
(gamma1, omega2, Gamma1, Omega2):
    d_t gamma1 = d_s n1 + (Omega x n)_1      = d_s Gamma1 + T Omega2
    d_t omega2 = D1 d_s Omega2 + (Gamma x n)_2 = D1 d_s Omega2 + (G - T) Gamma1
    d_t Gamma1 = d_s gamma1 - (omega x Gamma)_1 = d_s gamma1 - G omega2
    d_t Omega2 = d_s omega2
For exp(i k s) this is d_t y = M y; the frequencies are |Im| of M's eigenvalues (numerically,
not through the closed form of mdbridge/analysis/dispersion.py). The lab speed of the
fundamental is G omega / k. The twist only relabels k for an isotropic rod
(docs/analysis.md), which the run itself checks."""
import math
import subprocess

import numpy as np
import pytest

from dna_models.units import Units
from mdbridge.analysis import BasePairTrajectory, WaveAnalysis
from dnarod.steps.matched import mode_fit, rod_matched
from dnarod.steps.prestrain import make_prestrain_scene

SCENE = "workflows/scenes/dna158.toml"


def linear_frequencies(k, D1, G, T):
    M = np.array([[0, 0, 1j * k, T],
                  [0, 0, G - T, 1j * k * D1],
                  [1j * k, -G, 0, 0],
                  [0, 1j * k, 0, 0]], complex)
    w = np.sort(np.abs(np.linalg.eigvals(M).imag))
    return w[0], w[-1]  # bend, shear (each appears twice: +-omega)


@pytest.mark.parametrize("G", [1.01])
def test_prestrained_rod_speed(rodsim, tmp_path, G):
    from pathlib import Path
    root = Path(__file__).resolve().parents[2]
    u = Units.paper()
    meta = make_prestrain_scene(root / SCENE, tmp_path / "ps.toml", G, 0.001, 1000.0, 5.0)
    subprocess.run([str(rodsim), "run", str(tmp_path / "ps.toml"), "-o", str(tmp_path / "ps.h5")],
                   check=True, capture_output=True)
    traj = BasePairTrajectory.from_rod_h5(tmp_path / "ps.h5", 158)
    assert np.linalg.norm(traj.period[0]) == pytest.approx(158 * 3.38, rel=1e-9)  # the box's length
    a = WaveAnalysis(traj, in_plane=meta["in_plane"], offset=True, n_boot=0).run()
    f = mode_fit(a)
    L_fid = 158 * 3.38 / (u.ell_A * G)
    k = 2 * math.pi / L_fid
    T = u.C_star[2] * (G - 1)
    w_bend, _ = linear_frequencies(k, u.D_star[0], G, T)
    predicted = u.velocity_to_A_per_ps(G * w_bend / k)
    assert f["speed_A_per_ps"] == pytest.approx(predicted, rel=2e-4)
    assert a.results.planarity["planarity"] < 1e-6        # the scene's in-plane direction is right
    # control: without the axial force (Eq 39 as printed) the speed would be half
    w0, _ = linear_frequencies(k, u.D_star[0], G, 0.0)
    assert abs(u.velocity_to_A_per_ps(G * w0 / k) - f["speed_A_per_ps"]) > 0.3
    assert meta["dispersion"]["bend_branch_speed_A_per_ps"] == pytest.approx(predicted, rel=1e-9)
    # the workflow's step reads the same run through the scene's side record (n_bp, in_plane)
    from dnarod.steps.analyse import analyse_rod
    s = analyse_rod(tmp_path / "ps.toml", tmp_path / "ps.h5", tmp_path / "analysis", n_boot=0)
    assert s["wave_speed_A_per_ps"] == pytest.approx(f["speed_A_per_ps"], rel=1e-9)
    assert s["prestrain"]["Gamma03"] == G and s["plane"]["in_plane_source"] == "scene"
    m = rod_matched(traj, tmp_path / "ps.h5", {"initial": {"rise_A": 3.38}})
    assert m["tension_pN"] == pytest.approx(u.C * u.C_star[2] * (G - 1) * 1e12, rel=1e-4)  # ~10.8 pN


def test_buckling_strain_from_the_linearisation():
    """The closed-form Euler load of dispersion.critical_compression is where the bend
    branch of the matrix above reaches zero frequency."""
    from mdbridge.analysis.dispersion import critical_compression
    u = Units.paper()
    L = 158 * 3.38 / u.ell_A
    c = critical_compression(L, u.D_star[0], u.C_star[2])
    k = 2 * math.pi / L
    e = c["strain"]
    assert -0.004 < e < -0.003                               # ~0.35 %
    w_just_stable, _ = linear_frequencies(k, u.D_star[0], 1 + 0.99 * e, u.C_star[2] * 0.99 * e)
    w_at, _ = linear_frequencies(k, u.D_star[0], 1 + e, u.C_star[2] * e)
    assert w_just_stable > 1e-4 and w_at < 1e-6
