"""Figures of a coarse-graining: convergence (each continuum constant against the
number of frames used, the first n frames of the equilibrium part, with the full
run's bootstrap error scaled by sqrt(T / n) as a band) and the constants against the
segment length m (with their bootstrap errors)."""
from __future__ import annotations

import numpy as np

SHOWN = ("bend_persistence_length", "torsional_modulus", "stretch_modulus", "twist_stretch_coupling")


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
    fig.suptitle(f"convergence, m = {c['m']} ({params['source']})", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


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
    fig.suptitle(f"continuum constants against segment length ({params['source']})", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
