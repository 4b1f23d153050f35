"""results.json["comparison"]: the matched rod-vs-MD comparison built from the
per-run analysis files (their `standing_mode`, `matched` and `plane` blocks, written by
workflows/steps/analyse.py through workflows/steps/matched.py). Every key is described in
docs/analysis.md, "Matched comparison"."""
from __future__ import annotations

import html
import math

from mdbridge.analysis.matched import regime
from mdbridge.analysis.mode_error import combine_seeds

from dnarod.report.values import number


def _fit_of(j):
    """The run's standing-mode fit; older analysis files without it: NaN with the reason."""
    if not j:
        return None
    sm = j.get("standing_mode")
    if sm is None:
        return {"speed_A_per_ps": float("nan"), "reason": "analysis file has no standing_mode block"}
    return sm


def _rod_row(j) -> dict | None:
    if not j:
        return None
    f = _fit_of(j) or {}
    m = j.get("matched", {})
    return {"A_v_A_per_ps": j.get("A_v_A_per_ps"), "quantity": f.get("quantity"),
            "wave_kind": f.get("wave_kind"),
            "omega_per_ps": number(f.get("omega_per_ps")), "omega_err_per_ps": number(f.get("omega_err_per_ps")),
            "speed_A_per_ps": number(f.get("speed_A_per_ps")),
            "speed_err_A_per_ps": number(f.get("speed_err_A_per_ps")),
            "speed_err_fit_A_per_ps": number(f.get("speed_err_fit_A_per_ps")),
            "speed_err_record_A_per_ps": number(f.get("speed_err_record_A_per_ps")),
            "periods_in_record": number(f.get("periods_in_record")),
            "mode_amplitude_A": number(f.get("mode_amplitude_A")), "offset_A": number(f.get("offset_A")),
            "contour_strain": number(m.get("contour_strain_mean")),
            "tension_pN": number(m.get("tension_pN")), "tension_sem_pN": number(m.get("tension_sem_pN")),
            "tension_max_pN": number(m.get("tension_max_pN")),
            "plane_angle_to_scene_deg": (j.get("plane") or {}).get("plane_angle_to_scene_deg"),
            "reason": f.get("reason"), "complete": j.get("complete", True)}


def _md_row(runs: list[dict]) -> dict | None:
    runs = [r for r in runs if r]
    if not runs:
        return None
    fits = [_fit_of(r) for r in runs]
    comb = combine_seeds(fits)
    ms = [r.get("matched", {}) for r in runs]
    T = [number(m.get("tension_pN")) for m in ms]
    Te = [number(m.get("tension_sem_pN")) for m in ms]
    okT = [(t, e) for t, e in zip(T, Te) if math.isfinite(t)]
    tension = sum(t for t, _ in okT) / len(okT) if okT else float("nan")
    tension_sem = math.sqrt(sum(e * e for _, e in okT)) / len(okT) if okT else float("nan")
    strain = [number(m.get("contour_strain_mean")) for m in ms]
    strain = [s for s in strain if math.isfinite(s)]
    return dict(comb, A_v_A_per_ps=runs[0].get("A_v_A_per_ps"), seeds=[r.get("seed") for r in runs],
                per_seed=[{"seed": r.get("seed"), "speed_A_per_ps": number((f or {}).get("speed_A_per_ps")),
                           "speed_err_A_per_ps": number((f or {}).get("speed_err_A_per_ps")),
                           "reason": (f or {}).get("reason")} for r, f in zip(runs, fits)],
                contour_strain=sum(strain) / len(strain) if strain else float("nan"),
                tension_pN=tension, tension_sem_pN=tension_sem,
                tension_reason=next((m.get("tension_reason") for m in ms if m.get("tension_reason")), None),
                mass_per_length_kg_per_m=number(ms[0].get("mass_per_length_kg_per_m")),
                plane_angle_to_scene_deg=[(r.get("plane") or {}).get("plane_angle_to_scene_deg") for r in runs])


def comparison_block(cfg: dict, data: dict) -> dict:
    from mdbridge.analysis.dispersion import critical_compression
    from dna_models.units import Units
    from dnarod.steps.matched import interp_rod_curve
    u = Units.paper()
    seeds = [int(s) for s in cfg["seeds"]]
    avs = sorted(data["rod"])
    rows_or_none = [_rod_row(j) for j, _ in list(data["sweep"].values()) + list(data["rod"].values()) if j]
    curve = [r for r in rows_or_none if r and math.isfinite(r["omega_per_ps"])]
    rows = {}
    for av in avs:
        rows[av] = {"rod": _rod_row(data["rod"][av][0]),
                    "md": _md_row([data["md"].get((av, s), (None, None))[0] for s in seeds])}
    base_md = rows.get(0.0, {}).get("md")
    base_rod = rows.get(0.0, {}).get("rod")
    md_base_T = base_md["tension_pN"] if base_md else None
    rod_base_T = base_rod["tension_pN"] if base_rod else 0.0
    buck = None
    j = next((j for j, _ in data["rod"].values() if j), None)     # none: no wave analyses (analysis.waves)
    if j:
        d = j.get("dispersion", {})
        if d.get("fiducial_length"):
            c = critical_compression(d["fiducial_length"], d.get("D1", u.D_star[0]), u.C_star[2])
            buck = {"critical_strain": c["strain"], "critical_tension_pN": c["n3"] * u.C * 1e12,
                    "source": "bend branch of Eq 39 with axial force reaches 0 "
                              "(mdbridge/analysis/dispersion.py: critical_compression)"}
    out_rows = []
    for av, r in rows.items():
        rod, md = r["rod"], r["md"]
        row = {"A_v_A_per_ps": av, "rod": rod, "md": md}
        if rod:
            row["rod_regime"] = regime(rod["tension_pN"] - rod_base_T, rod_base_T)
            # the label uses the time-mean tension (as for MD); the rod's peak is known too
            row["rod_regime"]["peak_tension_pN"] = rod["tension_max_pN"]
            row["rod_regime"]["peak_regime"] = regime(rod["tension_max_pN"] - rod_base_T, rod_base_T)["regime"]
        if md:
            added = md["tension_pN"] - md_base_T if md_base_T is not None and math.isfinite(md_base_T) \
                else md["tension_pN"]
            base_err = base_md["tension_sem_pN"] if base_md and base_md is not md else 0.0
            row["md_regime"] = regime(added, md_base_T,
                                      math.hypot(md["tension_sem_pN"], base_err or 0.0))
            if md_base_T is None:
                row["md_regime"]["note"] = ("no A_v = 0 MD run: the added tension is the total; "
                                            "the baseline is not known")
            if md.get("mode_amplitude_A") and curve:
                at = interp_rod_curve(curve, md["mode_amplitude_A"])
                rho_rod = u.rho
                rho_md = md.get("mass_per_length_kg_per_m")
                if math.isfinite(at["omega_per_ps"]):
                    w = at["omega_per_ps"]
                    row["rod_at_md_amplitude"] = dict(at, md_omega_per_ps=md["omega_per_ps"],
                                                      md_over_rod=md["omega_per_ps"] / w)
                    if rho_md and math.isfinite(rho_md):
                        row["rod_at_md_amplitude"]["omega_at_md_mass_per_length_per_ps"] = \
                            w * math.sqrt(rho_rod / rho_md)
                else:
                    row["rod_at_md_amplitude"] = at
            if buck and math.isfinite(md.get("contour_strain", float("nan"))):
                row["md_beyond_rod_buckling"] = bool(md["contour_strain"] < buck["critical_strain"])
        if rod and md:
            row["same_kick_velocity"] = {"rod_omega_per_ps": rod["omega_per_ps"],
                                         "md_omega_per_ps": md.get("omega_per_ps"),
                                         "note": "secondary: the same A_v does not give the same "
                                                 "amplitude or strain"}
        out_rows.append(row)
    pre = [_rod_row(j) for j, _ in data.get("prestrain", {}).values() if j]
    return {"rows": out_rows, "md_baseline_tension_pN": md_base_T,
            "md_baseline_note": None if md_base_T is not None else "no A_v = 0 MD run",
            "rod_curve": [{"A_v_A_per_ps": r["A_v_A_per_ps"], "mode_amplitude_A": r["mode_amplitude_A"],
                           "omega_per_ps": r["omega_per_ps"], "omega_err_per_ps": r["omega_err_per_ps"],
                           "tension_pN": r["tension_pN"]} for r in sorted(curve, key=lambda r: r["mode_amplitude_A"])],
            "buckling": buck, "prestrain_rod": pre or None,
            "rod_mass_per_length_kg_per_m": u.rho}


def _f(x, nd=3):
    try:
        x = float(x)
    except (TypeError, ValueError):
        return "n/a" if x is None else html.escape(str(x))
    return "n/a" if not math.isfinite(x) else f"{x:.{nd}g}"


def html_table(comp: dict) -> str:
    """The matched comparison as an HTML section."""
    trs = []
    for r in comp["rows"]:
        rod, md = r.get("rod") or {}, r.get("md") or {}
        at = r.get("rod_at_md_amplitude") or {}
        if md.get("speed_err_realisations_A_per_ps") is not None:
            seeds = (f"one seed; between runs of this setting {_f(md['speed_err_realisations_A_per_ps'], 2)}, "
                     "results/main_job_realisations.json")
        elif md.get("speed_err_seeds_A_per_ps") is not None:
            seeds = _f(md["speed_err_seeds_A_per_ps"], 2)
        else:
            seeds = "not estimable: one seed"
        md_err = (f"{_f(md.get('speed_err_A_per_ps'), 2)} (fit {_f(md.get('speed_err_fit_A_per_ps'), 2)}, "
                  f"record {_f(md.get('speed_err_record_A_per_ps'), 2)}, seeds {seeds})") if md else "n/a"
        md_speed = (_f(md.get("speed_A_per_ps")) if math.isfinite(number(md.get("speed_A_per_ps")))
                    else "refused: " + html.escape(str(md.get("reason", "")))) if md else "n/a"
        trs.append(
            f"<tr><td>{_f(r['A_v_A_per_ps'])}</td>"
            f"<td>{_f(rod.get('mode_amplitude_A'))} / {_f(md.get('mode_amplitude_A'))}</td>"
            f"<td>{_f(rod.get('speed_A_per_ps'))} &plusmn; {_f(rod.get('speed_err_A_per_ps'), 2)} "
            f"({html.escape(str(rod.get('quantity')))})</td>"
            f"<td>{md_speed} &plusmn; {md_err} ({html.escape(str(md.get('quantity')))})</td>"
            f"<td>{_f(at.get('omega_per_ps'))} (MD: {_f(md.get('omega_per_ps'))}) "
            f"{html.escape(at.get('reason', ''))}</td>"
            f"<td>{_f(rod.get('contour_strain'))} / {_f(md.get('contour_strain'))}</td>"
            f"<td>{_f(rod.get('tension_pN'))} / {_f(md.get('tension_pN'))} &plusmn; {_f(md.get('tension_sem_pN'), 2)}"
            f"{' (' + html.escape(md['tension_reason']) + ')' if md.get('tension_reason') else ''}</td>"
            f"<td>rod: {html.escape((r.get('rod_regime') or {}).get('regime', 'n/a'))}; "
            f"MD: {html.escape((r.get('md_regime') or {}).get('regime', 'n/a'))}</td></tr>")
    b = comp.get("buckling") or {}
    notes = [f"A_v = {_f(r['A_v_A_per_ps'])}: the MD's mean contour strain is below the rod's buckling "
             f"strain {_f(b.get('critical_strain'))}: the rod would buckle there"
             for r in comp["rows"] if r.get("md_beyond_rod_buckling")]
    pre = comp.get("prestrain_rod") or []
    pre_html = ""
    if pre:
        pre_html = ("<h3>Rod at the MD's rest length</h3><table><tr><th>A_v [A/ps]</th><th>rod [A/ps]</th>"
                    "<th>tension [pN]</th></tr>" + "".join(
                        f"<tr><td>{_f(p.get('A_v_A_per_ps'))}</td><td>{_f(p.get('speed_A_per_ps'))} &plusmn; "
                        f"{_f(p.get('speed_err_A_per_ps'), 2)}</td><td>{_f(p.get('tension_pN'))}</td></tr>"
                        for p in pre) + "</table>")
    return ("<h2>Matched comparison (amplitude, strain, tension)</h2>"
            "<p>Frequencies from the fit with the static mode offset; errors = fit (parametric bootstrap) "
            "&oplus; record length &oplus; between seeds (docs/analysis.md). Regime from the tension "
            f"the kick adds above the A_v = 0 baseline (MD baseline: {_f(comp.get('md_baseline_tension_pN'))} pN). "
            f"Rod buckling strain: {_f(b.get('critical_strain'))}.</p>"
            "<table><tr><th>A_v [A/ps]</th><th>mode amplitude rod / MD [A]</th><th>rod [A/ps]</th>"
            "<th>MD [A/ps]</th><th>rod omega at the MD amplitude [rad/ps]</th>"
            "<th>contour strain rod / MD</th><th>tension rod / MD [pN]</th><th>regime</th></tr>"
            + "\n".join(trs) + "</table>"
            + "".join(f"<p><b>{html.escape(n)}</b></p>" for n in notes) + pre_html)
