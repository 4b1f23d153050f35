"""The coarse-grained rod's prediction with the stiffness each mode feels: the rule of
docs/coarse-graining.md, "Compliance by timescale", items 2 and 3.

A mode (kind, n) of frequency omega_n feels the storage stiffness K'(omega_n) = Re J*(omega_n)^-1
of the q -> 0 collective coordinates (mdbridge/coarsegrain/timescale.py dynamic_compliance_q0),
not the whole record's (relaxed) K: a slow episode that relaxes over many periods does not
resist the wave. omega_n is found self-consistently, with no MD frequency in it: start from the
relaxed rod's omega_n, evaluate K'(omega_n), take the linear rod of that stiffness (the same
mean shape, mass and inertia, at the MD's tension; mdbridge/analysis/dispersion_prediction.py),
and repeat until omega_n moves by less than TOLERANCE (at most MAX_ITERATIONS times).

Against the circle: a collective coordinate's J* at its own resonance is its inertia, not
the material, so mode n's own body-frame wavenumber is left out of the q -> 0 fit of its J*
(`left_out_wavenumber`: twist and stretch k = n, bend k = |turns - n|) and the intercept
refitted (timescale.Coordinates(..., leave_out=k)).

The lag window of J*: MAX_LAG_PERIODS periods of the mode, at most a quarter of the record.

The rod's error: each block-bootstrap replica of J*(omega_n) (timescale.dynamic_compliance_q0's
J_boot) mapped to omega_n and gamma_n, linearised: with G = d w^2 / dK at the estimate (one
forward difference per element of the symmetric K, GRADIENT_STEP of its diagonal scale), a
replica gives w^2 + <G, K'_rep - K'> and Delta_rep = <G, K''_rep>; their spreads are the errors.

The damping (the loss part): with K* = K' + i K'' (J* = J' - i J'', K'' >= 0 for a material
that dissipates), a mode's squared frequency becomes complex, omega^2 = w(K')^2 + i Delta,
Delta = d w^2 / d eps of K' + eps K'' at eps = 0 (to first order in K''). An oscillator
x'' + 2 gamma x' + omega0^2 x has the same Im omega^2 = 2 gamma omega, so the mode's amplitude
decay rate is gamma = Delta / (2 omega) (mdbridge/coarsegrain/damping.py `mode_decay_rate`;
the MD's `damping_per_ps`, dnarod modes). It is a prediction only where K'' comes from
coordinates that are not the mode: with the own wavenumber left out, or another seed's material.
"""
from __future__ import annotations

import math

import numpy as np

from dna_models.errors import InputError
from mdbridge.coarsegrain.damping import mode_decay_rate

MAX_ITERATIONS = 10
TOLERANCE = 0.01
MAX_LAG_PERIODS = 8.0
GRADIENT_STEP = 1e-4


def left_out_wavenumber(kind: str, n: int, turns: int) -> int:
    """The body-frame wavenumber of lab mode n (the rule's item 3)."""
    return abs(int(turns) - int(n)) if kind == "bend" else int(n)


def max_lag_frames(omega_per_ps: float, dt_ps: float, n_frames: int) -> int:
    """MAX_LAG_PERIODS periods of omega in frames, at most n_frames // 4 (at least 2)."""
    return int(max(2, min(n_frames // 4, round(MAX_LAG_PERIODS * 2 * math.pi / omega_per_ps / dt_ps))))


def storage_stiffness(coords, dt_ps: float, omega_per_ps: float, n_boot: int, seed: int) -> dict:
    """K'(omega) = Re J*(omega)^-1 (6, 6, kT units per step) of coords, J* with its errors."""
    from mdbridge.coarsegrain.timescale import dynamic_compliance_q0
    lag = max_lag_frames(omega_per_ps, dt_ps, coords.T)
    d = dynamic_compliance_q0(coords, dt_ps, [omega_per_ps], lag, n_boot=n_boot, seed=seed)
    return {"K_storage": d["K"][0].real, "K_loss": d["K"][0].imag, "J": d["J"][0],
            "J_storage_err": d["J_storage_err"][0], "J_loss_err": d["J_loss_err"][0],
            "J_boot": d["J_boot"][0], "max_lag_frames": lag}


def squared_frequency_gradient(K, material_of, frequency_of) -> np.ndarray:
    """G = d w^2 / dK (6, 6, symmetric: dK_ij = dK_ji) of the mode frequency_of gives, at K."""
    K = np.asarray(K, float)
    w2 = float(frequency_of(material_of(K))) ** 2
    scale = np.sqrt(np.outer(np.abs(np.diag(K)), np.abs(np.diag(K))))
    G = np.zeros((6, 6))
    for i in range(6):
        for j in range(i, 6):
            h = GRADIENT_STEP * scale[i, j]
            E = np.zeros((6, 6))
            E[i, j] = E[j, i] = h
            g = (float(frequency_of(material_of(K + E))) ** 2 - w2) / h
            G[i, j] = G[j, i] = g / (1.0 if i == j else 2.0)       # <G, E> = g h for both entries
    return G


def _replica_spread(J_boot, K_storage, omega: float, material_of, frequency_of) -> dict:
    """The errors of omega and gamma from the block-bootstrap replicas of J* (module doc)."""
    G = squared_frequency_gradient(K_storage, material_of, frequency_of)
    K = np.linalg.inv(np.asarray(J_boot))
    w2 = omega ** 2 + np.einsum("ij,rij->r", G, K.real - np.asarray(K_storage)[None])
    ws = np.sqrt(np.clip(w2, 0.0, None))
    gs = np.einsum("ij,rij->r", G, K.imag) / (2.0 * omega)
    return {"omega_err_per_ps": float(np.std(ws, ddof=1)), "gamma_err_per_ps": float(np.std(gs, ddof=1)),
            "replicas": len(J_boot), "replicas_failed": int(np.sum(w2 <= 0))}


def unrelaxed_mode(kind: str, n: int, q, keep, closed: bool, dt_ps: float, material_of, frequency_of,
                   omega_start: float, n_boot: int = 50, seed: int = 0) -> dict:
    """One mode's self-consistent frequency (module doc). material_of(F) turns a 6x6 per-step
    stiffness into the rod's material, frequency_of(material) gives this mode's omega [rad/ps];
    q (T, n_steps, 6) the kept frames' step parameters, keep (n_steps,) the steps used."""
    from mdbridge.coarsegrain.qstiffness import helical_turns
    from mdbridge.coarsegrain.timescale import Coordinates
    turns = helical_turns(np.asarray(q)[:, :, 5].mean(axis=0)) if closed else 0
    k = left_out_wavenumber(kind, n, turns) if closed else None
    coords = Coordinates(q, keep, closed, leave_out=k)
    if not (math.isfinite(omega_start) and omega_start > 0):
        raise InputError(f"{kind} n = {n}: the relaxed rod's frequency {omega_start} is no start")
    omega, path = float(omega_start), [float(omega_start)]
    for _ in range(MAX_ITERATIONS):
        s = storage_stiffness(coords, dt_ps, omega, n_boot, seed)
        new = float(frequency_of(material_of(s["K_storage"])))
        path.append(new)
        converged = abs(new - omega) < TOLERANCE * omega
        omega = new
        if converged:
            break
    gamma = mode_decay_rate(s["K_storage"], s["K_loss"], omega, material_of, frequency_of)
    err = _replica_spread(s["J_boot"], s["K_storage"], omega, material_of, frequency_of)
    return {"kind": kind, "n": int(n), "omega_per_ps": omega, "omega_err_per_ps": err["omega_err_per_ps"],
            "gamma_per_ps": gamma, "gamma_err_per_ps": err["gamma_err_per_ps"],
            "bootstrap": {"replicas": err["replicas"], "failed": err["replicas_failed"]},
            "converged": bool(converged), "iterations": len(path) - 1, "omega_path_per_ps": path,
            "left_out_wavenumber": k, "K_storage": s["K_storage"].tolist(), "K_loss": s["K_loss"].tolist(),
            "J_storage_err": np.asarray(s["J_storage_err"]).tolist(), "max_lag_frames": s["max_lag_frames"]}
