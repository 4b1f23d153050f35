"""What the report says first: what this run found in at most five plain sentences, each
reason for a missing number once (`opening`), and for every summary row without a number
the one-line reason it has none (`reason_missing`).

The page (report.py, write_html) opens with `opening(res)` and a figure; the summary table
then holds only rows with a number, and `reason_missing` fills the "not measured or
refused" list below it, where the reasons stand in full."""
from __future__ import annotations

import html
import math
import re

from dnarod.report import dispersion
from dnarod.report.values import number

Z_AGREE = 2.0   # two standard errors: "agree" below, "differ" at or above


def _headline_row(res: dict) -> dict:
    head = number(res.get("headline_A_v_A_per_ps"))
    for r in (res.get("comparison") or {}).get("rows", []):
        if number(r.get("A_v_A_per_ps")) == head:
            return r
    return {}


def md_reason(res: dict) -> str:
    """Why the headline MD has no speed: the fit's refusal, or no MD run."""
    md = _headline_row(res).get("md") or {}
    if md.get("reason"):
        return str(md["reason"])
    if not res.get("runs", {}).get("md"):
        return "no MD run at the headline A_v (md.enabled is false, or the MD has not finished)"
    return "the MD's wave fit gave no speed"


def _pm(v: float, e: float) -> str:
    return f"{v:.3g} &plusmn; {e:.2g}" if math.isfinite(e) else f"{v:.3g}"


def _compare(a: float, ea: float, b: float, eb: float) -> str:
    err = math.hypot(ea if math.isfinite(ea) else 0.0, eb if math.isfinite(eb) else 0.0)
    if not err > 0:
        return "(no error to judge the difference by)"
    z = (a - b) / err
    return ("they agree within two standard errors" if abs(z) < Z_AGREE
            else f"they differ by {abs(z):.1f} standard errors")


def _md_error_note(res: dict) -> str:
    """What the MD's +- holds (with one seed): the realisations' floor, or that it is one record's."""
    r = res.get("md_wave_speed_realisations") or {}
    if r.get("floor_A_per_ps") is not None:
        return (f" (this record's own error {number(res.get('md_wave_speed_err_one_record_A_per_ps')):.2g} and the "
                f"scatter between {r['k']} runs of this setting, {r['floor_A_per_ps']:.2g})")
    if r.get("reason") and not r.get("n_seeds"):
        return " (one record's error: the scatter between runs of this setting is not measured)"
    return ""


def findings(res: dict) -> tuple[list[str], list[tuple[str, str]]]:
    """What the kicked runs found, for the opening: at most two plain sentences (HTML-safe:
    numbers and fixed words only), and the results without a number as (what, reason)."""
    head = number(res.get("headline_A_v_A_per_ps"))
    rod, rod_e = number(res.get("rod_wave_speed_A_per_ps")), number(res.get("rod_wave_speed_err_A_per_ps"))
    md, md_e = number(res.get("md_wave_speed_A_per_ps")), number(res.get("md_wave_speed_err_A_per_ps"))
    cg, cg_e = number(res.get("cg_rod_wave_speed_A_per_ps")), number(res.get("cg_rod_wave_speed_err_A_per_ps"))
    out, refused = [], []
    if math.isfinite(md) and math.isfinite(rod):
        out.append(f"Kicked at A_v = {head:g} A/ps, the all-atom MD's mode runs at {_pm(md, md_e)} A/ps"
                   f"{_md_error_note(res)}, {md / rod:.2f} times the rod's {_pm(rod, rod_e)} A/ps (the paper's "
                   f"constants): {_compare(md, md_e, rod, rod_e)}.")
    elif math.isfinite(rod):
        out.append(f"Kicked at A_v = {head:g} A/ps, the rod's mode runs at {_pm(rod, rod_e)} A/ps (the paper's "
                   "constants).")
        refused.append(("the MD's kicked speed", md_reason(res)))
    else:
        refused.append(("the rod's kicked speed", "the rod run is missing or its fit failed"))
    if math.isfinite(cg) and math.isfinite(md):
        out.append(f"The rod coarse-grained from the unkicked MD predicts {_pm(cg, cg_e)} A/ps: "
                   f"{_compare(cg, cg_e, md, md_e)} from the MD.")
    elif math.isfinite(cg):
        out.append(f"The rod coarse-grained from the unkicked MD predicts {_pm(cg, cg_e)} A/ps, with no MD "
                   "speed to test it against.")
    else:
        refused.append(("the coarse-grained rod's kicked speed",
                        str(res.get("cg_rod_reason") or "the coarse-graining loop did not run")))
    return out, refused


def _clauses(reason: str) -> list[str]:
    # one sentence of the opening holds every reason: a reason's own full stops become
    # semicolons, and "refused: " says nothing the sentence does not
    r = re.sub(r"\.\s+(?=[A-Z])", "; ", reason.strip().rstrip("."))
    return [c for c in r.split(": ") if c]


COMMON_MIN_CHARS = 30   # a shared head of clauses at least this long is one reason


def group_reasons(items: list[tuple[str, str]]) -> list[tuple[list[str], str]]:
    """[(whats, reason)]: the items whose reasons are one reason, merged. Two reasons are one
    when one ends with the other (the loop's "coarse-graining refused: X" and the dispersion's
    "X": the longer is kept), or when they share leading clauses (split at ": ") of at least
    COMMON_MIN_CHARS (two rods refused at one tension: the shared head is kept, the rest is in
    the details below)."""
    groups: list[tuple[list[str], list[str]]] = []
    for what, reason in items:
        cl = _clauses(reason)
        if cl and cl[0] == "refused":
            cl = cl[1:]
        for whats, gcl in groups:
            a, b = ": ".join(cl), ": ".join(gcl)
            if a.endswith(b) or b.endswith(a):
                whats.append(what)
                gcl[:] = cl if len(a) > len(b) else gcl
                break
            n = 0
            while n < min(len(cl), len(gcl)) and cl[n] == gcl[n]:
                n += 1
            if n and len(": ".join(cl[:n])) >= COMMON_MIN_CHARS:
                whats.append(what)
                gcl[:] = gcl[:n]
                break
        else:
            groups.append(([what], cl))
    return [(whats, ": ".join(cl)) for whats, cl in groups]


def _and(xs: list[str]) -> str:
    return xs[0] if len(xs) == 1 else ", ".join(xs[:-1]) + " and " + xs[-1]


MAX_SENTENCES = 5     # findings: 2, dispersion.findings: 2, what has no number: 1


def opening(res: dict, waves: bool = True) -> list[str]:
    """What this run found, in at most MAX_SENTENCES plain sentences: the kicked wave (MD
    against the paper rod; the coarse-grained rod's prediction), the equilibrium modes
    (dispersion.findings), and one sentence that names what has no number, each reason once
    (group_reasons). The reasons in full stand below: the "not measured" list and the
    dispersion section."""
    said, refused = findings(res) if waves else ([], [])
    d_said, d_refused = dispersion.findings(res.get("dispersion"))
    out = said + d_said
    groups = group_reasons(refused + d_refused)
    if groups:
        out.append("Without a number (in full below): " + "; ".join(
            f"{_and(whats)} ({html.escape(why)})" for whats, why in groups) + ".")
    return out


def reason_missing(label: str, res: dict) -> str:
    """One line: why the summary row LABEL has no number in this run."""
    if label.startswith("MD") and "speed" not in label and "frequency" not in label:
        return "no MD run at the headline A_v" if not res.get("runs", {}).get("md") else "not measured in this run"
    if label.startswith("MD"):
        return md_reason(res)
    if label.startswith("predicted"):
        return str(res.get("cg_rod_reason") or "the coarse-graining loop did not run (no A_v = 0 MD run)")
    if label.startswith("rod D") or label.startswith("rod C3"):
        return ("the modulus fit is off in this configuration (analysis.fit_modulus)"
                if not res.get("modulus_fit_for_md_speed") else "the fit found no modulus for the MD speed")
    if label.startswith("rod-MD"):
        return "needs a rod run and an MD run at the headline A_v, each with frames"
    return "not measured in this run"
