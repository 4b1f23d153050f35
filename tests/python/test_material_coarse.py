"""Coarse segments (mdbridge/rod/material/coarse.py): one grid point per 10 base pairs, the material
composed from the steps it replaces by series compliance transported along the intrinsic shape.

The truth is the base-pair chain itself, sampled: every step a constant-strain piece exp(h (x0_i + e_i))
with e_i ~ N(0, kT K_i^-1 / h), composed exactly, against the coarse chain of constant-strain segments
exp(H (X0_k + E_k)), E_k ~ N(0, kT K_seg^-1 / H) (no Jacobian of the module in either). Bend and twist
persistence lengths, read from the frames at the segment boundaries (the rest frames there coincide),
agree within 2 % and within their Monte Carlo errors at 30-150 bp on a 500-bp Olson 1998 DNA at 300 K;
control: the arithmetic mean of the steps' stiffness (no series compliance, no transport) misses.
"""
import dataclasses
import math

import numpy as np
import pytest

from dna_models.errors import InputError
from dna_models.sequence import random_sequence
from dna_models.units import Units
from mdbridge.geometry.se3 import step_exp
from mdbridge.rod.material.coarse import coarse_material
from mdbridge.rod.material.parameter_sets import step_material
from mdbridge.rod.material.steps_to_rod import rod_material

KT = Units.paper().kT_to_rod(300.0)
M = 10


def chain_frames(Gamma0, Omega0, K, h, samples, rng, every=1):
    """Rotations (samples, n / every + 1, 3, 3) at every `every`-th point of the open chain of
    constant-strain pieces with Gaussian strains."""
    n = len(K)
    L = np.linalg.cholesky(np.linalg.inv(K) * KT / h)                     # (n, 6, 6)
    R = np.broadcast_to(np.eye(3), (samples, 3, 3)).copy()
    out = [R]
    for i in range(n):
        e = rng.standard_normal((samples, 6)) @ L[i].T
        Ri, _ = step_exp((Omega0[i] + e[:, 3:]) * h, (Gamma0[i] + e[:, :3]) * h)
        R = R @ Ri
        if (i + 1) % every == 0:
            out.append(R)
    return np.stack(out, axis=1)


def persistence(R, R_rest, lags):
    """Bend and twist persistence lengths [in steps of the chain] at each lag: D = R_rel,rest^T R_rel
    between every pair of boundary frames `lag` apart; <D33> = exp(-lag / l_b),
    <(D11 + D22) / (1 + D33)> (the cosine of the twist angle) = exp(-lag / (2 l_t))."""
    out = []
    for j in lags:
        rel = np.swapaxes(R[:, :-j], -1, -2) @ R[:, j:]
        rest = np.swapaxes(R_rest[:-j], -1, -2) @ R_rest[j:]
        D = np.swapaxes(rest, -1, -2)[None] @ rel
        b = D[..., 2, 2]
        t = (D[..., 0, 0] + D[..., 1, 1]) / (1 + D[..., 2, 2])
        # errors from independent chains (samples): means per chain
        mb, mt = b.mean(axis=1), t.mean(axis=1)
        lb, lt = -j / math.log(mb.mean()), -j / (2 * math.log(mt.mean()))
        se_b = lb * mb.std(ddof=1) / math.sqrt(len(mb)) / (mb.mean() * abs(math.log(mb.mean())))
        se_t = lt * mt.std(ddof=1) / math.sqrt(len(mt)) / (mt.mean() * abs(math.log(mt.mean())))
        out.append((lb, se_b, lt, se_t))
    return np.array(out)


def rest_frames(Gamma0, Omega0, h):
    R_i, _ = step_exp(Omega0 * h, Gamma0 * h)
    R = [np.eye(3)]
    for Ri in R_i:
        R.append(R[-1] @ Ri)
    return np.array(R)


@pytest.fixture(scope="module")
def dna():
    return rod_material(step_material(random_sequence(500, seed=3), "olson1998"))


def test_coarse_segments_keep_the_bend_and_twist_persistence_of_the_base_pair_chain(dna):
    cm, turns = coarse_material(dna, M)
    assert cm.K.shape == (50, 6, 6) and np.all(turns == 1)        # ~343 deg per segment: one turn dropped
    rng = np.random.default_rng(7)
    fine = rest_frames(dna.Gamma0, dna.Omega0, dna.h)[::M]
    coarse = rest_frames(cm.Gamma0, cm.Omega0, cm.h)
    assert np.abs(fine - coarse).max() < 1e-9                    # the rest frames coincide at the boundaries
    S = 20000
    Rf = chain_frames(dna.Gamma0, dna.Omega0, dna.K, dna.h, S, rng, every=M)
    Rc = chain_frames(cm.Gamma0, cm.Omega0, cm.K, cm.h, S, rng)
    lags = [3, 6, 11, 15]                                         # 30, 60, 110, 150 bp
    pf, pc = persistence(Rf, fine, lags), persistence(Rc, coarse, lags)
    for (lbf, sbf, ltf, stf), (lbc, sbc, ltc, stc) in zip(pf, pc):
        for a, sa, b, sb in ((lbf, sbf, lbc, sbc), (ltf, stf, ltc, stc)):
            assert abs(b / a - 1) < 0.02 and abs(b - a) < 4 * math.hypot(sa, sb), (a, sa, b, sb)
    # control: the arithmetic mean of the steps' stiffness per segment (no series compliance, no
    # transport by the intrinsic twist) is a stiffer rod
    naive = dna.K.reshape(50, M, 6, 6).mean(axis=1)
    pn = persistence(chain_frames(cm.Gamma0, cm.Omega0, naive, cm.h, S, rng), coarse, lags)
    assert any(abs(pn[k, c] / pf[k, c] - 1) > 0.02 and abs(pn[k, c] - pf[k, c]) > 4 * math.hypot(pn[k, c + 1],
                                                                                                 pf[k, c + 1])
               for k in range(len(lags)) for c in (0, 2)), pn


def test_an_untwisted_uniform_rod_keeps_its_rotational_compliance_and_gains_lever_arm_shear():
    """The paper's uniform material, intrinsically straight and untwisted: rotations compose without
    lever arms, so the segment's bend and twist compliance per length, (K_seg^-1)_rot, is the base
    pair's exactly; its shear compliance gains the lever arms of the bends inside it, H^2 / 12 per
    bend compliance (a constant-strain segment's rotation acts about its middle)."""
    rm = dataclasses.replace(rod_material(step_material("A" * 40, "paper")), Omega0=np.zeros((40, 3)))
    cm, turns = coarse_material(rm, M)
    assert np.all(turns == 0)
    C_fine, C_seg = np.linalg.inv(rm.K[0]), np.linalg.inv(cm.K[0])
    assert np.allclose(C_seg[3:, 3:], C_fine[3:, 3:], rtol=1e-8, atol=1e-12)
    H = M * rm.h
    shear = C_fine[0, 0] + (H ** 2 - rm.h ** 2) / 12 * C_fine[4, 4]
    assert C_seg[0, 0] == pytest.approx(shear, rel=1e-6), (C_seg[0, 0], shear)
    assert cm.h == pytest.approx(H)


def test_bp_per_point_must_divide_the_steps():
    rm = rod_material(step_material("ACGTACGTACGT", "paper"))
    with pytest.raises(InputError, match="bp-per-point 5"):
        coarse_material(rm, 5)
