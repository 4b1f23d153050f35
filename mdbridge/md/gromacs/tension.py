"""Axial tension of the periodic, ligated duplex from a GROMACS energy file, and a box
stretched along the helix axis (for measuring the tension at another length).

Tension, one formula per setting (`md_tension_pN`, the one home):
- vacuum: F(t) = -P_aa(t) A(t), P_aa the pressure-tensor component along the helix axis
  (box axis a, the axis of `build.json: box.axis`) and A the box cross-section normal to it,
  both per energy frame (so a run with the axis-only barostat is measured too). In vacuum
  P_aa holds the kinetic term of the atoms too, so F is the thermodynamic force -dA_free/dL
  of the periodic duplex at box length L (what the barostat of `equilibrate.py` brings to
  zero);
- in water (build.json "solvent" set): F(t) = (P_perp(t) - P_aa(t)) A(t), P_perp the mean of
  the two components across the axis: the water's own pressure acts on every face alike and
  only the excess stress along the axis is the duplex's (the vacuum formula would read the
  1 bar of the water as ~2.5 pN on a 25-nm^2 box).
F > 0 is tension (the duplex pulls the box faces together, a negative axial pressure), in
pN; 1 bar over 1 nm^2 is 0.1 pN. The barostat that holds a tension T (mdp.py
pressure_lines) targets the same formula: P_aa = P_perp - T / A (`ref_p_axis_bar`).
The error of its time mean is the blocking standard error (`mdbridge.stats.block_sem`).
Validated (vacuum) against the box's own zero-tension length and the coarse-grained stretch
modulus in docs/md.md ("Tension: validation on 21 bp")."""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from dna_models.units import BOLTZMANN as BOLTZMANN_J_PER_K
from mdbridge.stats import block_sem, sem_longest_blocks

from .energy import read_energies
from .gro import read_gro, write_gro

NM2_TO_A2 = 100.0
BAR_A2_TO_PN = 1e5 * 1e-20 * 1e12   # 1 bar x 1 A^2 in pN (= 1e-3)


PN_PER_NM2_IN_BAR = 10.0            # 1 pN / nm^2 = 1e-12 N / 1e-18 m^2 = 1e6 Pa = 10 bar


def md_tension_pN(P_axis_bar, area_A2, P_perp_bar=None) -> np.ndarray:
    """F = (P_perp - P_axis) A [pN] (P in bar, A in A^2); F > 0 is tension. P_perp None (the
    vacuum setting): F = -P_axis A. Arrays broadcast (per-frame areas too)."""
    P = np.asarray(P_axis_bar, float)
    excess = -P if P_perp_bar is None else np.asarray(P_perp_bar, float) - P
    return excess * np.asarray(area_A2, float) * BAR_A2_TO_PN


def ref_p_axis_bar(tension_pN: float, area_nm2: float, p_perp_bar: float = 1.0) -> float:
    """The barostat's reference pressure along the axis that holds TENSION_PN on a box of
    cross-section AREA_NM2 at P_PERP_BAR across: P_perp - T / A, in bar (10 bar per pN/nm^2)."""
    if not (np.isfinite(tension_pN) and area_nm2 > 0):
        raise InputError(f"axial tension {tension_pN} pN on a cross-section of {area_nm2} nm^2: need a finite "
                         "tension and an area > 0")
    return float(p_perp_bar - PN_PER_NM2_IN_BAR * tension_pN / area_nm2)


def solvated(build: dict) -> bool:
    """Whether a build (build.json's content) is in water: the tension's formula depends on it."""
    return bool(build.get("solvent"))


def tension_series(directory: Path, gmx: str, *, edr: str = "md.edr", axis: int | None = None,
                   box_from: str = "conf.gro") -> dict:
    """{"time": ps, "tension_pN": F(t), "length_nm": box length along the axis, "area_nm2",
    "axis"} from DIR/EDR (axis from DIR/build.json unless given). A fixed box writes no
    Box-* terms: its edges are then DIR/BOX_FROM's (the run's start)."""
    d = Path(directory)
    bj = d / "build.json"
    build = json.loads(bj.read_text()) if bj.is_file() else {}
    if axis is None:
        if not build:
            raise InputError(f"{bj}: missing; give the helix axis (0, 1, 2) instead")
        axis = int(build["box"]["axis"])
    if not (d / edr).is_file():
        raise InputError(f"{d / edr}: missing; the tension needs the run's energy file")
    e = read_energies(d, gmx, edr=edr)
    xyz = "XYZ"
    name = f"Pres-{xyz[axis] * 2}"
    if name not in e:
        raise InputError(f"{d / edr}: no {name} in the energy file "
                         f"(has {', '.join(k for k in e if k != 'time')})")
    if not all(f"Box-{c}" in e for c in xyz):      # fixed box: edges of the start
        if not (d / box_from).is_file():
            raise InputError(f"{d / edr}: no Box-X/Y/Z terms (fixed box) and no {d / box_from}")
        box = read_gro(d / box_from).box
        for k, c in enumerate(xyz):
            e[f"Box-{c}"] = np.full(len(e["time"]), float(box[k]))
    across = [k for k in range(3) if k != axis]
    area = e[f"Box-{xyz[across[0]]}"] * e[f"Box-{xyz[across[1]]}"]
    P = e[name]
    P_perp = None
    if solvated(build):
        lateral = [f"Pres-{xyz[k] * 2}" for k in across]
        missing = [n for n in lateral if n not in e]
        if missing:
            raise InputError(f"{d / edr}: no {', '.join(missing)} in the energy file (the tension in water needs "
                             "the pressure across the axis)")
        P_perp = 0.5 * (e[lateral[0]] + e[lateral[1]])
    F = md_tension_pN(P, area * NM2_TO_A2, P_perp)
    return {"time": e["time"], "tension_pN": F, "pressure_bar": P, "pressure_perp_bar": P_perp,
            "formula": "vacuum: F = -P_aa A" if P_perp is None else "water: F = (P_perp - P_aa) A",
            "length_nm": e[f"Box-{xyz[axis]}"], "area_nm2": area, "axis": axis}


def mean_with_error(t, y, *, discard_ps: float = 0.0) -> dict:
    """Time mean of y after discarding the first discard_ps, its standard error, and a
    stationarity check: the means of the two halves of the kept window differ by less than
    3 x the standard error of that difference (each half on its own).

    The error is the larger of `block_sem` (the first plateau of the blocking
    curve) and the error from the longest blocks that leave 8 (`sem_longest_blocks`). The
    MD tension needs the second: its instantaneous value is white noise of ~400 pN over a
    slow part of ~30 pN (10-ps means of the 21-bp duplex; conformational changes such as
    fraying), so the blocking curve is flat for short blocks (a false plateau, where
    block_sem stops) and rises again beyond ~1 ps (docs/md.md, "Tension: validation on 21 bp")."""
    t, y = np.asarray(t, float), np.asarray(y, float)
    keep = t >= t[0] + discard_ps
    t, y = t[keep], y[keep]
    b = block_sem(y)
    h = len(y) // 2

    def err(x):
        return max(block_sem(x)["sem"], sem_longest_blocks(x))

    e1, e2 = err(y[:h]), err(y[h:])
    diff = float(np.mean(y[h:]) - np.mean(y[:h]))
    se = float(np.hypot(e1, e2))
    long = sem_longest_blocks(y)
    return {"mean": b["mean"], "sem": max(b["sem"], long), "sem_first_plateau": b["sem"],
            "sem_plateau": b.get("plateau"), "sem_longest_blocks": long,
            "block_length_frames": b.get("block_length"), "naive_sem": b.get("naive_sem"),
            "n": b["n"], "window_ps": [float(t[0]), float(t[-1])],
            "sem_rule": "larger of the first blocking plateau and the longest blocks leaving 8",
            "halves": {"first": float(np.mean(y[:h])), "second": float(np.mean(y[h:])),
                       "difference": diff, "difference_se": se, "stationary": bool(abs(diff) < 3.0 * se)}}


def isotension_stretch_modulus(t, length_nm, temperature_K: float, *, discard_ps: float = 0.0) -> dict:
    """The stretch modulus of the whole periodic duplex from its box length L(t) in the
    isotension ensemble that a semi-isotropic barostat samples (build-md --axial-tension-pN):
    S = kT <L> / var L (pN), the q = 0 stretch stiffness, which no per-step analysis reaches.
    The barostat's time constant sets how fast L moves, not its distribution. Errors: the
    blocking errors of <L> and of the mean squared deviation (mean_with_error), propagated."""
    t, L = np.asarray(t, float), np.asarray(length_nm, float)
    keep = t >= t[0] + discard_ps
    mean = mean_with_error(t, L, discard_ps=discard_ps)
    dev2 = mean_with_error(t[keep], (L[keep] - L[keep].mean()) ** 2)
    kT_pN_nm = BOLTZMANN_J_PER_K * temperature_K * 1e21
    S = kT_pN_nm * mean["mean"] / dev2["mean"]
    err = S * float(np.hypot(dev2["sem"] / dev2["mean"], mean["sem"] / mean["mean"]))
    return {"S_pN": S, "S_err_pN": err, "length_nm": mean, "length_std_nm": float(np.sqrt(dev2["mean"])),
            "temperature_K": temperature_K, "rule": "S = kT <L> / var L over the frames after the discard"}


def force_extension(L0: dict, L1: dict, dT_pN: float, S0_pN: float, S0_err_pN: float) -> dict:
    """The length gained between two set tensions, <L>(T1) - <L>(T0), against the one the
    lower run's own stiffness predicts, <L>(T0) (T1 - T0) / S0 (L0, L1: mean_with_error of the
    box length); and the force-extension modulus <L>(T0) (T1 - T0) / dL that it implies. The
    barostat holds the same virial whatever the DNA does, so only this asks the DNA."""
    predicted = L0["mean"] * dT_pN / S0_pN
    measured = L1["mean"] - L0["mean"]
    err = float(np.hypot(L0["sem"], L1["sem"]))
    pred_err = predicted * S0_err_pN / S0_pN
    S_fe = L0["mean"] * dT_pN / measured if measured > 0 else None
    return {"delta_tension_pN": dT_pN, "delta_length_nm": measured, "delta_length_err_nm": err,
            "predicted_nm": predicted, "predicted_err_nm": pred_err,
            "S_force_extension_pN": S_fe,
            "S_force_extension_err_pN": None if S_fe is None else S_fe * err / measured,
            "consistent_2_sigma": bool(abs(measured - predicted) < 2.0 * float(np.hypot(err, pred_err))),
            "resolved_from_zero_2_sigma": bool(measured > 2.0 * err)}


def stretch_box(src: Path, dst: Path, factor: float, *, axis: int | None = None,
                conf: str = "conf.gro") -> dict:
    """Copy a build-md directory's inputs (conf.gro, topology, itp, md.mdp, build.json) to
    DST with conf.gro scaled affinely by `factor` along the helix axis (coordinates and box
    edge; velocities kept). Affine scaling keeps a periodic, ligated duplex closed: every
    minimum-image vector, across the boundary too, scales by the same factor."""
    src, dst = Path(src), Path(dst)
    if factor <= 0:
        raise InputError(f"stretch factor {factor}: must be > 0")
    bj = json.loads((src / "build.json").read_text())
    a = int(bj["box"]["axis"]) if axis is None else axis
    dst.mkdir(parents=True, exist_ok=True)
    for f in src.iterdir():
        if f.suffix == ".itp" or f.name in ("topol.top", "md.mdp", "build.json"):
            shutil.copy2(f, dst / f.name)
    g = read_gro(src / conf)
    g.x[:, a] *= factor
    g.box[a] *= factor
    write_gro(dst / "conf.gro", g)
    return {"axis": a, "factor": factor, "box_nm": g.box.tolist()}
