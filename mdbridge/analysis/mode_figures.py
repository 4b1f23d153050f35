"""Figures of `dnarod modes`: each mode's power spectrum with its fitted model
(spectra.png) and omega against k (dispersion.png)."""
from __future__ import annotations

import numpy as np

from mdbridge.analysis.modes import KINDS
from mdbridge.analysis.spectrum import band_indices, expected_periodogram, frequencies_per_ps, periodogram


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def spectra_figure(series, table: dict, path):
    """One panel per mode (rows: bend, twist, stretch): the periodogram summed over the
    pooled series (grey), the fitted model's expected periodogram on its band, common
    background included (red), the fitted omega (dashed); a refused mode's panel names the
    reason."""
    from mdbridge.analysis.mode_spectra import pooled_series
    plt = _plt()
    n_frames, dt = table["n_frames"], table["dt_ps"]
    n_modes = max(e["n"] for e in table["modes"])
    fig, axes = plt.subplots(len(KINDS), n_modes, figsize=(1.9 * n_modes, 1.9 * len(KINDS)), squeeze=False)
    lam = frequencies_per_ps(n_frames, dt)
    for e in table["modes"]:
        r, c = KINDS.index(e["kind"]), e["n"] - 1
        ax = axes[r, c]
        x = pooled_series(series, e["kind"], c, n_frames)
        I = periodogram(x).sum(axis=0)
        ax.loglog(lam[1:], I[1:], color="0.6", lw=0.5)
        f = e.get("fit")
        if f is not None:
            j = band_indices(n_frames, dt, e["band_per_ps"])
            model = (float(np.sum(f["variance"])) * expected_periodogram(n_frames, dt, f["omega_per_ps"],
                                                                         f["damping_per_ps"])[j]
                     + float(np.sum(f["floor"])))
            if f.get("background") is not None:
                model = model + np.asarray(f["background"])
            ax.loglog(lam[j], model, color="C3", lw=1)
        if e["reason"] is None:
            ax.axvline(e["omega_per_ps"], color="C3", ls="--", lw=0.6)
        else:
            ax.text(0.03, 0.03, "refused:\n" + e["reason"][:40], transform=ax.transAxes, fontsize=5, va="bottom")
        ax.set_title(f"{e['kind']} n = {e['n']}", fontsize=7)
        ax.tick_params(labelsize=5)
    for ax in axes[-1]:
        ax.set_xlabel("omega [rad/ps]", fontsize=6)
    # a fixed layout: tight_layout of 40-odd panels costs ~10 s
    fig.subplots_adjust(left=0.03, right=0.99, bottom=0.08, top=0.95, wspace=0.35, hspace=0.45)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def dispersion_figure(table: dict, path):
    """omega (with its error) against k for each kind; refused modes are left out."""
    plt = _plt()
    fig, axes = plt.subplots(1, len(KINDS), figsize=(4 * len(KINDS), 3.2), squeeze=False)
    for ax, kind in zip(axes[0], KINDS):
        ok = [e for e in table["modes"] if e["kind"] == kind and e["reason"] is None]
        if ok:
            ax.errorbar([e["k_per_A"] for e in ok], [e["omega_per_ps"] for e in ok],
                        yerr=[e["omega_err_per_ps"] or 0.0 for e in ok], fmt="o", ms=3, capsize=2)
        ax.set_xlabel("k [1/A]")
        ax.set_ylabel("omega [rad/ps]")
        ax.set_title(f"{kind} ({len(ok)} modes measured)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
