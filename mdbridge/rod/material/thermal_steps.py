"""The step parameters of a thermal rod: the known answer the coarse-graining loop is checked
against (docs/coarse-graining.md, "A sequence rod").

A Langevin rod without the closure projection samples exp(-E / kT) of its material alone
(docs/thermal.md, "Liouville"): independent grid strains x_i ~ N(x0_i, kT K_i^-1 / h). Its
step parameters are read as the coarse-graining reads a rod run: the grid strains composed
along their trigonometric interpolant over each base-pair step (composition.py) and read
with the 3DNA definitions.

Its holonomy (the motion from s = 0 to s = L) is held only by the semi-discrete rod's
closure defect: each run sits on its own slowly wandering holonomy, and samples the
distribution given it. Given the holonomy, the mean of x moves by K^-1 B^T lambda (Gaussian
conditioning; B the holonomy's Jacobian, closed_rest.holonomy_jacobian), which spreads a
change of the holonomy over the steps by their compliance: on a sequence rod not the k = 0
and k = helical-turns modes of each parameter. `holonomy_directions` gives the step
parameters' six response directions, `off_holonomy` the deviations less them.
"""
from __future__ import annotations

import numpy as np

from dna_models.units import Units
from mdbridge.geometry.steps import step_parameters

from .closed_rest import holonomy_jacobian
from .composition import cell_matrix, compose_stretches


def grid_steps(x, L, n_bp, refine=8):
    """Step parameters (..., n_bp, 6) [A, deg] of grid strains x (..., N, 6) = (Gamma, Omega)
    of a periodic rod of length L [l]: the last step closes the period."""
    N = x.shape[-2]
    R, d = compose_stretches(np.einsum("mg,...gi->...mi", cell_matrix(N, L, refine), x),
                             L / (refine * N), refine * (N // n_bp))
    return step_parameters(np.broadcast_to(np.eye(3), R.shape), np.zeros(d.shape), R, d * Units.paper().ell_A)


def rest_strains(material):
    """(N, 6) intrinsic grid strains (Gamma0, Omega0) of a material dict (K, Gamma0, Omega0)."""
    return np.hstack([material["Gamma0"], material["Omega0"]])


def stationary_step_means(material, L, kT, n_bp, samples=8000, seed=5, batch=500):
    """<q_j> (n_bp, 6) [A, deg] and its Monte Carlo error under the stationary distribution
    of the unconstrained rod, grid strains x_i ~ N(x0_i, kT K_i^-1 / h) independent."""
    x0 = rest_strains(material)
    N = len(x0)
    chol = np.linalg.cholesky(np.linalg.inv(material["K"]) * kT / (L / N))
    rng = np.random.default_rng(seed)
    total, total2 = 0.0, 0.0
    for _ in range(samples // batch):
        q = grid_steps(x0 + np.einsum("gij,sgj->sgi", chol, rng.standard_normal((batch, N, 6))), L, n_bp)
        total, total2 = total + q.sum(axis=0), total2 + (q ** 2).sum(axis=0)
    n = batch * (samples // batch)
    mean = total / n
    return mean, np.sqrt(np.maximum(total2 / n - mean ** 2, 0.0) / n)


def holonomy_directions(material, L, n_bp, size=1e-4):
    """(6, n_bp, 6): the step parameters' response to moving the holonomy along each of its six
    body-twist directions by the least change of strain energy, dx_i = K_i^-1 B_i^T e_k
    (central differences; linear to ~1e-4 of the response for the ~1 rad twist a run
    wanders by)."""
    x0 = rest_strains(material)
    N = len(x0)
    _, _, dzeta = holonomy_jacobian(x0, L, 8)
    Kinv = np.linalg.inv(material["K"])
    out = []
    for k in range(6):
        dx = np.einsum("gij,gj->gi", Kinv, dzeta[k].reshape(N, 6)) * size
        out.append((grid_steps(x0 + dx, L, n_bp) - grid_steps(x0 - dx, L, n_bp)) / (2 * size))
    return np.array(out)


def off_holonomy(dev, err, directions):
    """dev / err (n, 6), less its weighted least-squares part along the holonomy directions
    (6, n, 6): one fit of six numbers over all steps and parameters."""
    A = (directions / err[None]).reshape(6, -1).T
    y = (dev / err).reshape(-1)
    return (y - A @ np.linalg.lstsq(A, y, rcond=None)[0]).reshape(dev.shape)
