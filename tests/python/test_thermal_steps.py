"""The holonomy directions of mdbridge/rod/material/thermal_steps.py against an independent
Monte Carlo: under the stationary distribution of a sequence-dependent rod (per-point coupled
K varying by tens of %), the regression of the step parameters on the holonomy's change,
beta = cov(q, D) cov(D)^-1 (the conditional mean's slope), lies in the span of the six
holonomy directions. Control: the per-parameter k = 0 and k = turns modes (the former shape
check's closure modes) do not span it."""
import numpy as np

from mdbridge.rod.material.closed_rest import holonomy_jacobian
from mdbridge.rod.material.thermal_steps import grid_steps, holonomy_directions, rest_strains

N_BP, PER_BP, TURNS = 8, 2, 1


def sequence_rod(seed=3):
    """A straight, twisted rod (one turn) with a sequence-dependent coupled K and rest roll."""
    rng = np.random.default_rng(seed)
    N = N_BP * PER_BP
    L = float(N)
    A = rng.normal(size=(N, 6, 6)) * 0.3
    K = np.einsum("gij,gkj->gik", A, A) + np.diag([4.0, 4.0, 10.0, 1.0, 1.0, 1.5])
    K *= rng.uniform(0.6, 1.4, size=(N, 1, 1))
    Omega0 = np.zeros((N, 3))
    Omega0[:, 2] = 2 * np.pi * TURNS / L
    Omega0[:, 1] = 0.05 * rng.normal(size=N)
    Gamma0 = np.tile([0.0, 0.0, 1.0], (N, 1))
    return {"K": K, "Gamma0": Gamma0, "Omega0": Omega0}, L


def unexplained(beta, basis):
    """Fraction of beta's norm (..., columns) outside the span of basis (rows of vectors)."""
    Q, _ = np.linalg.qr(basis.T)
    r = beta - Q @ (Q.T @ beta)
    return np.linalg.norm(r) / np.linalg.norm(beta)


def test_conditional_mean_moves_along_the_holonomy_directions():
    material, L = sequence_rod()
    x0 = rest_strains(material)
    N = len(x0)
    kT, samples = 2e-3, 20000
    chol = np.linalg.cholesky(np.linalg.inv(material["K"]) * kT / (L / N))
    x = x0 + np.einsum("gij,sgj->sgi", chol, np.random.default_rng(7).standard_normal((samples, N, 6)))
    q = grid_steps(x, L, N_BP).reshape(samples, -1)                    # (S, 6 n_bp)
    _, _, dzeta = holonomy_jacobian(x0, L, 8)
    D = (x - x0).reshape(samples, -1) @ dzeta.T                        # (S, 6) linear holonomy change
    dq, dD = q - q.mean(axis=0), D - D.mean(axis=0)
    beta = np.linalg.solve(dD.T @ dD, dD.T @ dq).T                     # (6 n_bp, 6)
    G = holonomy_directions(material, L, N_BP).reshape(6, -1)
    j = np.arange(N_BP)
    modes = []
    for p in range(6):
        for f in (np.ones(N_BP), np.cos(2 * np.pi * TURNS * j / N_BP), np.sin(2 * np.pi * TURNS * j / N_BP)):
            m = np.zeros((N_BP, 6))
            m[:, p] = f
            modes.append(m.ravel())
    # Monte Carlo noise of beta: var(beta_ij) = var(q_i | D) [cov(D)^-1]_jj / S, of which the
    # fraction (n - 6) / n of its n = 6 n_bp dimensions falls outside the six directions
    resid = dq - dD @ beta.T
    noise2 = resid.var(axis=0).sum() * np.trace(np.linalg.inv(dD.T @ dD / samples)) / samples
    expected = np.sqrt(noise2 * (beta.shape[0] - 6) / beta.shape[0]) / np.linalg.norm(beta)
    inside, control = unexplained(beta, G), unexplained(beta, np.array(modes))
    print("fraction of the slope outside the holonomy directions:", round(inside, 3),
          "(Monte Carlo noise", round(expected, 3), "); outside the closure modes:", round(control, 3))
    assert inside < 2.0 * expected
    assert control > 5.0 * expected
