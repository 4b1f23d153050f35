"""The paper's rod at the MD's box (mdbridge/analysis/box_rod.py) against independent truths:
Gamma3 = 1 under the tension (the paper's own rod stands at 1 + T / C3); the stretch modes
sqrt(C3 / rho) q move by the mass alone; and in the string limit (bending 1e-4 of the paper's)
the lowest bend mode obeys omega = k sqrt(T / mu) with the box's k and mu, which sets the
box row over the paper row to sqrt((1 + T / C3) rho_paper / rho_md): the control without the
length factor (the mass alone) misses it by the 1.7 % that the pre-stretch makes at 38 pN."""
import json
import math
from pathlib import Path

import numpy as np
import pytest

from dna_models.errors import InputError
from dna_models.units import Units
from mdbridge.analysis.box_rod import md_mass_inertia, paper_rod_box
from mdbridge.analysis.dispersion_prediction import Duplex, frequencies, paper_material, rest_state
from mdbridge.rod.linear import UniformMaterial

ROOT = Path(__file__).resolve().parents[2]
DUPLEX = Duplex(158, 15)
T = 38.0
RHO, I_MD = 0.94, np.diag([1.5, 0.5, 1.7])


def test_gamma3_is_one_at_the_box():
    paper = paper_material(DUPLEX)
    box = paper_rod_box(paper, T, RHO, I_MD)
    C3 = Units.paper().C_star[2]
    eps = T * 1e-12 / Units.paper().C / C3
    assert rest_state(box, DUPLEX, T)["Gamma"][2] == pytest.approx(1.0, abs=1e-12)
    assert rest_state(paper, DUPLEX, T)["Gamma"][2] == pytest.approx(1.0 + eps, abs=1e-12)


def test_stretch_moves_by_the_mass_and_the_string_by_length_and_mass():
    paper = paper_material(DUPLEX)
    u = Units.paper()
    eps = T * 1e-12 / u.C / u.C_star[2]
    f_paper = frequencies(paper, DUPLEX, T, 3)
    f_box = frequencies(paper_rod_box(paper, T, RHO, I_MD), DUPLEX, T, 3)
    for n in (1, 2, 3):
        assert f_box["stretch"][n][0] / f_paper["stretch"][n][0] == pytest.approx(math.sqrt(1 / RHO), rel=1e-6)
    # the string limit: bending 1e-4 of the paper's
    K = np.array(paper.K, float)
    K[3, 3] *= 1e-4
    K[4, 4] *= 1e-4
    soft = UniformMaterial(K=K, I=paper.I, rho=paper.rho, Gamma0=paper.Gamma0, Omega0=paper.Omega0)
    w_paper = frequencies(soft, DUPLEX, T, 1)["bend"][1][0]
    w_box = frequencies(paper_rod_box(soft, T, RHO, I_MD), DUPLEX, T, 1)["bend"][1][0]
    expected = math.sqrt((1 + eps) / RHO)
    assert w_box / w_paper == pytest.approx(expected, rel=2e-3)
    assert abs(w_box / w_paper - math.sqrt(1 / RHO)) > 5e-3       # the control: mass alone


def test_md_mass_inertia_from_build_and_from_params(tmp_path):
    a = md_mass_inertia(ROOT / "results/dispersion/build.json")
    b = md_mass_inertia(ROOT / "results/dispersion/cg_provisional/params.json")
    # the same atoms: the builder's templates and the coarse-graining's measured mass per length
    assert a["rho_star"] == pytest.approx(b["rho_star"], rel=1e-4)
    assert a["rho_star"] == pytest.approx(616 / 655, rel=0.01)       # ~616 Da/bp against the paper's 655
    (tmp_path / "x.json").write_text(json.dumps({"foo": 1}))
    with pytest.raises(InputError, match="build.json"):
        md_mass_inertia(tmp_path / "x.json")
