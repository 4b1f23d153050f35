"""What `dnarod build-md` prints at the end: each number of build.json with its meaning
and its limit, and the one check of the finished build that has a hard limit.

Limits:
- O3'-P links as built: 1.5-1.8 A (mdbridge/md/builder/backbone.py makes them so and
  refuses a build where it cannot). In conf.gro after an equilibration at T the bonds
  vibrate: about sqrt(kT / k_b) = 0.03 A rms at 300 K (CHARMM27 O3'-P, k_b = 225936
  kJ/mol/nm^2; the build's force field from mdbridge/md/forcefields.py), so no hard
  limit there.
- Base-pair frames of conf.gro against the rod's t = 0 frames: without an equilibration
  they differ only by the builder's placement (0.03 A / 0.3 deg, docs/builder.md) and
  the restrained minimisation (base heavy atoms held; about 0.01 A / 0.3 deg on the
  158-bp build): FRAMES_LIMIT, beyond which the build is refused. After an
  equilibration they differ by the thermal motion of the stage, which is the point of
  it: reported, no limit.
"""
from __future__ import annotations

import numpy as np

from dna_models.errors import DnarodError
from dna_models.units import BOLTZMANN_KJ_PER_MOL_K

from mdbridge.md.builder.backbone import LINK_RANGE_A
from mdbridge.md.forcefields import forcefield
from mdbridge.md.gromacs import defaults

FRAMES_LIMIT = {"max_origin_A": 0.1, "max_angle_deg": 1.0}


def _solvent_line(w: dict, md: dict) -> str:
    """In water: what surrounds the DNA and the checks of solvent_checks.py."""
    c = w["checks"]
    tension = ("fixed box" if md.get("axial_tension_pN") is None else
               f"axial tension {md['axial_tension_pN']:g} pN (semi-isotropic C-rescale)")
    return (f"in water: {w['n_water']} {w['model']}, {w['ions']['n_cation']} {w['cation']} + {w['ions']['n_anion']} "
            f"{w['anion']} ({c['ion_counts']['salt_realised_mM']:.0f} mM salt in {c['ion_counts']['water_volume_nm3']:.0f}"
            f" nm^3 of water), {w['n_atoms']} atoms, total charge {c['total_charge']['total_charge_e']:+.3f} e, "
            f"{w['n_water_removed_inside_duplex']} waters removed from the duplex, none left within 2.5 A of a base "
            f"ring; the DNA's topology is the vacuum build's, its atoms first; PME, {tension}")


def summary_lines(info: dict, built_links_A, temperature_K: float) -> list[str]:
    """The lines of build-md's summary from build.json's content (INFO) and the O3'-P
    lengths of the duplex as built (backbone.check_structure_links); a DnarodError when
    the frames of a build without equilibration differ from the rod's beyond FRAMES_LIMIT."""
    lines = []
    n_terms = sum(r["junction_total"] for r in info["junctions"])
    lines.append(f"{info['n_atoms']} atoms, charge {info['total_charge_e']:+g} e; {n_terms} junction terms "
                 "verified (each strand's junction carries exactly an interior step's bonded terms)")
    if info.get("solvent"):
        lines.append(_solvent_line(info["solvent"], info["md_settings"]))
    d = np.asarray(built_links_A, dtype=float)
    lo, hi = LINK_RANGE_A
    js = info["junction_O3P_t0_A"]
    moved = info.get("minimization") or info.get("equilibration")
    junctions = ", ".join(f"{s} {v['junction']:.2f}" for s, v in js.items())
    text = f"O3'-P links as built {d.min():.2f}-{d.max():.2f} A (limits {lo}-{hi} A; covalent 1.60 A)"
    if moved:
        gro = [x for v in js.values() for x in (v["interior_min"], v["interior_max"], v["junction"])]
        text += f"; in conf.gro {min(gro):.2f}-{max(gro):.2f} A, junctions {junctions} A"
        if info.get("equilibration") and temperature_K > 0:
            k_b = forcefield(info.get("forcefield", defaults.FORCEFIELD)).o3_p.k_kJ_mol_nm2
            sigma = np.sqrt(BOLTZMANN_KJ_PER_MOL_K * temperature_K / k_b) * 10.0
            text += f" (bonds vibrate by {sigma:.2f} A rms at {temperature_K:g} K)"
    else:
        text += f"; junctions {junctions} A"
    lines.append(text)

    fr = info["frames_t0_vs_rod"]
    what = (f"base-pair frames of conf.gro vs the rod's t = 0 frames: at most {fr['max_origin_A']:.3f} A / "
            f"{fr['max_angle_deg']:.2f} deg")
    if info.get("equilibration"):
        q = info["equilibration"]
        lines.append(f"{what} (rms {fr['rms_origin_A']:.2f} A / {fr['rms_angle_deg']:.1f} deg): the thermal "
                     f"motion of the {q['ps']:g}-ps equilibration, the state the rod's velocities are added "
                     "to (no limit)")
    else:
        cause = "the builder's placement" + (" and the restrained minimisation" if info.get("minimization") else "")
        limit = f"{FRAMES_LIMIT['max_origin_A']} A / {FRAMES_LIMIT['max_angle_deg']} deg"
        if any(fr[k] > v for k, v in FRAMES_LIMIT.items()):
            raise DnarodError(f"{what}, beyond the limit {limit} of {cause}: conf.gro is not the rod's "
                              "t = 0 shape (build.json: frames_t0_vs_rod)")
        lines.append(f"{what} (limit {limit}: {cause})")

    if info.get("minimization"):
        m = info["minimization"]
        steps = f" in {m['steps']} steps" if m.get("steps") else ""
        lines.append(("minimisation converged" + steps + " (Fmax < 500 kJ/mol/nm)" if m.get("converged")
                      else "minimisation NOT converged (Fmax above 500 kJ/mol/nm: see build.json "
                           "closest_nonbonded_contact)")
                     + f"; base-pair frames moved {m['frames_moved']['max_origin_A']:.3f} A / "
                       f"{m['frames_moved']['max_angle_deg']:.2f} deg (base heavy atoms held)")
    if info.get("equilibration"):
        q = info["equilibration"]
        zt = q.get("axial_pressure")
        T_mean = q["temperature_K"]["mean_second_half"]
        lines.append(f"equilibrated {q['ps']:g} ps at {temperature_K:g} K: T {T_mean:.1f} K over the second half;"
                     " stationary (T and E_pot: the 3rd- and 4th-quarter means within 2 "
                     "standard errors): " + ("yes" if q["stationary"] else "NO, use a longer --equilibrate-ps")
                     + (f"; zero-tension length {zt['zero_tension_length_nm']:.3f} +- "
                        f"{zt['zero_tension_length_se_nm']:.3f} nm (built {zt['box_length_start_nm']:.3f})"
                        if zt else ""))
    return lines
