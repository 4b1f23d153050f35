"""Olson et al. 1998 step tables (dna_models/data/olson1998_steps.toml): against
the refdata transcription, the strand-complement symmetry (checked directly
and through the 3DNA geometry of a duplex read on its other strand), and the
published numbers."""
import csv

import numpy as np
import pytest

from dna_models.sequence import random_sequence, reverse_complement
from mdbridge.geometry import frames_from_steps, step_parameters_along
from mdbridge.rod.material.parameter_sets import olson1998_steps, olson1998_table
from dna_models import presets

S = np.diag([-1.0, 1, 1, -1, 1, 1])          # shift and tilt change sign
TABLE1 = ["AA", "AC", "AG", "AT", "CA", "CC", "CG", "GA", "GC", "TA"]
EMDNA_TO_TOOLKIT = [3, 4, 5, 0, 1, 2]        # emDNA (tilt roll twist shift slide rise) -> ours


def _comp_step(xy):
    c = {"A": "T", "C": "G", "G": "C", "T": "A"}
    return c[xy[1]] + c[xy[0]]               # strand II read 5'->3': Y' X'


def _csv(path):
    rows = [r for r in csv.reader(open(path)) if r and not r[0].startswith("#")]
    return {r[0]: np.array([float(x) for x in r[1:]]) for r in rows[1:]}


@pytest.fixture(scope="module")
def tab():
    return olson1998_table()["steps"]


def test_sixteen_steps_all_positive_definite(tab):
    assert sorted(tab) == sorted(a + b for a in "ACGT" for b in "ACGT")
    for k, (m, F) in tab.items():
        assert np.array_equal(F, F.T), k
        assert np.linalg.eigvalsh(F)[0] > 0, k


def test_table1_entries_equal_refdata(refdata, tab):
    M = _csv(refdata / "olson1998" / "olson1998_PplusDNA_step_means.csv")
    F = _csv(refdata / "olson1998" / "olson1998_force_constants_6x6.csv")
    P = EMDNA_TO_TOOLKIT
    for k in TABLE1:
        assert np.array_equal(tab[k][0], M[k]), k
        assert np.allclose(tab[k][1], F[k].reshape(6, 6)[np.ix_(P, P)], atol=0, rtol=0), k
    # the refdata force constants of all 16 steps (emDNA's) are the carried ones
    for k in tab:
        assert np.allclose(tab[k][1], F[k].reshape(6, 6)[np.ix_(P, P)], atol=1e-12), k


def test_strand_complement_symmetry(tab):
    for xy, (m, F) in tab.items():
        mc, Fc = tab[_comp_step(xy)]
        assert np.allclose(mc, S @ m, atol=1e-12), xy
        assert np.allclose(Fc, S @ F @ S, atol=1e-12), xy
    # self-complementary steps: shift = tilt = 0 and no shift/tilt coupling to the rest
    for xy in ("AT", "CG", "GC", "TA"):
        m, F = tab[xy]
        assert m[0] == 0 and m[3] == 0
        odd = np.outer(np.diag(S), np.diag(S)) < 0
        assert np.all(F[odd] == 0), xy


def test_refdata_means_of_four_steps_break_the_symmetry(refdata):
    """Control (the symmetry test can fail): emDNA's means of GT, TG, CT, TC are
    the complements X'Y' of CA, AC, GA, AG instead of Y'X', which is why the
    carried table computes those four from Table 1."""
    M = _csv(refdata / "olson1998" / "olson1998_PplusDNA_step_means.csv")
    for xy in ("AC", "CA", "AG", "GA"):
        assert not np.allclose(M[_comp_step(xy)], S @ M[xy], atol=1e-3), xy
        xpyp = "".join({"A": "T", "C": "G", "G": "C", "T": "A"}[b] for b in xy)
        assert np.allclose(M[xpyp], S @ M[xy], atol=1e-12), xy


def test_other_strand_through_3dna_geometry():
    """Build a duplex from the table, read it on strand II (base-pair frames turned
    180 deg about x, order reversed), analyse with the 3DNA code: the steps are
    the table's steps of the reverse complement."""
    seq = random_sequence(40, seed=11)
    sm = olson1998_steps(seq, closed=False)
    R, o = frames_from_steps(sm.step_params)
    R2 = R[::-1] * np.array([1.0, -1.0, -1.0])[None, None, :]   # columns y, z reversed
    p2 = step_parameters_along(R2, o[::-1])
    sm2 = olson1998_steps(reverse_complement(seq), closed=False)
    assert np.max(np.abs(p2 - sm2.step_params)) < 1e-10


def test_published_numbers(tab):
    # Olson 1998 Table 1 (P+DNA) twist and roll [deg]
    assert tab["AA"][0][5] == 35.1 and tab["TA"][0][5] == 37.8 and tab["AT"][0][5] == 29.3
    assert tab["CA"][0][4] == 4.7 and tab["CG"][0][4] == 5.4 and tab["GC"][0][4] == 0.3
    # the sequence averages printed in dna_models/data/olson1998_average.toml
    avg = presets.olson1998_table()
    mean = np.mean([m for m, _ in tab.values()], axis=0)
    Fd = np.mean([np.diag(F) for _, F in tab.values()], axis=0)
    names = ("shift", "slide", "rise", "tilt", "roll", "twist")
    for k, name in enumerate(names):
        assert mean[k] == pytest.approx(avg["step_means"][name], abs=5e-5), name
        assert Fd[k] == pytest.approx(avg["force_constants_diagonal"][name], abs=5e-5), name
