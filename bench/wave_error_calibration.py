"""Is the stated error of the standing-mode frequency (mdbridge/analysis/mode_error.py,
the error WaveAnalysis and the workflow report) the real one? A calibration study over a
grid of synthetic records.

Each record is the fundamental's complex amplitude c(t) of a standing mode,

    c(t) = A cos(w t + p) + B e^{i q} + z(t),

A = 10 A, a small static offset |B| = 1 A, and z complex Ornstein-Uhlenbeck noise (each
part an exact AR(1) of correlation time tau, stationary from the first sample) of rms
sigma per part. The grid: sigma / A (weak to as large as the mode), tau (a few ps to a
period) and the record length in periods (0.75 to 3), the period 400 ps sampled every
5 ps. Over N realisations (fixed seeds) it records, per grid point: the RMS error of the
fitted w about the true w; the RMS of the stated error (total, and its fit and record
parts) and their ratios to it, with the 68 % interval of the stated ratio from resampling
the realisations; the bias; how many records were refused (mode_error.refusal) or gave no
fit, per refusal rule. Errors that are not stated are given beside it: the linearised
error with the estimated noise (`linear`), with the true noise covariance (`oracle`; where
even it is off, the fit is nonlinear there) and with the estimated noise taken as white
(`white`: the error model that ignores the noise's correlation, the calibration test's
control). Each point also keeps, per record, what the record shows of itself (the rule
that refused it, the fitted noise / mode, correlation time, detection margin, fraction of
bootstrap records on another peak; `record_diagnostics`) with its error about the truth,
so that other refusal thresholds can be judged on the same records without refitting
(`rescore`, `--rescore`).

    nice -n 10 /usr/bin/python3 bench/wave_error_calibration.py [--n-real 60] [--n-boot 200]
        [--out bench/results/wave_error_calibration.json] [--part K/N] [--points K ...]
    /usr/bin/python3 bench/wave_error_calibration.py --merge part0.json part1.json [--out ...]
    /usr/bin/python3 bench/wave_error_calibration.py --rescore 0 1 2 3 | --scan | --slipped [--out ...]
    /usr/bin/python3 bench/wave_error_calibration.py --table [--out ...]
"""
from __future__ import annotations

import argparse
import itertools
import json
import math
import platform
import time

import numpy as np
from scipy.signal import lfilter

from dna_models.bdna import RISE_A
from mdbridge.analysis import mode_error, mode_noise
from mdbridge.analysis.wavespeed import amplitudes, jacobian, linear_covariance
from mdbridge.jsonio import write_json

PERIOD_PS = 400.0
DT_PS = 5.0
AMPLITUDE_A = 10.0
OFFSET_A = 1.0
K_PER_A = 2 * math.pi / (158 * RISE_A)
W_TRUE = 2 * math.pi / PERIOD_PS
NOISE_REL = (0.03, 0.3, 1.0)
TAU_PS = (2.0, 40.0, 400.0)
PERIODS = (0.75, 1.5, 3.0)
BAND = (0.7, 1.4)
# mode_error.refusal's rules, by a phrase of their reason
REFUSAL_RULES = {"noise": "exceeds", "detection": "no oscillation", "other_peak": "does not select",
                 "short": "periods of the fitted", "other": ""}


def records(rng, periods: float, noise_rel: float, tau_ps: float, n_real: int):
    """Times (T,) and n_real records c (n_real, T); the noise rms per part."""
    t = np.arange(0.0, periods * PERIOD_PS + 1e-9, DT_PS)
    phi = math.exp(-DT_PS / tau_ps)
    sigma = noise_rel * AMPLITUDE_A
    e = rng.standard_normal((2, n_real, len(t)))
    e[..., 0] /= math.sqrt(1 - phi ** 2)          # stationary from the first sample
    z = lfilter([math.sqrt(1 - phi ** 2) * sigma], [1, -phi], e, axis=-1)
    p = rng.uniform(0, 2 * np.pi, (n_real, 1))
    q = rng.uniform(0, 2 * np.pi, (n_real, 1))
    c = AMPLITUDE_A * np.cos(W_TRUE * t[None] + p) + OFFSET_A * np.exp(1j * q) + z[0] + 1j * z[1]
    return t, c, sigma


def ratio_interval(stated: np.ndarray, error: np.ndarray, rng, n_resample: int = 400):
    """16th and 84th percentiles of RMS(stated) / RMS(error) over realisations resampled
    with replacement: the sampling error of the ratio itself."""
    idx = rng.integers(0, len(error), (n_resample, len(error)))
    r = np.sqrt(np.mean(stated[idx] ** 2, axis=1) / np.mean(error[idx] ** 2, axis=1))
    return [float(x) for x in np.percentile(r, [15.865, 84.135])]


def record_diagnostics(f: dict) -> dict:
    """What one record shows of itself (no truth): the refusal rule that stopped it (or
    None), the fitted frequency's error about the truth and its stated error, and the
    quantities a refusal rule can judge -- the fitted noise over the fitted mode amplitude,
    the fitted correlation time, the detection margin (the record's line power over the
    noise-alone quantile) and the fraction of bootstrap records on another peak."""
    g = f.get("unreported", f)
    rule = None
    if "reason" in f and f["reason"]:
        rule = next((r for r, key in REFUSAL_RULES.items() if key in f["reason"]), "other")
    row = {"rule": rule}
    if "noise_rms_A" not in g:
        return row

    def r4(x):                    # 4 significant digits
        return float(f"{x:.4g}") if math.isfinite(x) else None
    mode = g["amplitude_forward_A"] + g["amplitude_backward_A"]
    row.update(omega_error_per_ps=r4(g["omega_per_ps"] - W_TRUE), omega_err_per_ps=r4(g["omega_err_per_ps"]),
               noise_over_mode=r4(g["noise_rms_A"] / mode) if mode > 0 else None,
               tau_ps=r4(g["noise_tau_ps"]),
               detection_margin=r4(g["line_power"] / g["noise_only_line_power"])
               if g["noise_only_line_power"] > 0 else None,
               other_peak=r4(g["bootstrap_other_peak_fraction"]))
    return row


def grid_point(periods: float, noise_rel: float, tau_ps: float, n_real: int, seed: int,
               n_boot: int = mode_error.N_BOOT) -> dict:
    """The calibration of one grid point (module doc)."""
    rng = np.random.default_rng(seed)
    t, c, sigma = records(rng, periods, noise_rel, tau_ps, n_real)
    tc = t - t.mean()
    rows = []
    refused, no_fit = 0, 0
    refused_by = {rule: 0 for rule in REFUSAL_RULES}
    per_record = []
    for i, ci in enumerate(c):
        f = mode_error.standing_mode_fit(t, ci, K_PER_A, n_boot=n_boot, seed=i)
        per_record.append(record_diagnostics(f))
        if "unreported" in f:
            refused += 1
            refused_by[next((r for r, key in REFUSAL_RULES.items() if key in f["reason"]), "other")] += 1
            continue
        if not math.isfinite(f["speed_A_per_ps"]):
            no_fit += 1
            continue
        w = f["omega_per_ps"]
        A, _ = amplitudes(tc, ci[None], np.array([w]), True)
        J = jacobian(tc, w, A[0])
        oracle = math.sqrt(linear_covariance(t, J, sigma, tau_ps)[0, 0])
        rec = f["omega_err_record_per_ps"]
        white = math.sqrt(linear_covariance(t, J, f["noise_rms_A"], 0.0)[0, 0])
        rows.append((w - W_TRUE, f["omega_err_per_ps"], f["omega_err_fit_per_ps"],
                     rec if math.isfinite(rec) else 0.0, f["omega_err_linear_per_ps"], oracle, white))
    out = {"periods": periods, "noise_rel": noise_rel, "tau_ps": tau_ps, "n_real": n_real,
           "n_boot": n_boot, "seed": seed, "n_reported": len(rows), "n_refused": refused,
           "n_no_fit": no_fit, "refused_by": refused_by, "records": per_record}
    if len(rows) < 3:
        return out
    a = np.array(rows)
    err = a[:, 0]
    rms = float(np.sqrt(np.mean(err ** 2)))

    def ratio(col):
        return float(np.sqrt(np.mean(a[:, col] ** 2)) / rms)
    out.update(rms_error_per_ps=rms, bias_over_rms=float(err.mean() / rms),
               stated_over_rms=ratio(1), stated_over_rms_interval=ratio_interval(a[:, 1], err, rng),
               fit_over_rms=ratio(2), record_over_rms=ratio(3), linear_over_rms=ratio(4),
               oracle_over_rms=ratio(5), white_over_rms=ratio(6))
    return out


MIN_REPORTED = 10          # a ratio needs this many numbers (its 68 % interval is in the row)


def status(row: dict) -> str:
    """"refused": no realisation gives a number (each is refused with its reason); "in band":
    stated / RMS within BAND over at least MIN_REPORTED numbers; else "out of band" or
    "too few" (numbers whose error cannot be checked)."""
    if row["n_reported"] == 0:
        return "refused"
    if row["n_reported"] < MIN_REPORTED:
        return "too few"
    return "in band" if BAND[0] <= row["stated_over_rms"] <= BAND[1] else "out of band"


def in_band(row: dict) -> bool:
    return status(row) == "in band"


def table_lines(rows: list[dict]) -> list[str]:
    """The grid as the markdown table of docs/analysis.md (held to it by
    tests/python/test_wave_error_calibration.py)."""
    lines = ["| periods | noise / mode | tau [ps] | numbers / refused / no fit | stated / RMS (68 %) | linear | "
             "white | bias / RMS | status |", "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        head = (f"| {r['periods']:g} | {r['noise_rel']:g} | {r['tau_ps']:g} | "
                f"{r['n_reported']} / {r['n_refused']} / {r['n_no_fit']} | ")
        if "stated_over_rms" in r:
            lo, hi = r["stated_over_rms_interval"]
            head += (f"{r['stated_over_rms']:.2f} ({lo:.2f}-{hi:.2f}) | {r['linear_over_rms']:.2f} | "
                     f"{r['white_over_rms']:.2f} | {r['bias_over_rms']:+.2f} | ")
        else:
            head += "- | - | - | - | "
        lines.append(head + status(r) + " |")
    return lines


def rms_rel_err(n_frames: int, phi: float) -> float:
    """Relative standard error u of the rms of complex AR(1) noise (coefficient phi per
    frame) estimated over n_frames: the sample variance of one part has relative variance
    (2 / n) (1 + phi^2) / (1 - phi^2) (the sum of the squared autocorrelation phi^2|k|), the
    two parts halve it, and the rms has half the relative error of the variance. For a
    correlation time tau >> the step this is 1/2 sqrt(tau / span): a noise as slow as the
    record is known to no better than ~50 %."""
    return 0.5 * math.sqrt((1 + phi ** 2) / (n_frames * (1 - phi ** 2)))


def rescore(row: dict, noise_sigma: float = 0.0, noise_max_rel: float = mode_error.NOISE_MAX_REL,
            other_peak_max: float = mode_error.OTHER_PEAK_MAX, rel_err_max: float = 0.5) -> dict:
    """The grid point `row` under other refusal constants, from its records' diagnostics
    alone (no refit): how many numbers it keeps and their stated / RMS. The noise rule
    compares the fitted noise / mode raised by noise_sigma of its relative sampling error
    (rms_rel_err at the fitted correlation time, at most rel_err_max, one independent sample
    per part) with noise_max_rel; noise_sigma = 0 is mode_error.refusal's rule. The rules
    before it (drift, detection) and the last (too short, which does not depend on these
    constants) keep their verdicts; a record they did not reach is judged by the last one
    as a standing mode. With the module's constants it reproduces the committed counts
    (tests/python/test_wave_error_calibration.py)."""
    span_ps = row["periods"] * PERIOD_PS
    n_frames = int(round(span_ps / DT_PS)) + 1
    kept = []
    for x in row["records"]:
        if x["rule"] not in (None, "noise", "other_peak") or "noise_over_mode" not in x:
            continue                  # refused by a rule that does not depend on these constants
        phi = math.exp(-DT_PS / x["tau_ps"]) if x["tau_ps"] > 0 else 0.0
        u = min(rms_rel_err(n_frames, min(phi, mode_noise.PHI_MAX)), rel_err_max)
        if x["noise_over_mode"] * (1 + noise_sigma * u) > noise_max_rel:
            continue
        if x["other_peak"] > other_peak_max:
            continue
        w, err = W_TRUE + x["omega_error_per_ps"], x["omega_err_per_ps"]
        upper = (w + mode_error.REFUSE_SIGMA * err) * span_ps / (2 * math.pi)
        if x["rule"] is not None and upper < mode_error.REPORT_MIN_PERIODS:
            continue                  # (a record that gave a number passed it: it may be travelling)
        kept.append((x["omega_error_per_ps"], err))
    out = {"n_reported": len(kept), "n_real": row["n_real"]}
    if len(kept) >= 3:
        a = np.array(kept)
        out["stated_over_rms"] = float(np.sqrt(np.mean(a[:, 1] ** 2) / np.mean(a[:, 0] ** 2)))
    return out


def inflated_in_band(row: dict, r0: float, p: float) -> bool:
    """Whether the grid point `row` is in band (or gives no number) when each record that gave
    a number has its stated error multiplied by max(1, r / r0)^p, r its fitted noise / mode:
    an error model that grows with the noise the record shows of itself (--scan-inflation)."""
    kept = [x for x in row["records"] if x["rule"] is None and "noise_over_mode" in x]
    if len(kept) < 3:
        return True
    stated = np.array([x["omega_err_per_ps"] * max(1.0, x["noise_over_mode"] / r0) ** p for x in kept])
    error = np.array([x["omega_error_per_ps"] for x in kept])
    ratio = float(np.sqrt(np.mean(stated ** 2) / np.mean(error ** 2)))
    return BAND[0] <= ratio <= BAND[1]


GRID = [(P, nr, tau) for P in PERIODS for nr in NOISE_REL for tau in TAU_PS]


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n-real", type=int, default=60)
    ap.add_argument("--n-boot", type=int, default=mode_error.N_BOOT)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", default="bench/results/wave_error_calibration.json")
    ap.add_argument("--part", default="0/1", help="K/N: run only grid points k with k %% N == K "
                    "(to spread the grid over processes; --merge joins the parts)")
    ap.add_argument("--points", nargs="+", type=int, metavar="K",
                    help="run only these grid points (index k in the grid, periods x noise x tau)")
    ap.add_argument("--rescore", nargs="+", type=float, metavar="NOISE_SIGMA",
                    help="print, from the records of --out, what the noise rule raised by these "
                         "many sampling errors of the fitted noise would keep at each grid point "
                         "(rescore), and stop")
    ap.add_argument("--scan", action="store_true",
                    help="print, from the records of --out, how many grid points are neither in band nor "
                         "refused under each noise limit 0.3-0.5, NOISE_SIGMA 0-4 and other-peak limit 2 or 10 %%")
    ap.add_argument("--scan-inflation", action="store_true",
                    help="print, from the records of --out, how many grid points are out of band when every "
                         "kept record's stated error is multiplied by max(1, r / r0)^p (r its fitted noise / "
                         "mode), r0 0.1-0.3, p 0.5-6: an error model that grows with the noise")
    ap.add_argument("--slipped", action="store_true",
                    help="print, from --out, what the records that give a number show of themselves: "
                         "each one at noise as large as the mode, the 5-95 %% range at noise 0.3")
    ap.add_argument("--table", action="store_true", help="print the grid of --out as docs/analysis.md's table")
    ap.add_argument("--merge", nargs="+", metavar="PART_JSON", help="join these parts into --out and stop")
    return ap


def print_scan(a) -> None:
    """--scan: grid points neither in band nor refused under each rule's limits."""
    rows = json.loads(open(a.out).read())["grid"]
    print("| noise limit | NOISE_SIGMA | other-peak limit | points neither in band nor refused |")
    print("|---|---|---|---|")
    for limit, sigma, other in itertools.product((0.3, 0.35, 0.4, 0.45, 0.5), range(5), (0.02, 0.1)):
        bad = [r for r in rows if status(dict(r, **rescore(r, sigma, limit, other))) not in ("in band", "refused")]
        print(f"| {limit:g} | {sigma} | {other:g} | {len(bad)} |")


def print_scan_inflation(a) -> None:
    """--scan-inflation: grid points out of band under an error that grows with the noise."""
    rows = json.loads(open(a.out).read())["grid"]
    print("| r0 | p | points out of band |")
    print("|---|---|---|")
    for r0, p in itertools.product((0.1, 0.15, 0.2, 0.25, 0.3), (0.5, 1, 2, 3, 4, 6)):
        bad = [r for r in rows if not inflated_in_band(r, r0, p)]
        print(f"| {r0:g} | {p:g} | {len(bad)} |")


def print_slipped(a) -> None:
    """--slipped: what the records that give a number show of themselves."""
    keys = ("noise_over_mode", "detection_margin", "tau_ps")
    for r in json.loads(open(a.out).read())["grid"]:
        kept = [x for x in r["records"] if x["rule"] is None and "noise_over_mode" in x]
        if r["noise_rel"] == 0.3 and kept:
            rng5_95 = {k: np.percentile([x[k] for x in kept], [5, 95]).round(3).tolist() for k in keys}
            print(f"{r['periods']:g} periods, noise 0.3, tau {r['tau_ps']:g} ps: 5-95 % {rng5_95}")
        elif r["noise_rel"] == 1.0:
            for x in kept:
                z = x["omega_error_per_ps"] / x["omega_err_per_ps"]
                print(f"{r['periods']:g} periods, noise 1, tau {r['tau_ps']:g} ps: "
                      + ", ".join(f"{k} {x[k]:.3g}" for k in keys) + f", error / stated {z:+.2f}")


def print_rescore(a) -> None:
    """--rescore: what the raised noise rule would keep at each grid point."""
    rows = json.loads(open(a.out).read())["grid"]
    print("| periods | noise / mode | tau [ps] | " + " | ".join(f"NOISE_SIGMA = {x:g}" for x in a.rescore) + " |")
    print("|---|---|---|" + "---|" * len(a.rescore))
    for r in rows:
        cells = []
        for x in a.rescore:
            q = rescore(r, x)
            ratio = f" ({q['stated_over_rms']:.2f})" if "stated_over_rms" in q else ""
            cells.append(f"{q['n_reported']}{ratio}")
        print(f"| {r['periods']:g} | {r['noise_rel']:g} | {r['tau_ps']:g} | " + " | ".join(cells) + " |")


def merge(a) -> None:
    """--merge: join the parts into --out."""
    parts = [json.loads(open(f).read()) for f in a.merge]
    rows = sorted((r for p in parts for r in p["grid"]),
                  key=lambda r: GRID.index((r["periods"], r["noise_rel"], r["tau_ps"])))
    merged = dict(parts[0], grid=rows, points_in_band=sum(in_band(r) for r in rows), points=len(rows),
                  command="; ".join([p["command"] for p in parts]
                                    + [f"bench/wave_error_calibration.py --merge {' '.join(a.merge)}"]),
                  wall_s=round(sum(p["wall_s"] for p in parts), 1), part="merged")
    write_json(a.out, merged)
    print(f"wrote {a.out}: {merged['points_in_band']} of {merged['points']} points in band")


def run_grid(a) -> None:
    """The grid points of --part (and --points), printed as they finish, written to --out."""
    part, n_parts = (int(x) for x in a.part.split("/"))
    rows = []
    t0 = time.time()
    print("| periods | noise / mode | tau [ps] | reported | refused / no fit | stated / RMS (68 %) | fit | record "
          "| linear | oracle | bias / RMS |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for k, (P, nr, tau) in enumerate(GRID):
        if k % n_parts != part or (a.points and k not in a.points):
            continue
        r = grid_point(P, nr, tau, a.n_real, a.seed + k, a.n_boot)
        rows.append(r)
        if "stated_over_rms" in r:
            lo, hi = r["stated_over_rms_interval"]
            print(f"| {P:g} | {nr:g} | {tau:g} | {r['n_reported']}/{a.n_real} | {r['n_refused']} / {r['n_no_fit']} | "
                  f"{r['stated_over_rms']:.2f} ({lo:.2f}-{hi:.2f}) | {r['fit_over_rms']:.2f} | "
                  f"{r['record_over_rms']:.2f} | {r['linear_over_rms']:.2f} | {r['oracle_over_rms']:.2f} | "
                  f"{r['bias_over_rms']:+.2f} |", flush=True)
        else:
            print(f"| {P:g} | {nr:g} | {tau:g} | {r['n_reported']}/{a.n_real} | {r['n_refused']} / {r['n_no_fit']} | "
                  "too few reported | | | | | |", flush=True)
    write_json(a.out, {"about": __doc__.strip().splitlines()[0], "band": list(BAND),
                       "period_ps": PERIOD_PS, "dt_ps": DT_PS, "amplitude_A": AMPLITUDE_A,
                       "offset_A": OFFSET_A, "grid": rows,
                       "points_in_band": sum(in_band(r) for r in rows), "points": len(rows),
                       "command": "/usr/bin/python3 bench/wave_error_calibration.py "
                                  f"--n-real {a.n_real} --n-boot {a.n_boot} --seed {a.seed} --part {a.part}",
                       "wall_s": round(time.time() - t0, 1), "part": a.part,
                       "date": time.strftime("%Y-%m-%d"), "machine": platform.node()})
    print(f"wrote {a.out}")


def print_table(a) -> None:
    """--table: the grid of --out as docs/analysis.md's table."""
    print("\n".join(table_lines(json.loads(open(a.out).read())["grid"])))


def main(argv=None):
    a = parser().parse_args(argv)
    for flag, report in (("scan", print_scan), ("scan_inflation", print_scan_inflation), ("slipped", print_slipped),
                         ("table", print_table), ("rescore", print_rescore), ("merge", merge)):
        if getattr(a, flag):
            return report(a)
    run_grid(a)


if __name__ == "__main__":
    main()
