"""The equilibration stage before the kick and the axis-only barostat.

Truths: v-rescale at T gives a kinetic temperature near T (canonical
fluctuation sqrt(2/(3N)) ~ 2 % for 1,335 atoms); the final velocities are the
stage's velocities plus the rod field of the paper's Table 1 written out in
test_gromacs_build.py (a formula, not the code's output); the barostat acts
along the helix axis only (box edges across it unchanged to the last digit);
the stationarity test accepts noise and rejects a trend (synthetic series)."""
import numpy as np
import pytest

from mdbridge.md.gromacs.equilibrate import stationarity
from mdbridge.md.gromacs.gro import read_gro
from mdbridge.md.gromacs.mdp import MdSettings
from mdbridge.md.gromacs.velocities import kinetic_temperature
from test_gromacs_build import _expected_rod_velocity, _tpr, make  # noqa: F401  (gmx: conftest)


def test_stationarity_accepts_noise_and_rejects_a_trend():
    rng = np.random.default_rng(1)
    t = np.arange(0, 20, 0.1)
    flat = 300 + rng.normal(0, 5, t.size)
    assert stationarity(t, flat)["stationary"]
    trend = flat + 2.0 * t            # 2 K/ps: the quarter means differ by 10 K, noise 5 K
    r = stationarity(t, trend)
    assert not r["stationary"] and r["change_between_quarters"] == pytest.approx(10.0, abs=1.5)


@pytest.fixture(scope="module")
def equilibrated(gmx, tmp_path_factory):
    d = tmp_path_factory.mktemp("eq")
    rod, info = make(d, T=300.0, seed=5, gmx=gmx, minimize=True, protocol="equilibrated",
                     equilibrate_ps=2.0, settings=MdSettings(nsteps=100))
    return d, rod, info


def test_kick_is_added_to_the_equilibrated_velocities(equilibrated, gmx):
    d, rod, info = equilibrated
    assert info["protocol"] == "equilibrated" and info["equilibration"]["ps"] == 2.0
    eq, conf = read_gro(d / "eq.gro"), read_gro(d / "conf.gro")
    u = _tpr(d, gmx)
    m = u.atoms.masses
    # the stage's velocities are canonical at 300 K: +-2.2 % (1 sigma) for 1,335 atoms
    T = kinetic_temperature(m, eq.v, 3 * len(m) - 3)
    assert 280.0 < T < 320.0, T
    shift = np.asarray(info["box"]["shift_A"])
    # base pair of each atom by the documented numbering (strand II residue r pairs with
    # strand I residue 2n + 1 - r): after 2 ps at 300 K the geometric nearest-base rule
    # of test_gromacs_build can pick a neighbour of a fraying pair
    n = info["n_bp"]
    r = u.atoms.resids
    pair = np.where(r <= n, r - 1, 2 * n - r)
    v_rod = _expected_rod_velocity(conf.x * 10.0, pair, rod, shift)
    # conf.gro = eq.gro velocities + the rod field, to the .gro rounding (1e-4 nm/ps)
    assert np.abs(conf.v - eq.v - v_rod).max() < 2.5e-4
    assert np.abs(v_rod).max() > 0.05          # control: the rod field is not negligible


def test_axial_pressure_changes_only_the_axis(gmx, tmp_path):
    rod, info = make(tmp_path, T=300.0, seed=5, gmx=gmx, minimize=True, protocol="equilibrated",
                     equilibrate_ps=1.0, axial_pressure=True)
    a = info["box"]["axis"]
    before = np.asarray(info["box"]["box_A"]) / 10.0
    after = np.asarray(info["box_nm"])
    across = [k for k in range(3) if k != a]
    assert np.array_equal(np.round(after[across], 5), np.round(before[across], 5))
    assert after[a] != pytest.approx(before[a], abs=1e-4)
    zt = info["equilibration"]["axial_pressure"]
    assert zt["box_length_start_nm"] == pytest.approx(before[a], abs=1e-3)
    assert zt["zero_tension_length_nm"] > 0


def test_equilibrated_protocol_needs_a_temperature(gmx, tmp_path):
    from dna_models.errors import InputError
    with pytest.raises(InputError, match="temperature"):
        make(tmp_path, T=0.0, gmx=gmx, protocol="equilibrated")


def test_edr_temperature_is_gmx_energys_own_average(equilibrated, gmx, tmp_path):
    """The coarse-graining's --edr temperature (read through mdbridge/md/gromacs/energy.py)
    against the average gmx energy prints itself, from the stage's real eq.edr."""
    import re
    import subprocess
    from mdbridge.coarsegrain.temperature import edr_temperature
    d = equilibrated[0]
    p = subprocess.run([gmx, "energy", "-f", str(d / "eq.edr"), "-o", str(tmp_path / "T.xvg")],
                       input="Temperature\n\n", capture_output=True, text=True, check=True)
    avg = float(re.search(r"^Temperature\s+(\S+)", p.stdout, re.M).group(1))
    T, sd = edr_temperature(d / "eq.edr", gmx=gmx)
    assert T == pytest.approx(avg, abs=1e-3) and 0 < sd < 30
    # control: a later start reads a different stretch of the same file
    assert edr_temperature(d / "eq.edr", gmx=gmx, begin_ps=1.5)[0] != pytest.approx(T, abs=1e-6)
