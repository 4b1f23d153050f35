"""The long-wavelength stiffness of a duplex: the compliance spectrum S(q) of its step
parameters along the sequence, and its limit q -> 0 (docs/coarse-graining.md, "The rod's K").

Steps in series add their compliances, and neighbouring steps are coupled (Lankas et al.
2009 PCCP 11:10565), so the uniform rod that responds like the duplex over many steps is
neither the mean of the per-step stiffness matrices nor, in general, the inverse of the
mean per-step covariance. With x_j(t) the deviation of step j's parameters (A, deg) from
their mean and X_k = sum_j x_j exp(-2 pi i j k / n) over the n steps,

    S(q_k) = <X_k X_k^H> / n,   q_k = 2 pi k / n (rad per step),

is the 6 x 6 Hermitian compliance per step at wavenumber q (kT units). For independent
steps it is flat: S(q) = mean_j <x_j x_j^T>, whatever the sequence, so the per-step
compliance average is the q -> 0 limit. Couplings of range r make Re S(q) a cosine
series of order r. The rod's K is S(0)^-1 taken as q -> 0 (Noy & Golestanian 2012 PRL
109:228101; the q-stiffness of Laeremans et al. 2024 J Chem Phys and Segers et al. 2021
PRE 103:042408):

* Closure. A ligated duplex in a box holds its total twist and its length (q = 0 of twist
  and rise) and closes its rotation in the laboratory frame, which in the base-pair
  (body) frames that turn by the helical twist is the bend at k = the number of helical
  turns. Those modes are left out (`usable_modes`); for an open duplex every mode is used.
  With them out, a fixed total of n independent steps biases nothing (the mean per-step
  covariance would be low by (n - 1) / n).
* Extrapolation. Re S at the lowest usable modes (q <= Q_FIT_RAD, below the helical
  repeat of a closed duplex) is fitted by least squares as a0 + a1 lam(q),
  lam = 4 sin^2(q / 2) = 2 (1 - cos q), the symbol of a nearest-neighbour coupling (exact
  for it at every q, q^2 at small q); S(0) = a0. The imaginary part is odd in q and
  vanishes there. The same fit with a2 lam^2 added (range-2 couplings) measures what the
  model leaves out: where the two differ by more than the bootstrap spread of their
  difference, the excess enters the error (`extrapolation_err`).
* Per-step compliance average: the mean of Re S over the usable modes (Parseval: the mean
  per-step covariance with the closure's modes taken out), reported beside K(q -> 0).
* Excluded steps (the opening rule's sensitivity) are set to zero deviation and the
  spectrum normalised by the number of steps kept: for independent steps S is then the
  compliance average of the kept steps; for coupled steps the holes smear S over q.

Both averages are linear in the frames' second moments, so the moving-block bootstrap
(mdbridge/stats.py) redoes them per replicate at the cost of the 12 x 12 moments of each
mode's real and imaginary parts.
"""
from __future__ import annotations

import numpy as np

from mdbridge.stats import integrated_time, replicate_moments, spread, weighted_moments


Q_FIT_RAD = 0.5      # highest q of the fit: lam = 4 sin^2(q / 2) <= 0.245, where a range-2 coupling's
                     # lam^2 term is at most a quarter of its lam term
P = 6
TWIST = 5


def helical_turns(mean_twist_deg) -> int:
    """Number of helical turns of a closed duplex: its total mean twist / 360, rounded."""
    return int(round(float(np.sum(mean_twist_deg)) / 360.0))


def half_modes(n: int) -> np.ndarray:
    """k = 0 .. n // 2: the modes of a real series (S(q_{n-k}) is the conjugate of S(q_k))."""
    return np.arange(n // 2 + 1)


def mode_weights(n: int) -> np.ndarray:
    """How many of the n modes each half-mode stands for (1 for k = 0 and k = n / 2)."""
    k = half_modes(n)
    w = np.full(len(k), 2.0)
    w[0] = 1.0
    if n % 2 == 0:
        w[-1] = 1.0
    return w


def usable_modes(n: int, closed: bool, turns: int | None) -> np.ndarray:
    """(n // 2 + 1,) bool: the half-modes the closure leaves free (all for an open duplex;
    for a closed one all but k = 0 and k = turns)."""
    ok = np.ones(n // 2 + 1, dtype=bool)
    if closed:
        ok[0] = False
        if turns is not None and 0 < turns <= n // 2:
            ok[turns] = False
    return ok


def fit_modes(n: int, closed: bool, turns: int | None, q_fit: float = Q_FIT_RAD) -> np.ndarray:
    """Half-modes of the q -> 0 fit: usable, q_k <= q_fit, and for a closed duplex below
    turns - 1 (the closure's bend mode k = turns spreads to its neighbours at second order)."""
    k = half_modes(n)
    ok = usable_modes(n, closed, turns) & (2 * np.pi * k / n <= q_fit + 1e-12)
    if closed and turns is not None and turns > 0:
        ok &= k <= turns - 2
    return ok


def lam(q):
    """4 sin^2(q / 2): the Fourier symbol of a nearest-neighbour coupling, q^2 at small q."""
    return 4.0 * np.sin(0.5 * np.asarray(q, dtype=float)) ** 2


def intercept_weights(q: np.ndarray, order: int) -> np.ndarray | None:
    """w (len(q),) with a0 = sum w_k y_k for the least-squares fit y = a0 + a1 lam + ...
    (order terms in lam); None when there are not enough modes for it."""
    q = np.asarray(q, dtype=float)
    if len(q) < order + 1:
        return None
    A = np.vander(lam(q), order + 1, increasing=True)
    return np.linalg.pinv(A)[0]


def features(q_steps: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """(T, n // 2 + 1, 12): real and imaginary parts of X_k (6 each) of the kept steps."""
    x = np.where(np.asarray(keep, bool)[None, :, None], q_steps, 0.0)
    X = np.fft.rfft(x, axis=1)
    return np.concatenate([X.real, X.imag], axis=-1)


def spectrum_from_cov(cov12: np.ndarray, n_kept: int) -> np.ndarray:
    """Complex S (..., 6, 6) from the 12 x 12 covariance of (Re X, Im X):
    X X^H = a a^T + b b^T + i (b a^T - a b^T)."""
    a, b = slice(0, P), slice(P, 2 * P)
    re = cov12[..., a, a] + cov12[..., b, b]
    im = cov12[..., b, a] - cov12[..., a, b]
    return (re + 1j * im) / float(n_kept)


def second_moment_time(Y: np.ndarray) -> np.ndarray:
    """tau_2 (frames) per mode of the standardised squared amplitude sum_i (y_i / sd_i)^2 of
    Y (T, K, 12), the columns with variance only (X_0 and X_{n/2} are real)."""
    d = Y - Y.mean(axis=0)
    sd = d.std(axis=0)
    z = np.where(sd > 0, d / np.where(sd > 0, sd, 1.0), 0.0)
    return integrated_time((z * z).sum(axis=-1))


def fit_mode_time(q_steps: np.ndarray, keep: np.ndarray, closed: bool, q_fit: float = Q_FIT_RAD) -> float:
    """The slowest integrated autocorrelation time (frames) of the fit modes' amplitudes (every
    real component of every fit mode: the bends are slow where the rest is fast, so no median
    over components). In the base-pair frames the bend at wavenumber
    k is the laboratory bend at turns -+ k, so on a closed duplex the fit modes include slow
    low laboratory bending modes; the bootstrap's blocks must span them."""
    n = q_steps.shape[1]
    turns = helical_turns(q_steps[:, :, TWIST].mean(axis=0)) if closed else None
    fit = fit_modes(n, closed, turns, q_fit)
    if not fit.any():
        return 0.5
    Y = features(q_steps, keep)[:, fit]
    return float(np.max(integrated_time(Y)))                  # (K, 12); a real X_0 gives 0.5 for Im


def _inv_sym(S):
    K = np.linalg.inv(S)
    return 0.5 * (K + np.swapaxes(K, -1, -2))


def _stiffnesses(S, fit_idx, w1, w2, avg_w, f_q0, f_avg):
    """K(q -> 0) (order 1, order 2 or None) and the compliance-average K of spectra S (..., k, 6, 6)."""
    re = S.real
    S0 = np.einsum("k,...kij->...ij", w1, re[..., fit_idx, :, :])
    K0 = _inv_sym(S0) * f_q0
    K0b = None
    if w2 is not None:
        K0b = _inv_sym(np.einsum("k,...kij->...ij", w2, re[..., fit_idx, :, :])) * f_q0
    Sa = np.einsum("k,...kij->...ij", avg_w, re)
    return K0, K0b, _inv_sym(Sa) * f_avg, S0, Sa


def long_wavelength(q_steps: np.ndarray, keep: np.ndarray, closed: bool, boot, W_half=None,
                    q_fit: float = Q_FIT_RAD) -> dict:
    """Spectrum, K(q -> 0) and compliance average of the steps `keep` (n,) of q_steps
    (T, n, 6), with their moving-block bootstrap replicates (boot = (starts, b)) and, with
    W_half (2, T), those of each half of the run. Stiffness in kT/A^2, kT/(A deg), kT/deg^2."""
    T, n, _ = q_steps.shape
    keep = np.asarray(keep, bool)
    n_kept = int(keep.sum())
    turns = helical_turns(q_steps[:, :, TWIST].mean(axis=0)) if closed else None
    k_all = half_modes(n)
    q_all = 2 * np.pi * k_all / n
    use = usable_modes(n, closed, turns)
    fit = fit_modes(n, closed, turns, q_fit)
    fit_idx = np.flatnonzero(fit)
    if len(fit_idx) == 0:                         # a very short duplex: the lowest usable mode
        fit_idx = np.flatnonzero(use)[:1]
    w1 = intercept_weights(q_all[fit_idx], 1)
    order = 1
    if w1 is None:
        w1, order = np.ones(1), 0
    w2 = intercept_weights(q_all[fit_idx], 2)
    avg_w = np.where(use, mode_weights(n), 0.0)
    avg_w = avg_w / avg_w.sum()

    Y = features(q_steps, keep)                                          # (T, K, 12)
    d = Y - Y.mean(axis=0)
    cov = np.einsum("tki,tkj->kij", d, d) / (T - 1)
    S = spectrum_from_cov(cov, n_kept)                                   # (K, 6, 6)
    # effective degrees of freedom: per mode 2 T / (2 tau_2) (two quadratures), combined
    # with the fit's weights; per-step average over the usable modes
    tau2 = second_moment_time(Y[:, use | fit])
    n_mode = np.full(len(k_all), np.inf)
    n_mode[use | fit] = T / tau2
    dof_q0 = 1.0 / np.sum(w1 ** 2 / n_mode[fit_idx])
    dof_avg = 1.0 / np.sum(avg_w[use] ** 2 / n_mode[use])
    # S is inverted without the Wishart factor of stiffness.py: the rod is to reproduce the
    # duplex's compliances (its fluctuations, and the marginal compliances the constants and
    # the isotropic view use), which S estimates without bias; K's elements are then high by
    # about (p + 1) / dof (0.7 % at dof = 1000), reported as degrees_of_freedom
    f_q0 = f_avg = 1.0
    K0, K0b, Kavg, S0, Sa = _stiffnesses(S, fit_idx, w1, w2, avg_w, f_q0, f_avg)

    _, bcov = replicate_moments(Y, *boot)                                # (B, K, 12, 12)
    bS = spectrum_from_cov(bcov, n_kept)
    bK0, bK0b, bKavg, _, _ = _stiffnesses(bS, fit_idx, w1, w2, avg_w, f_q0, f_avg)
    K0_err = spread(bK0)
    extra = np.zeros((P, P))
    if K0b is not None and bK0b is not None:
        diff, sd = K0 - K0b, spread(bK0 - bK0b)
        extra = np.sqrt(np.maximum(diff ** 2 - sd ** 2, 0.0))
    out = {"n_steps": n, "n_kept": n_kept, "closed": closed, "helical_turns": turns,
           "k": k_all, "q_rad_per_step": q_all, "usable": use, "fit_modes": k_all[fit_idx],
           "fit_order": order, "fit_q_max_rad": q_fit, "fit_weights": w1,
           "S": S, "S_boot": bS, "S0": S0, "S_avg": Sa,
           "K_q0": K0, "K_q0_boot": bK0, "K_q0_boot_err": K0_err,
           "K_q0_order2": K0b, "extrapolation_err": extra,
           "K_avg_compliance": Kavg, "K_avg_compliance_boot": bKavg, "K_avg_compliance_err": spread(bKavg),
           "dof_q0": dof_q0, "dof_avg": dof_avg, "tau2_modes": tau2}
    if W_half is not None:
        _, hcov = weighted_moments(Y, W_half)
        hK0, _, hKavg, _, _ = _stiffnesses(spectrum_from_cov(hcov, n_kept), fit_idx, w1, None, avg_w, 1.0, 1.0)
        out["halves"] = {"K_q0": hK0, "K_avg_compliance": hKavg}
    return out


def combined_error(lw: dict, rule: dict | None) -> tuple[np.ndarray, np.ndarray]:
    """(error of K(q -> 0), the opening rule's spread where it counts): the bootstrap and
    extrapolation errors in quadrature, plus |K(all steps) - K(rule)| wherever that
    spread exceeds the bootstrap error."""
    boot, extra = lw["K_q0_boot_err"], lw["extrapolation_err"]
    rule_part = np.zeros_like(boot)
    if rule is not None:
        d = np.abs(lw["K_q0"] - rule["K_q0"])
        rule_part = np.where(d > boot, d, 0.0)
    return np.sqrt(boot ** 2 + extra ** 2 + rule_part ** 2), rule_part


# -- the q-stiffness view -----------------------------------------------------------
def view(S: np.ndarray, rise_A: float, kT_pN_nm: float) -> dict:
    """Bend, twist and stretch stiffness of spectra S (..., k, 6, 6) (A, deg) as continuum
    constants of a segment of one mean rise: bend persistence 2 h / (S_tilt + S_roll)
    (the compliances averaged, as the helical twist averages them), torsional modulus
    kT h / S_twist (twist free to couple), stretch modulus kT h [(S_rise,twist)^-1]_rise
    (at fixed twist, as the m-step constants)."""
    deg = np.pi / 180.0
    h_nm = rise_A / 10.0
    bend = 2.0 * h_nm / ((S[..., 3, 3].real + S[..., 4, 4].real) * deg * deg)
    twist = kT_pN_nm * h_nm / (S[..., 5, 5].real * deg * deg)
    block = S[..., [2, 5], :][..., :, [2, 5]] * np.array([0.1, deg])[:, None] * np.array([0.1, deg])[None, :]
    stretch = kT_pN_nm * h_nm * np.linalg.inv(block)[..., 0, 0].real
    return {"bend_persistence_length": bend, "torsional_modulus": twist, "stretch_modulus": stretch}


VIEW_UNITS = {"bend_persistence_length": "nm", "torsional_modulus": "pN nm^2", "stretch_modulus": "pN"}
