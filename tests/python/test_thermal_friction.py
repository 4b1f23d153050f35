"""The length of a "water" friction ([thermal] friction_length_nm; docs/thermal.md, "Solvent"):
the Tirado cylinder formulas taken at the length of the motion instead of the rod's.

* the 158-bp rod given the 21-bp rod's length has the 21-bp rod's frictions (control: at its
  own length it does not);
* the across-friction ratio between two lengths is that of the formula,
  (ln p2 + nu(p2)) / (ln p1 + nu(p1)), nu(p) = 0.839 + 0.185 / p + 0.233 / p^2, computed here
  from the published coefficients (Tirado, Lopez Martinez & Garcia de la Torre 1984);
* the key without a "water" friction is an error naming it.
"""
import math
import re

import pytest
import rodcore

from dna_models.units import Units

RISE_NM = Units.paper().rise_A / 10


def frictions(bp, length_nm=None, water=True):
    """(translational [along, across], rotational [about, across]) as the resolved scene states them."""
    th = {"temperature_K": 300.0, "friction_translational": "water" if water else 0.1,
          "friction_rotational": "water" if water else 0.1}
    if length_nm is not None:
        th["friction_length_nm"] = length_nm
    sc = {"initial": {"kind": "dna_planar", "bp": bp, "turns": 2, "A_v_A_per_ps": 0.0}, "thermal": th,
          "solver": {"dt": 0.05}, "output": {"t_end": 0.1, "frames": 2}}
    text = rodcore.Simulation(sc).scene
    found = [re.search(rf"{key} = \"water\"  # \[[^]]*\] = \[([^,]+), ([^]]+)\]", text) for key in
             ("friction_translational", "friction_rotational")]
    assert all(found), text
    return [(float(m.group(1)), float(m.group(2))) for m in found]


def test_friction_length_gives_the_cylinder_of_that_length():
    short = frictions(21)
    given = frictions(158, 21 * RISE_NM)
    own = frictions(158)
    for a, b in zip(short, given):
        assert a == pytest.approx(b, rel=1e-12)
    assert own[0][1] < 0.9 * short[0][1]                      # control: the rod's own length differs
    assert own[1] == pytest.approx(short[1], rel=1e-12)       # rotation: per length, no length in it

    def across(L_nm):                                          # radius 1 nm: p = L / 2a
        p = L_nm / 2.0
        return 1.0 / (math.log(p) + 0.839 + 0.185 / p + 0.233 / p ** 2)

    assert own[0][1] / short[0][1] == pytest.approx(across(158 * RISE_NM) / across(21 * RISE_NM), rel=1e-9)


def test_friction_length_needs_water():
    with pytest.raises(Exception, match="thermal.friction_length_nm: is used only by a \"water\" friction"):
        frictions(158, 7.0, water=False)
