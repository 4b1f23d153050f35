"""results.json["dispersion"] and the report's dispersion section: the unkicked MD's
measured modes against the coarse-grained and the paper rod's predicted ones
(workflows/steps/dispersion.py writes DIR/dispersion/box*/dispersion.json; docs/dispersion.md)."""
from __future__ import annotations

import html
import math
from pathlib import Path

import numpy as np

from dnarod.report.values import number

KINDS = ("bend", "twist", "stretch")
MODELS = (("cg_rod", "coarse-grained rod"), ("cg_rod_box_twist", "coarse-grained rod, box twist"),
          ("paper_rod", "paper rod"))
Z_AGREE = 2.0


def collect(cfg: dict, out: Path) -> dict:
    """{box scale label: its dispersion.json as a Prediction (mdbridge/analysis/results.py)} of
    the scales that were analysed."""
    from mdbridge.analysis.results import Prediction
    found = {}
    d = out / "dispersion"
    for p in sorted(d.glob("box*/dispersion.json")) if d.is_dir() else []:
        found[p.parent.name[3:]] = Prediction.read(p)
    return found


def _row(r: dict) -> dict:
    keys = ["kind", "n", "k_per_A", "md_omega0_per_ps", "md_omega0_err_per_ps", "md_omega_damped_per_ps",
            "md_damping_per_ps", "md_reason"]
    for name, _ in MODELS:
        keys += [f"{name}_omega_per_ps", f"{name}_omega_err_per_ps", f"z_{name}"]
    return {k: r.get(k) for k in keys}


def _summary(rows: list, name: str) -> dict:
    z = np.array([float(r[f"z_{name}"]) for r in rows if r.get(f"z_{name}") is not None])
    return {"modes_compared": len(z), "within_2_sigma": int(np.sum(np.abs(z) < Z_AGREE)),
            "median_abs_z": float(np.median(np.abs(z))) if len(z) else None,
            "chi2": float(np.sum(z ** 2)) if len(z) else None}


def results(cfg: dict, found: dict) -> dict | None:
    """results.json["dispersion"] (None when the dispersion did not run): one row per mode of
    the unstretched run (MD omega0, the two rods' omega, errors, z), the tension, the MD's T
    and B from its dynamics and its statics, and per box scale the tension and the fits."""
    disp = cfg.get("dispersion", {}) or {}
    if not (disp.get("enabled") and cfg.get("md", {}).get("enabled", True)
            and 0.0 in [float(a) for a in cfg["A_v_A_per_ps"]]):
        return None     # as the Snakefile's DISP_ON: the dispersion needs the unkicked MD
    base = found.get("1")
    if base is None:
        return {"reason": "no dispersion result (dispersion/box1/dispersion.json): the MD or its analysis "
                          "has not finished", "rows": []}
    rows = [_row(r) for r in base.rows]
    out = {"rows": rows, "tension_pN": base.tension["tension_pN"],
           "tension_err_pN": base.tension["tension_err_pN"], "temperature_K": base.temperature_K,
           "length_A": base.length_A, "record_ps": base.record_ps, "discard_ps": disp.get("discard_ps"),
           "cg_rod_reason": base.cg_rod_reason, "refused": base.refused,
           "rod_states": {n: p.get("state") for n, p in base.predictions.items()},
           "summary": {name: dict(_summary(rows, name), **{kind: _summary([r for r in rows if r["kind"] == kind],
                                                                           name) for kind in KINDS})
                       for name, _ in MODELS},
           "fit": base.fit, "definition": base.definition,
           "box_scales": [{"scale": float(s), "tension_pN": j.tension["tension_pN"],
                           "tension_err_pN": j.tension["tension_err_pN"],
                           "length_A": j.length_A,
                           "fit_dynamics": {k: j.fit["dynamics"].get(k) for k in
                                            ("tension_pN", "tension_err_pN", "B_pN_nm2", "B_err_pN_nm2", "reason")},
                           "bend_omega0_per_ps": {r["n"]: r["md_omega0_per_ps"] for r in j.rows_of("bend")
                                                  if r["md_omega0_per_ps"] is not None}}
                          for s, j in sorted(found.items(), key=lambda kv: float(kv[0]))]}
    return out


def findings(d: dict | None) -> tuple[list[str], list[tuple[str, str]]]:
    """What the dispersion found, for the report's opening (verdict.opening): at most two plain
    sentences (the modes against the rods; the MD's own tension and stiffness), and the
    predictions without a number as (what, reason) pairs, whose reasons the opening states once
    and `html_section` in full. Empty when the dispersion did not run."""
    if d is None:
        return [], []
    if not d.get("rows"):
        return [], [("the equilibrium modes", str(d.get("reason")))]
    measured = sum(1 for r in d["rows"] if r["md_omega0_per_ps"] is not None)
    compared, refused = [], []
    for name, label in MODELS:
        s = d["summary"][name]
        if s["modes_compared"]:
            per = ", ".join(f"{s[k]['within_2_sigma']} of {s[k]['modes_compared']} {k}" for k in KINDS
                            if s[k]["modes_compared"])
            compared.append(f"the {label} for {per} (median |z| {s['median_abs_z']:.2g})")
        elif (d.get("refused") or {}).get(name) and name != "cg_rod_box_twist":
            refused.append((f"the {label}'s modes", str(d["refused"][name])))
    first = (f"At equilibrium the MD resolves {measured} of its {len(d['rows'])} modes (bend, twist, stretch) at its "
             f"virial tension {d['tension_pN']:.3g} &plusmn; {d['tension_err_pN']:.2g} pN")
    out = [first + ("; within two standard errors of them, with no fitted parameter: " + "; ".join(compared)
                    if compared else "") + "."]
    dyn = d["fit"]["dynamics"]
    if not dyn.get("reason"):
        out.append(f"From its own bend modes the MD's tension is {dyn['tension_pN']:.3g} &plusmn; "
                   f"{dyn['tension_err_pN']:.2g} pN and its bend persistence length {dyn['persistence_length_nm']:.3g} "
                   f"&plusmn; {dyn['persistence_length_err_nm']:.2g} nm.")
    return out, refused


def _f(x, nd=3):
    x = number(x)
    return "n/a" if not math.isfinite(x) else f"{x:.{nd}g}"


def _pm(v, e):
    if v is None:
        return "n/a"
    if e is not None and abs(number(e)) <= 1e-9 * abs(number(v)):
        e = 0.0          # round-off (a rod's twist and stretch do not feel the tension)
    return f"{_f(v, 4)} &plusmn; {_f(e, 2)}"


def html_section(d: dict | None) -> str:
    """The z-score table (one row per mode; a refused MD mode with its reason) and the fit of
    T and B, as HTML."""
    if d is None:
        return ""
    if not d.get("rows"):
        return f"<h2 id=\"dispersion\">Dispersion</h2><p>{html.escape(str(d.get('reason')))}</p>"
    body = []
    for r in d["rows"]:
        z = "".join(f"<td>{_pm(r.get(f'{n}_omega_per_ps'), r.get(f'{n}_omega_err_per_ps'))}</td>"
                    f"<td>{_f(r.get(f'z_{n}'), 2)}</td>" for n, _ in MODELS)
        md = _pm(r["md_omega0_per_ps"], r["md_omega0_err_per_ps"]) if r["md_omega0_per_ps"] is not None else \
            f"refused: {html.escape(str(r['md_reason']))}"
        body.append(f"<tr><td>{r['kind']}</td><td>{r['n']}</td><td>{_f(r['k_per_A'], 3)}</td><td>{md}</td>{z}</tr>")
    fit = d["fit"]

    def fit_line(f, what):
        if f.get("reason"):
            return f"<li>{what}: not fitted ({html.escape(f['reason'])})</li>"
        return (f"<li>{what} (bend n = {', '.join(map(str, f['n']))}): "
                f"T = {_pm(f['tension_pN'], f['tension_err_pN'])} pN, "
                f"B = {_pm(f['B_pN_nm2'], f['B_err_pN_nm2'])} pN nm^2 (persistence length "
                f"{_pm(f['persistence_length_nm'], f['persistence_length_err_nm'])} nm), chi2 = {_f(f['chi2'], 2)} "
                f"for {f['dof']} degrees of freedom</li>")
    mats = "; ".join(f"{label}: B = {_f(fit['materials'][n]['B_pN_nm2'], 4)} pN nm^2 "
                     f"({_f(fit['materials'][n]['persistence_length_nm'], 3)} nm)"
                     for n, label in MODELS if n in fit["materials"])
    boxes = ""
    if len(d["box_scales"]) > 1:
        rows = []
        for b in d["box_scales"]:
            fd = b["fit_dynamics"]
            rows.append(f"<tr><td>{b['scale']:g}</td><td>{_pm(b['tension_pN'], b['tension_err_pN'])}</td>"
                        f"<td>{_pm(fd.get('tension_pN'), fd.get('tension_err_pN'))}</td>"
                        f"<td>{', '.join(_f(b['bend_omega0_per_ps'].get(n), 3) for n in (1, 2, 3, 4))}</td></tr>")
        boxes = ("<table id=\"dispersion-boxes\"><tr><th>box length scale</th><th>virial tension [pN]</th>"
                 "<th>T from the bend dynamics [pN]</th><th>bend omega0, n = 1..4 [rad/ps]</th></tr>"
                 + "".join(rows) + "</table>")
    refused = "".join(f"<li><b>{html.escape(label)}</b>: {html.escape(str(d['refused'][n]))}</li>"
                      for n, label in MODELS if (d.get("refused") or {}).get(n))
    refused = f"<p>Predictions without a number:</p><ul id=\"dispersion-refused\">{refused}</ul>" if refused else ""
    st = (d.get("rod_states") or {}).get("cg_rod")
    torque = (f"<p>The coarse-grained material's intrinsic twist is {_f(st['intrinsic_twist_over_box'], 4)} times the "
              f"ligated box's: held at the box's twist its rod carries a torque of {_f(st['torque_pN_nm'], 3)} pN nm, "
              "which softens its bend modes; the box-twist rod is the same material without it.</p>") if st else ""
    heads = "".join(f"<th>{label} omega [rad/ps]</th><th>z</th>" for _, label in MODELS)
    return (f"<h2 id=\"dispersion\">Dispersion: the MD's modes against the rod's</h2>"
            f"<p>The unkicked MD's Fourier modes (<code>dnarod modes</code>, {_f(d['record_ps'], 4)} ps after "
            f"{_f(d['discard_ps'], 4)} ps discarded): the undamped frequency omega0 = sqrt(omega^2 + gamma^2) of "
            f"each fitted mode, against the linear rod's at the MD's virial tension "
            f"{_pm(d['tension_pN'], d['tension_err_pN'])} pN (rod errors: the coarse-graining's bootstrap "
            "materials and the tension's error); z = (MD - rod) / sqrt(err_MD^2 + err_rod^2). "
            "docs/dispersion.md.</p>"
            f"<table id=\"dispersion-table\"><tr><th>kind</th><th>n</th><th>k [1/A]</th><th>MD omega0 [rad/ps]</th>"
            f"{heads}</tr>{''.join(body)}</table>{refused}{torque}"
            f"<p>The MD's own tension and bend stiffness, fitted with the linear rod ({html.escape(fit['template'])} "
            f"for every other constant):</p><ul id=\"dispersion-fit\">"
            + fit_line(fit["dynamics"], "from the frequencies")
            + fit_line(fit["statics"], "from the oscillators' static variances")
            + f"</ul><p>z (T, dynamics - virial) = {_f(fit.get('z_T_dynamics_vs_virial'), 2)}; z (B, dynamics - "
            f"statics) = {_f(fit.get('z_B_dynamics_vs_statics'), 2)}. The rods' own: {mats}.</p>" + boxes)


def markdown_table(d: dict) -> str:
    """The prediction-vs-MD table of a dispersion.json (workflows/steps/dispersion.py) as
    Markdown: the tension, one row per mode (MD omega0, each rod's omega, errors, z) and the
    MD's own T and B; what `python -m dnarod.steps.dispersion table` prints."""
    def pm(v, e):
        return "n/a" if v is None else _pm(v, e).replace("&plusmn;", "±")
    t = d["tension"]
    names = [(n, label) for n, label in MODELS if n in d["predictions"]]
    out = [f"{d['n_bp']} bp, {d['turns']} turns, {_f(d.get('record_ps'), 4)} ps of MD at "
           f"{_f(d['temperature_K'], 4)} K; "
           f"virial tension {pm(t['tension_pN'], t['tension_err_pN'])} pN; omega in rad/ps, "
           "z = (MD - rod) / sqrt(err_MD^2 + err_rod^2).", ""]
    for n, why in (d.get("refused") or {}).items():
        out += [f"No {n}: {why}", ""]
    out.append("| kind | n | k [1/A] | MD omega0 | " + " | ".join(f"{label} | z" for _, label in names) + " |")
    out.append("|---" * (4 + 2 * len(names)) + "|")
    for r in d["rows"]:
        md = pm(r["md_omega0_per_ps"], r["md_omega0_err_per_ps"]) if r["md_omega0_per_ps"] is not None else \
            f"refused ({r['md_reason']})"
        cells = [r["kind"], str(r["n"]), _f(r["k_per_A"], 3), md]
        for n, _ in names:
            cells += [pm(r.get(f"{n}_omega_per_ps"), r.get(f"{n}_omega_err_per_ps")), _f(r.get(f"z_{n}"), 2)]
        out.append("| " + " | ".join(cells) + " |")
    out.append("")
    for key, what in (("dynamics", "from the bend frequencies"), ("statics", "from the oscillators' static variances")):
        f = d["fit"][key]
        out.append(f"- MD's T and B {what}: " + (f"not fitted ({f['reason']})" if f.get("reason") else
                   f"n = {', '.join(map(str, f['n']))}: T = {pm(f['tension_pN'], f['tension_err_pN'])} pN, "
                   f"B = {pm(f['B_pN_nm2'], f['B_err_pN_nm2'])} pN nm^2 (persistence length "
                   f"{pm(f['persistence_length_nm'], f['persistence_length_err_nm'])} nm), "
                   f"chi2 {_f(f['chi2'], 2)} for {f['dof']} dof"))
    fit = d["fit"]
    out.append(f"- z (T, dynamics - virial) = {_f(fit.get('z_T_dynamics_vs_virial'), 2)}; z (T, statics - virial) = "
               f"{_f(fit.get('z_T_statics_vs_virial'), 2)}; z (B, dynamics - statics) = "
               f"{_f(fit.get('z_B_dynamics_vs_statics'), 2)}")
    return "\n".join(out) + "\n"


def figure(d: dict | None):
    """omega against k, one panel per kind: MD points (omega0 with errors), the coarse-grained
    rod's and the paper rod's predictions (lines, with the CG rod's error band)."""
    if d is None or not d.get("rows"):
        return None
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    for ax, kind in zip(axes, KINDS):
        rows = [r for r in d["rows"] if r["kind"] == kind]
        k = [r["k_per_A"] for r in rows]
        for (name, label), style, color in zip(MODELS, ("-", ":", "--"), ("C0", "C2", "k")):
            w = [r.get(f"{name}_omega_per_ps") for r in rows]
            if all(v is not None for v in w) and w:
                ax.plot(k, w, style, marker=".", ms=3, color=color, lw=1, label=label)
                e = [r.get(f"{name}_omega_err_per_ps") or 0.0 for r in rows]
                if name != "paper_rod":
                    ax.fill_between(k, [a - b for a, b in zip(w, e)], [a + b for a, b in zip(w, e)],
                                    color=color, alpha=0.2, lw=0)
        ok = [r for r in rows if r["md_omega0_per_ps"] is not None]
        if ok:
            ax.errorbar([r["k_per_A"] for r in ok], [r["md_omega0_per_ps"] for r in ok],
                        yerr=[r["md_omega0_err_per_ps"] or 0.0 for r in ok], fmt="o", ms=4, capsize=2, color="C3",
                        label="MD (omega0)")
        if kind == "bend":
            ax.set_xscale("log")
            ax.set_yscale("log")
        ax.set(xlabel="k = 2 pi n / L [1/A]", ylabel="omega [rad/ps]",
               title=f"{kind}: {len(ok)} of {len(rows)} modes measured")
        ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


CAPTION = ("Frequency against wavenumber of the unkicked MD's Fourier modes (points: the undamped frequency of "
           "each fitted mode, with its error; refused modes left out), the coarse-grained rod's prediction (line, "
           "with its error band from the material's bootstrap replicas and the tension's error), the same "
           "material with its intrinsic twist at the box's (dotted: no torque held by the ligation) and the paper "
           "rod's (dashed), all at the MD's virial tension, with no fitted parameter. Look for where the MD "
           "leaves the rod's curve: the lowest bend modes measure the tension, the highest what shear and rotary "
           "inertia add over a Kirchhoff rod.")
