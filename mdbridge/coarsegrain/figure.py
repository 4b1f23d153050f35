"""Figures of a coarse-graining: the stiffness against the wavenumber q along the sequence,
convergence (each continuum constant against the number of frames used, the first n frames
of the equilibrium part, with the full run's bootstrap error scaled by sqrt(T / n) as a
band) and the constants against the segment length m (with their bootstrap errors)."""
from __future__ import annotations

import numpy as np

SHOWN = ("bend_persistence_length", "torsional_modulus", "stretch_modulus", "twist_stretch_coupling")


def _save(fig, path, title: str):
    """The figures' common ending: title, layout, file, figure closed."""
    import matplotlib.pyplot as plt
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def convergence_figure(path, params: dict):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    c = params["convergence"]
    n = np.array(c["frames"], dtype=float)
    phys = params["by_length"][[b["m"] for b in params["by_length"]].index(c["m"])]["physical"]
    fig, axes = plt.subplots(1, len(SHOWN), figsize=(4 * len(SHOWN), 3.2))
    for ax, k in zip(axes, SHOWN):
        v = np.array(c["physical"][k], dtype=float)
        full, err = phys[k]["value"], phys[k]["err"]
        band = err * np.sqrt(n[-1] / n)
        ax.fill_between(n, full - band, full + band, color="0.85", label="full-run error x sqrt(T/n)")
        ax.plot(n, v, "o-", color="C0", label="first n frames")
        ax.axhline(full, color="k", lw=0.8)
        ax.set_xlabel("frames used")
        ax.set_title(f"{k.replace('_', ' ')} [{phys[k]['unit']}]", fontsize=9)
    axes[0].legend(fontsize=7)
    return _save(fig, path, f"convergence, m = {c['m']} ({params['source']})")


def length_figure(path, params: dict):
    """Continuum constants against the coarse-graining length m (by_length)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    bl = params["by_length"]
    m = np.array([b["m"] for b in bl])
    shown = ("bend_persistence_length", "bend_persistence_length_tangent") + SHOWN[1:]
    fig, axes = plt.subplots(1, len(shown), figsize=(4 * len(shown), 3.2))
    for ax, k in zip(axes, shown):
        v = np.array([b["physical"][k]["value"] for b in bl])
        e = np.array([b["physical"][k]["err"] for b in bl])
        ax.errorbar(m, v, yerr=e, fmt="o-", ms=3, capsize=2)
        ax.set_xlabel("m (steps per segment)")
        ax.set_title(f"{k.replace('_', ' ')} [{bl[0]['physical'][k]['unit']}]", fontsize=9)
    return _save(fig, path, f"continuum constants against segment length ({params['source']})")


def q_stiffness_figure(path, params: dict):
    """Bend, twist and stretch stiffness against the wavenumber q along the sequence
    (params.json q_stiffness): every mode with its bootstrap error (open: left out by the
    closure), the modes of the q -> 0 fit, K(q -> 0) at q = 0 and the per-step compliance
    average as a line. The helical wavenumber (twist per step) is marked: a laboratory-frame
    bend of long wavelength sits there in the base-pair frames."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    qs = params["q_stiffness"]
    q = np.array(qs["q_rad_per_step"])
    use = np.array(qs["usable"], bool)
    fit = np.isin(np.array(qs["k"]), qs["fit_modes"])
    twist_deg = params["average"]["mean"][5]
    shown = ("bend_persistence_length", "torsional_modulus", "stretch_modulus")
    fig, axes = plt.subplots(1, len(shown), figsize=(4.2 * len(shown), 3.4))
    for ax, k in zip(axes, shown):
        d = qs[k]
        v, e = np.array(d["value"], float), np.array(d["err"], float)
        ax.errorbar(q[use], v[use], yerr=e[use], fmt="o", ms=3, capsize=1.5, color="C0", label="S(q) per mode")
        ax.errorbar(q[fit], v[fit], yerr=e[fit], fmt="o", ms=4, capsize=1.5, color="C3", label="fit modes")
        if (~use).any():
            ax.plot(q[~use], v[~use], "x", color="0.5", label="closure's modes (not used)")
        ax.errorbar([0.0], [d["at_q0"]], yerr=[d["at_q0_err"]], fmt="s", ms=5, color="k", capsize=2,
                    label="K(q -> 0) (the rod)")
        ax.axhline(d["compliance_average"], color="C2", ls="--", lw=1, label="per-step compliance average")
        ax.axvline(np.radians(twist_deg), color="0.6", ls=":", lw=1, label="helical wavenumber")
        ax.set_xlabel("q [rad per step]")
        ax.set_title(f"{k.replace('_', ' ')} [{d['unit']}]", fontsize=9)
    axes[0].legend(fontsize=6)
    return _save(fig, path, f"stiffness against wavenumber along the sequence ({params['source']})")
