"""The figures and checks `dnarod paper-figures` can make, in order.

Each entry: name -> (what it reproduces, function(outdir, quick) writing <name>.png
and/or <name>.json into outdir)."""
from __future__ import annotations

from pathlib import Path


def _fig(module, name):
    def make(outdir: Path, quick: bool):
        import importlib
        return getattr(importlib.import_module(f"dnarod.paper.{module}"), name)(outdir, quick)
    return make


TARGETS = {
    "fig1": ("Fig 1: four dispersion branches, Eq 26 (Omega03 = 1)", _fig("fig_dispersion", "fig1")),
    "fig2": ("Fig 2: shear/bend energy ratio, Eq 27", _fig("fig_dispersion", "fig2")),
    "fig3": ("Fig 3: exact twisted wave snapshots (run)", _fig("fig_snapshots", "fig3")),
    "fig4": ("Fig 4: pure shear oscillation of a twisted rod (run vs Eqs 28-30)", _fig("fig_snapshots", "fig4")),
    "fig5": ("Fig 5: |Gamma1|/|Omega2| vs k, Eqs 40-43", _fig("fig_dispersion", "fig5")),
    "fig6": ("Fig 6: untwisted wave snapshots, omega_+, k = 2, eps = 0.5 (run)", _fig("fig_snapshots", "fig6")),
    "fig7": ("Fig 7: Gamma3/|Gamma| at k = 8, equal energy (runs)", _fig("sec52", "fig7")),
    "dispersion_check": ("measured frequencies of small-amplitude runs vs Eqs 26/39",
                         _fig("check_dispersion", "check")),
    "sec41_displacement": ("Sec 4.1: maximum centerline displacement formula", _fig("sec52", "max_displacement")),
    "sec52_energy": ("Sec 5.2: energy components, run vs Eqs 40-45", _fig("sec52", "energy_components")),
    "sec52_harmonic": ("Sec 4.1/5.2: second-harmonic extension wave vs Eq 45", _fig("sec52", "second_harmonic")),
    "validation": ("Sec 5.1: RK4 order, energy and director-norm conservation (exact wave)",
                   _fig("validation", "check")),
    "rings": ("Sec 5.1: ring tests vs closed forms and Eq 46", _fig("rings", "check")),
    "wavespeed": ("Sec 6: rod wave speed of the 158-bp scene", _fig("wavespeed", "check")),
}
FIGURES = [k for k in TARGETS if k.startswith("fig")]
