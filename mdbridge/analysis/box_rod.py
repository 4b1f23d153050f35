"""The paper's rod at the MD's box (docs/dispersion.md, "The paper's rod at the box"): the
second row of the prediction, `paper_rod_box`.

`paper_rod` (dispersion_prediction.paper_material) has its rest length, Gamma3 = 1, at the box
length, so at the MD's tension T it stands stretched to Gamma3 = 1 + T / C3 (3.5 % at 38 pN):
a rod longer than the box it is compared with, and lighter per unit of its own length. The MD's
duplex fills the box. `paper_rod_box` is the paper's stiffness with
  * Gamma3 = 1 at the box length under the MD's tension: the intrinsic stretch Gamma0_3 =
    1 - T / C3, so that the tension's own strain brings it to 1 (the rod's reference length is
    the box, its mass per length the MD's at the box);
  * the MD's own mass per length rho and inertia per length I: from its atoms
    (`md_mass_inertia`: the builder's all-atom templates of the build's sequence,
    mdbridge.rod.material.parameter_sets.atomic_mass_inertia, over the box's rise; or a
    coarse-graining's measured rod rho_star and I_star).
The stiffness, twist and everything else stay the paper's, so the two rows differ by length and
mass alone: the systematics that the string-beam omega = (2 pi n / L) sqrt(T / mu) says move
the low bend modes (the rest length by ~T / (2 C3), the mass by sqrt(rho_paper / rho)).
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from dna_models.units import Units
from mdbridge.rod.linear import UniformMaterial


def md_mass_inertia(path, units: Units | None = None) -> dict:
    """{"rho_star", "I_star" (3, 3), "source"} of the MD's duplex in rod units, from `path`:
    the MD's build.json (its sequence and box: the builder's all-atom templates, mass and
    inertia per base pair over the box length / n_bp), or a coarse-graining's params.json (its
    measured rod rho_star and I_star)."""
    from mdbridge.rod.material.parameter_sets import atomic_mass_inertia
    u = units or Units.paper()
    p = Path(path)
    try:
        d = json.loads(p.read_text())
    except (OSError, ValueError) as e:
        raise InputError(f"{p}: not a JSON file ({e})") from None
    if isinstance(d.get("rod"), dict) and "rho_star" in d["rod"]:
        return {"rho_star": float(d["rod"]["rho_star"]), "I_star": np.asarray(d["rod"]["I_star"], float),
                "source": f"{p}: rod rho_star, I_star (the coarse-graining's, measured on the MD's atoms)"}
    if "sequence" in d and isinstance(d.get("box"), dict):
        seq = str(d["sequence"])
        box = d["box"]
        L = float(box.get("closure_length_A") or box["box_A"][int(box["axis"])])
        h = L / len(seq)
        m, inertia = atomic_mass_inertia(seq)
        return {"rho_star": float(u.mass_amu_per_length_A_to_rod(float(np.mean(m)), h)),
                "I_star": np.asarray(u.inertia_amu_A2_per_length_A_to_rod(np.mean(inertia, axis=0), h), float),
                "source": f"{p}: the builder's all-atom templates of its {len(seq)}-bp sequence over its box "
                          f"({L:g} A; mdbridge.rod.material.parameter_sets.atomic_mass_inertia)"}
    raise InputError(f"{p}: neither a build-md build.json (keys sequence, box) nor a coarse-graining's params.json "
                     "(rod.rho_star, rod.I_star)")


def paper_rod_box(paper: UniformMaterial, tension_pN: float, rho_star: float, I_star,
                  units: Units | None = None) -> UniformMaterial:
    """The paper's material `paper` (dispersion_prediction.paper_material) at Gamma3 = 1 under
    tension_pN, with mass rho_star and inertia I_star per length (module doc). Its stiffness
    must be diagonal in the stretch (no coupling of Gamma3 to the other strains), as the
    paper's is."""
    u = units or Units.paper()
    K = np.asarray(paper.K, float)
    if np.any(np.abs(np.delete(K[2], 2)) > 0):
        raise InputError("paper_rod_box: the material couples stretch to other strains; Gamma3 = 1 under tension "
                         "is set by Gamma0_3 = 1 - T / C3 only for an uncoupled stretch")
    T = tension_pN * 1e-12 / u.C
    G0 = np.array(paper.Gamma0, float)
    G0[2] = 1.0 - T / K[2, 2]
    return UniformMaterial(K=K, I=np.asarray(I_star, float), rho=float(rho_star), Gamma0=G0, Omega0=paper.Omega0)
