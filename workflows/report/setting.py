"""The setting of an MD number: what surrounded the duplex and what held it, read from the
build that made the run (its build.json), not from the configuration, so an adopted or
rebuilt folder is named as it is.

    full-charge vacuum
    held pairs, full-charge vacuum
    TIP3P water, 150 mM NaCl, T = 10 pN

Vacuum: the phosphates' charges (build.json "electrostatics": the paper's full charges or
neutral phosphates, mdbridge/md/gromacs/charges.py), the Watson-Crick pairs held or not
("pair_hold", mdbridge/md/gromacs/pair_hold.py) and a box set to the zero-tension length
("equilibration.axial_pressure"). Water ("solvent", mdbridge/md/gromacs/solvent.py): the water
model, the salt on top of the counterions, and the tension the barostat holds
("md_settings.axial_tension_pN") or a fixed box. A build.json older than these keys is the
full-charge vacuum build it was. The force field is stated beside the setting.
"""
from __future__ import annotations

import html
import json
from pathlib import Path

FULL_CHARGE = "paper"           # build.json "electrostatics" of the paper's full charges


def label(build: dict) -> str:
    """The setting of one build (build.json's content) in words."""
    held = ["held pairs"] if build.get("pair_hold") else []
    charges = build.get("electrostatics", FULL_CHARGE)
    water = build.get("solvent")
    if not water:
        box = [] if not (build.get("equilibration") or {}).get("axial_pressure") else ["box at zero tension"]
        medium = ("full-charge" if charges == FULL_CHARGE else charges.rstrip("s")) + " vacuum"
        return ", ".join(held + [medium] + box)
    salt = f"{water['cation'].title()}{water['anion'].title()}"
    ions = (f"{float(water['salt_mM']):g} mM {salt}" if float(water.get("salt_mM", 0)) > 0
            else f"no salt ({water['cation'].title()} counterions)")
    T = (build.get("md_settings") or {}).get("axial_tension_pN")
    hold = "fixed box" if T is None else f"T = {float(T):g} pN"
    extra = held + ([] if charges == FULL_CHARGE else [charges.replace("-", " ")])
    return ", ".join([f"{water['model'].upper()} water", ions, hold] + extra)


def collect(cfg: dict, out: Path) -> dict:
    """{run folder (md/...): {"setting", "forcefield"}} of the configuration's MD runs whose build
    is under OUT: every (A_v, seed), and the stretched boxes of the dispersion (workflows/Snakefile)."""
    folders = [f"md/Av{float(a):g}_seed{int(s)}" for a in cfg["A_v_A_per_ps"] for s in cfg["seeds"]]
    disp = cfg.get("dispersion") or {}
    if disp.get("enabled"):
        folders += [f"md/Av0_seed{int(s)}_box{float(f):g}" for s in cfg["seeds"] for f in disp.get("box_scales") or []]
    runs = {}
    for folder in folders:
        p = out / folder / "build.json"
        if p.is_file():
            b = json.loads(p.read_text())
            runs[folder] = {"setting": label(b), "forcefield": b.get("forcefield", "charmm27")}
    return runs


def of_run(runs: dict, summary: dict) -> str:
    """The setting of the MD run whose analysis summary is SUMMARY (its A_v and seed), '' when
    its build is not there."""
    if summary.get("A_v_A_per_ps") is None or summary.get("seed") is None:
        return ""
    folder = f"md/Av{float(summary['A_v_A_per_ps']):g}_seed{int(summary['seed'])}"
    return (runs.get(folder) or {}).get("setting", "")


def html_section(runs: dict) -> str:
    """The page's statement of the settings: one sentence when every MD run shares one, else
    one line per setting with its runs."""
    if not runs:
        return ""
    groups: dict[tuple, list] = {}
    for folder, r in runs.items():
        groups.setdefault((r["setting"], r["forcefield"]), []).append(folder)
    lines = [f"<b>{html.escape(s)}</b> ({html.escape(ff)}): {html.escape(', '.join(f))}"
             for (s, ff), f in groups.items()]
    if len(lines) == 1:
        return f'<p id="md-setting">Every MD number on this page is of one setting, {lines[0]} (each build.json).</p>'
    return ('<p id="md-setting">The MD runs are of different settings (each build.json); every MD number is '
            'of its run\'s:</p><ul>' + "".join(f"<li>{x}</li>" for x in lines) + "</ul>")
