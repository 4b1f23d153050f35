"""Per-mode frequency errors from the scatter of independent blocks of a record, pooled over
realisations (docs/dispersion.md, "Errors from blocks").

The fit error of `dnarod modes` (mdbridge/analysis/mode_spectra.py) is the observed
information of one record's periodogram: it sees the record's own noise, not a frequency that
wanders over the record (slow episodes of the vacuum duplex, docs/dispersion.md "The
statics"), so two realisations of one system differ by more than it says (bend: chi2 70 for
9). The error here is what the same estimator does from one stretch of the record to the next.

Blocks. The record is cut into B blocks of equal length, and every mode of a kind is fitted
in each block by the same estimator as the whole record (`mode_spectra.fit_kind`: each block
with its own common background; a block fit refused by `mode_spectra.refusal` is dropped).
The rule for a mode's blocks:
  * each block holds BLOCK_PERIODS periods of the mode (the estimator's own minimum,
    mode_spectra.MIN_PERIODS), so that every block can be fitted;
  * each block is at least BLOCK_CORRELATION_TIMES amplitude correlation times 1 / gamma
    long: the mode's amplitude forgets its phase in 1 / gamma, its periodogram (quadratic in
    it) in 1 / (2 gamma), so neighbouring blocks' periodograms are nearly independent;
  * B is the largest of BLOCK_COUNTS that the record allows under both (omega, gamma from the
    whole record's fit): MIN_BLOCKS = 8 where the mode allows it, and no more, so that the
    blocks are as long as 8 of them can be. Fewer (down to 3) where the mode needs longer
    blocks, with Student-t (below).
A frequency that wanders more slowly than the blocks are long makes neighbouring blocks agree,
and then their scatter understates the error: the block error covers a wander whose
correlation time is up to a block, not beyond (the test's control: episodes two blocks long).
With one record nothing can tell a wander slower than its blocks from a fixed offset of that
realisation; only more realisations can (pooled here, and mdbridge/analysis/realisation_floor.py).

Error. Each realisation r has m_r block frequencies; their relative scatter (each over its own
mean) is pooled over realisations,
    s^2 = sum_r (m_r - 1) s_r^2 / nu,   nu = sum_r (m_r - 1),
and realisation r's frequency (the whole record's fit) has the error omega_r s / sqrt(m_r)
(the error of the mean of m_r blocks). With nu degrees of freedom, (omega - truth) / error is
Student-t: its variance is nu / (nu - 2), so a chi^2 built from these errors has
E[chi^2 / dof] = nu / (nu - 2) instead of 1 (1.4 at nu = 7, 3 at nu = 3). `err_chi2` is the
error times sqrt(nu / (nu - 2)), whose z has variance 1; nu < MIN_NU gives no variance and no
error. Both omega (the damped frequency, what the fit reports) and omega0 =
sqrt(omega^2 + gamma^2) (the undamped one, what a rod without friction has) are given.

Checked (tests/python/test_block_errors.py) on synthetic damped oscillators of known
frequency: over 100 independent realisations the z of the whole record's frequency with the
block error has variance ~1, with a stationary oscillator and with one whose frequency jumps
between eight episodes of the record (one per block); in the second the fit (curvature) error
fails (its z variance is several), and so does a block error halved (the control); with four
episodes (two blocks each) the block error fails too, as the rule says it must.
"""
from __future__ import annotations

import math

import numpy as np

from mdbridge.analysis.mode_spectra import MIN_PERIODS, ModeSeries, fit_kind, pooled_series, refusal

BLOCK_PERIODS = MIN_PERIODS
BLOCK_CORRELATION_TIMES = 2.0
MIN_BLOCKS = 8                        # per realisation where the mode allows; fewer enter through Student-t
BLOCK_COUNTS = (MIN_BLOCKS, 6, 4, 3)  # tried largest first; each costs one fit of every mode of a kind per block
MIN_NU = 3                            # Student-t has a variance only for nu > 2
MAX_REFUSED_FRACTION = 0.5            # more block fits refused than this: no block error for the realisation


def block_length_ps(omega_per_ps: float, gamma_per_ps: float) -> float:
    """The shortest block the rule allows for a mode of damped frequency omega and damping
    gamma (module doc): BLOCK_PERIODS periods and BLOCK_CORRELATION_TIMES / gamma."""
    tau = BLOCK_CORRELATION_TIMES / gamma_per_ps if gamma_per_ps > 0 else math.inf
    return max(BLOCK_PERIODS * 2 * math.pi / omega_per_ps, tau)


def block_count(record_ps: float, omega_per_ps: float, gamma_per_ps: float, counts=BLOCK_COUNTS) -> int | None:
    """The largest of `counts` whose blocks satisfy the rule in a record of record_ps, or None."""
    allowed = record_ps / block_length_ps(omega_per_ps, gamma_per_ps)
    ok = [b for b in counts if b <= allowed + 1e-9]
    return max(ok) if ok else None


def block_frequencies(s: ModeSeries, kind: str, n_blocks: int, wanted=None) -> np.ndarray:
    """(n_blocks, n_modes, 2): omega and omega0 [rad/ps] of every mode of `kind` fitted in each
    of n_blocks equal blocks of the realisation s (mode_spectra.fit_kind, each block with its
    own common background); NaN where a block's fit is refused (mode_spectra.refusal) or the
    mode is not wanted."""
    n_modes = len(s.n)
    T = len(s.times_ps)
    m = T // n_blocks
    block_ps = m * s.dt_ps
    out = np.full((n_blocks, n_modes, 2), np.nan)
    for b in range(n_blocks):
        part = slice(b * m, (b + 1) * m)
        xs = [pooled_series([s], kind, i, T, part) for i in range(n_modes)]
        for i, (fit, why) in enumerate(fit_kind(xs, s.dt_ps, "none", wanted=wanted)):
            if why is None and refusal(fit, block_ps) is None:
                out[b, i] = fit.omega_per_ps, fit.omega0_per_ps
    return out


def _pooled_scatter(blocks: list[np.ndarray]) -> tuple[float, int, list[int]]:
    """(s^2, nu, m_r) of the relative scatter of each realisation's block values about their
    own mean, pooled (module doc)."""
    ss, nu, ms = 0.0, 0, []
    for v in blocks:
        v = v[np.isfinite(v)]
        ms.append(len(v))
        if len(v) >= 2:
            rel = v / v.mean()
            ss += float(np.sum((rel - rel.mean()) ** 2))
            nu += len(v) - 1
    return (ss / nu if nu else math.nan), nu, ms


def pooled_block_error(full: list[float], blocks: list[np.ndarray]) -> dict:
    """The block error of each realisation's whole-record frequency `full[r]` from its block
    frequencies `blocks[r]` (NaN: refused), pooled over realisations (module doc). Returns
    {"err": [per realisation], "err_chi2": [...], "nu", "blocks_per_realisation",
    "relative_scatter", "student_t_variance"} or, with too few blocks, err None and a `reason`."""
    cur = [np.asarray(v, float) for v in blocks]
    for r, v in enumerate(cur):
        if len(v) and np.mean(~np.isfinite(v)) > MAX_REFUSED_FRACTION:
            cur[r] = np.full(0, np.nan)
    s2, nu, ms = _pooled_scatter(cur)
    if nu < MIN_NU:
        n_ok = [int(np.isfinite(np.asarray(v, float)).sum()) for v in blocks]
        return {"err": None, "err_chi2": None, "nu": nu, "blocks_per_realisation": ms, "relative_scatter": None,
                "reason": f"too few blocks fitted ({n_ok} per realisation; at least {MIN_NU} degrees of freedom "
                          f"pooled are needed, and no realisation with more than {100 * MAX_REFUSED_FRACTION:g} % "
                          "of its block fits refused)"}
    s = math.sqrt(s2)
    inflate = math.sqrt(nu / (nu - 2))
    err = [f * s / math.sqrt(m) if m >= 2 else None for f, m in zip(full, ms)]
    return {"err": err, "err_chi2": [None if e is None else e * inflate for e in err], "nu": nu,
            "blocks_per_realisation": ms, "relative_scatter": s, "student_t_variance": nu / (nu - 2)}


def mode_block_errors(series: list[ModeSeries], tables: list[dict], kinds=("bend", "twist", "stretch"),
                      counts=BLOCK_COUNTS) -> list[dict]:
    """Every mode's block error, pooled over the realisations `series` (one ModeSeries each,
    the window already cut: ModeSeries.after) whose whole-record mode tables are `tables`
    (modes.json of each, from `dnarod modes` on that window). A mode enters when every
    realisation measures it; its block count is the smallest that the rule gives over the
    realisations (module doc). Returns one entry per (kind, n): per realisation omega,
    omega0 and their fit errors, the block errors of both, nu, blocks, or the reason there
    are none."""
    if len(series) != len(tables):
        raise ValueError(f"{len(series)} realisations, {len(tables)} mode tables")
    rows: dict[tuple, list] = {(e["kind"], int(e["n"])): [] for e in tables[0]["modes"]}
    for t in tables:
        for e in t["modes"]:
            rows.setdefault((e["kind"], int(e["n"])), []).append(e)
    plan: dict = {}
    out = []
    for (kind, n), es in rows.items():
        if kind not in kinds:
            continue
        entry = {"kind": kind, "n": n, "omega_per_ps": [e.get("omega_per_ps") for e in es],
                 "omega_err_fit_per_ps": [e.get("omega_err_per_ps") for e in es],
                 "omega0_per_ps": [e.get("omega0_per_ps") for e in es],
                 "omega0_err_fit_per_ps": [e.get("omega0_err_per_ps") for e in es], "reason": None}
        if len(es) != len(series) or any(e.get("omega_per_ps") is None for e in es):
            entry["reason"] = "not measured in every realisation"
        else:
            bs = [block_count(len(s.times_ps) * s.dt_ps, e["omega_per_ps"], e["damping_per_ps"] or 0.0, counts)
                  for s, e in zip(series, es)]
            ok = [b for b in bs if b is not None]
            if len(ok) < len(bs):
                entry["reason"] = (f"the record holds no {min(counts)} blocks of {BLOCK_PERIODS:g} periods and "
                                   f"{BLOCK_CORRELATION_TIMES:g} correlation times 1 / gamma")
            else:
                entry["n_blocks"] = min(ok)
                plan.setdefault((kind, min(ok)), []).append(n)
        out.append(entry)
    fitted: dict = {}
    for (kind, B), ns in plan.items():
        wanted = [int(n) in ns for n in series[0].n]
        fitted[(kind, B)] = [block_frequencies(s, kind, B, wanted) for s in series]
    for entry in out:
        if entry["reason"] is not None:
            continue
        B = entry["n_blocks"]
        i = [int(v) for v in series[0].n].index(entry["n"])
        per = fitted[(entry["kind"], B)]
        for j, key in ((0, "omega"), (1, "omega0")):
            r = pooled_block_error(entry[f"{key}_per_ps"], [p[:, i, j] for p in per])
            r["block_values_per_ps"] = [[None if not np.isfinite(v) else float(v) for v in p[:, i, j]] for p in per]
            entry[f"{key}_block"] = r
        entry["block_ps"] = [len(s.times_ps) // B * s.dt_ps for s in series]
        if entry["omega_block"]["err"] is None:
            entry["reason"] = entry["omega_block"]["reason"]
    return out
