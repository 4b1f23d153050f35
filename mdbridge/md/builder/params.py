"""Reading base-pair-step parameters for the builder.

Two formats:
* CSV with header `step,shift,slide,rise,tilt,roll,twist` (A, degrees), one
  row per step, steps numbered from 1 along strand I; the output of
  `dnarod helical-params` (`frame,step,shift,...`) is accepted too, one frame
  chosen by `frame`.
* 3DNA's `.par` (what `analyze` writes and `rebuild` reads): line 1 the number
  of base pairs, line 2 a flag, a header, then per base pair the pair
  ("C-G"), six base-pair parameters (shear, stretch, stagger, buckle,
  propeller, opening) and six step parameters to the previous pair (shift,
  slide, rise, tilt, roll, twist; all zero on the first line).
"""
from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dna_models.errors import InputError

STEP_COLUMNS = ("shift", "slide", "rise", "tilt", "roll", "twist")


@dataclass(frozen=True)
class ParFile:
    sequence: str            # strand I, 5'->3'
    base_pair_params: np.ndarray  # (n, 6) shear, stretch, stagger, buckle, propeller, opening
    steps: np.ndarray        # (n - 1, 6) shift, slide, rise, tilt, roll, twist


def read_3dna_par(path) -> ParFile:
    path = Path(path)
    try:
        lines = path.read_text().splitlines()
    except OSError as e:
        raise InputError(f"{path}: cannot read 3DNA parameter file ({e.strerror})") from e
    try:
        n = int(lines[0].split()[0])
    except (IndexError, ValueError):
        raise InputError(f"{path}:1: expected the number of base pairs, got {lines[:1]!r}")
    rows = [ln for ln in lines[3:] if ln.strip() and not ln.lstrip().startswith("#")]
    if len(rows) != n:
        raise InputError(f"{path}: line 1 announces {n} base pairs but {len(rows)} parameter "
                         "lines follow")
    seq, values = [], []
    for k, ln in enumerate(rows):
        parts = ln.split()
        try:
            values.append([float(v) for v in parts[1:13]])
        except ValueError:
            raise InputError(f"{path}: base pair {k + 1}: expected a pair like C-G and 12 numbers, "
                             f"got {ln.strip()!r}")
        if len(values[-1]) != 12:
            raise InputError(f"{path}: base pair {k + 1}: expected 12 numbers, got {len(parts) - 1}")
        seq.append(parts[0][0].upper())
    v = np.array(values)
    return ParFile(sequence="".join(seq), base_pair_params=v[:, :6], steps=v[1:, 6:])


def read_steps_csv(path, frame: int | None = None) -> np.ndarray:
    """(n_steps, 6) step parameters from a CSV file (see module doc), in step order."""
    path = Path(path)
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
            header = rows[0].keys() if rows else []
    except OSError as e:
        raise InputError(f"{path}: cannot read step-parameter CSV ({e.strerror})") from e
    missing = [c for c in ("step",) + STEP_COLUMNS if c not in header]
    if not rows or missing:
        raise InputError(f"{path}: need a header with step,{','.join(STEP_COLUMNS)} "
                         f"(optionally frame first) and one row per step; missing {missing}")
    if "frame" in header:
        frames = sorted({int(r["frame"]) for r in rows})
        if frame is None and len(frames) > 1:
            raise InputError(f"{path}: holds frames {frames[0]}..{frames[-1]}; choose one "
                             "(--frame)")
        pick = frames[0] if frame is None else frame
        if pick not in frames:
            raise InputError(f"{path}: frame {pick} not present (frames {frames[0]}..{frames[-1]})")
        rows = [r for r in rows if int(r["frame"]) == pick]
    try:
        rows.sort(key=lambda r: int(r["step"]))
        steps = [int(r["step"]) for r in rows]
        values = np.array([[float(r[c]) for c in STEP_COLUMNS] for r in rows])
    except ValueError as e:
        raise InputError(f"{path}: non-numeric value ({e})") from e
    if steps != list(range(1, len(steps) + 1)):
        raise InputError(f"{path}: steps must be numbered 1..{len(steps)} without gaps or repeats")
    if not np.all(np.isfinite(values)):
        raise InputError(f"{path}: NaN/Inf in the step parameters")
    return values
