"""The MD tension (mdbridge/md/gromacs/tension.py) on real GROMACS runs of the 21-bp duplex.

Truth: a duplex in a box stretched along its axis pulls on it. The same equilibrated,
unkicked duplex (300 K, smooth cut-offs, 2 fs, h-bonds) in its built box and in the box
stretched affinely by 20 % along the helix axis (far beyond linear elasticity: a test of sign, axis
and cross-section that a few ps can resolve), 10 ps of NVT each, energies every 5 steps:
the stretched box must carry a positive tension, many standard errors above the built
box's. It fails if the sign convention, the axis (the pressure component across the axis
does not respond like this) or the cross-section were wrong. The validation against the
stretch modulus and the zero-tension length (long runs) is bench/md_tension.py, docs/md.md."""
import math

import numpy as np
import pytest

from mdbridge.md.builder import build_duplex
from mdbridge.md.gromacs.box import plan_box
from mdbridge.md.gromacs.gro import read_gro
from mdbridge.md.gromacs.inputs import build_inputs
from mdbridge.md.gromacs.mdp import MdSettings
from mdbridge.md.gromacs.run import _set_keys, run_md
from mdbridge.md.gromacs.tension import mean_with_error, stretch_box, tension_series
from test_gromacs_build import table1_rod

STRETCH = 1.20
PS = 10.0


@pytest.fixture(scope="module")
def two_boxes(gmx, tmp_path_factory):
    d = tmp_path_factory.mktemp("tension")
    rod = table1_rod(21, 2, A=0.0, Av=0.0, w=0.0)          # straight and unkicked
    seq = "ACGTTGCAGGCATCGATCCGA"
    st = build_duplex(seq, rod.origins_A, rod.R, periodic_box=(0, rod.closure_length_A, 0))
    box = plan_box(rod.origins_A[None], rod.origins_A, rod.closure_length_A, rod_run_ps=1.0)
    s = MdSettings(dt_ps=0.002, constraints="h-bonds", cutoffs="smooth", nsteps=100)
    build_inputs(d / "base", st, rod, box, sequence=seq, temperature_K=300.0, seed=3, settings=s,
                 minimize=True, gmx=gmx, protocol="equilibrated", equilibrate_ps=2.0)
    out = {}
    for f in (1.0, STRETCH):
        r = d / f"box_{f:g}"
        stretch_box(d / "base", r, f)
        mdp = (r / "md.mdp").read_text()
        (r / "md.mdp").write_text(_set_keys(mdp, {
            "tcoupl": "V-rescale", "tc-grps": "System", "tau-t": 1.0, "ref-t": 300,
            "nstenergy": 5, "nstcalcenergy": 5, "nstxout-compressed": 1000}))
        run_md(r, ps=PS, gmx=gmx, threads=1, checks=False, stream=None)
        ser = tension_series(r, gmx)
        out[f] = (r, ser, mean_with_error(ser["time"], ser["tension_pN"], discard_ps=1.0))
    return d, out


def test_stretched_box_pulls(two_boxes):
    d, out = two_boxes
    (_, s1, F1), (r2, s2, F2) = out[1.0], out[STRETCH]
    assert s2["axis"] == 1 and s1["axis"] == 1                     # the scene's helix axis, Y
    assert s2["length_nm"][0] == pytest.approx(STRETCH * s1["length_nm"][0], rel=1e-4)
    assert s2["area_nm2"][0] == pytest.approx(s1["area_nm2"][0], rel=1e-6)
    # the box in the run is the stretched one (conf.gro of the run, not of the base)
    assert read_gro(r2 / "conf.gro").box[1] == pytest.approx(s2["length_nm"][0])
    err = math.hypot(F1["sem"], F2["sem"])
    assert np.isfinite(err) and err > 0
    assert F2["mean"] > 0, F2
    # measured: 210 +- 30 pN (7.1 sigma) and 172; with 6-ps runs 222 +- 44 (5.0)
    assert F2["mean"] - F1["mean"] > 3.0 * err, (F1, F2)


def test_transverse_component_does_not_respond_like_the_axis(two_boxes, gmx):
    """Control: the same quantity across the axis (-P_xx x the box's y-z face) changes by
    less than the axial tension does: the axis is the one that carries the stretch."""
    d, out = two_boxes
    dF = {}
    for f in (1.0, STRETCH):
        s = tension_series(out[f][0], gmx, axis=0)
        dF[f] = mean_with_error(s["time"], s["tension_pN"], discard_ps=1.0)["mean"]
    axial = out[STRETCH][2]["mean"] - out[1.0][2]["mean"]
    assert abs(dF[STRETCH] - dF[1.0]) < 0.5 * axial
