"""A mode branch rises with n from its first mode on (mdbridge/analysis/mode_spectra.py,
off_branch): the main job's report gave stretch n = 1 at 0.329 +- 0.041 rad/ps above its
n = 2 at 0.293, where a 5-ns record gives 0.104 for n = 1. Such a first mode is refused;
a rising branch keeps every mode (the control), and the older rule (a mode below two lower
ones) still holds."""
from types import SimpleNamespace

from mdbridge.analysis.mode_spectra import off_branch


def _fits(omegas, err=0.04):
    return [(SimpleNamespace(omega_per_ps=w, omega_err_per_ps=err), None) for w in omegas]


def test_a_first_mode_above_the_second_is_refused():
    reasons = off_branch(_fits([0.329, 0.293, 0.45]), [None, None, None])
    assert reasons[0] is not None and "above that of mode n = 2" in reasons[0]
    assert reasons[1:] == [None, None]


def test_a_rising_branch_keeps_every_mode():
    # the control: the same errors, a branch that rises (stretch: omega ~ n)
    assert off_branch(_fits([0.104, 0.21, 0.31, 0.40]), [None] * 4) == [None] * 4


def test_a_refused_mode_does_not_count_and_the_old_rule_holds():
    # n = 2 already refused (reason given): n = 1 is compared with n = 3 only
    assert off_branch(_fits([0.3, 0.1, 0.5]), [None, "no peak", None]) == [None, "no peak", None]
    # a mode far below two lower ones: refused by the older rule, before it could refuse them
    r = off_branch(_fits([0.10, 0.20, 0.01, 0.40], err=0.001), [None] * 4)
    assert r[2] is not None and "below those of modes n = 1, 2" in r[2] and r[:2] == [None, None] and r[3] is None
