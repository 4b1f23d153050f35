"""What the report says first: the headline result in plain language, and for every summary
row without a number the one-line reason it has none.

The page (report.py, write_html) opens with `verdict(res)` and a figure; the summary table
then holds only rows with a number, and `reason_missing` fills the "not measured or
refused" list below it."""
from __future__ import annotations

import math

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


def verdict(res: dict) -> str:
    """Two or three plain sentences (HTML-safe: numbers and fixed words only, plus escaped
    reasons from the caller) on what this run found at the headline kick."""
    import html
    head = number(res.get("headline_A_v_A_per_ps"))
    rod, rod_e = number(res.get("rod_wave_speed_A_per_ps")), number(res.get("rod_wave_speed_err_A_per_ps"))
    md, md_e = number(res.get("md_wave_speed_A_per_ps")), number(res.get("md_wave_speed_err_A_per_ps"))
    cg, cg_e = number(res.get("cg_rod_wave_speed_A_per_ps")), number(res.get("cg_rod_wave_speed_err_A_per_ps"))
    out = []
    if math.isfinite(md) and math.isfinite(rod):
        out.append(f"Kicked at A_v = {head:g} A/ps, the all-atom MD's mode runs at {_pm(md, md_e)} A/ps, "
                   f"{md / rod:.2f} times the rod's {_pm(rod, rod_e)} A/ps (the paper's constants): "
                   f"{_compare(md, md_e, rod, rod_e)}.")
    elif math.isfinite(rod):
        out.append(f"Kicked at A_v = {head:g} A/ps, the rod's mode runs at {_pm(rod, rod_e)} A/ps (the paper's "
                   f"constants); the MD gives no speed: {html.escape(md_reason(res))}.")
    else:
        out.append(f"No rod speed at the headline A_v = {head:g} A/ps: the rod run is missing or its fit failed.")
    if math.isfinite(cg) and math.isfinite(md):
        out.append(f"The rod coarse-grained from the unkicked MD predicts {_pm(cg, cg_e)} A/ps: "
                   f"{_compare(cg, cg_e, md, md_e)} from the MD.")
    elif math.isfinite(cg):
        out.append(f"The rod coarse-grained from the unkicked MD predicts {_pm(cg, cg_e)} A/ps, with no MD "
                   "speed to test it against.")
    else:
        out.append("No coarse-grained prediction: "
                   + html.escape(str(res.get("cg_rod_reason") or "the coarse-graining loop did not run")) + ".")
    return " ".join(out)


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
