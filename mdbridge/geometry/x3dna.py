"""Readers for 3DNA v2.3 output files, to compare with 3DNA and to reuse its
results (bp_step.par, ref_frames.dat, the .out report). Lu & Olson 2003 NAR
31:5108; 2008 Nat Protoc 3:1213."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from dna_models.errors import InputError


def read_bp_step_par(path):
    """3DNA `bp_step.par`: (labels, bp (n, 6), steps (n - 1, 6)).

    bp: shear, stretch, stagger [A], buckle, propeller, opening [deg] per pair;
    steps: shift, slide, rise [A], tilt, roll, twist [deg] (the first row of the
    file, all zeros, is dropped)."""
    rows, labels = [], []
    for ln in Path(path).read_text().splitlines()[3:]:
        s = ln.split()
        if len(s) == 13:
            labels.append(s[0])
            rows.append([float(x) for x in s[1:]])
    if not rows:
        raise InputError(f"{path}: no parameter rows found (not a 3DNA bp_step.par?)")
    a = np.array(rows)
    return labels, a[:, :6], a[1:, 6:]


def read_ref_frames(path):
    """3DNA `ref_frames.dat`: (origins (n, 3), R (n, 3, 3) with axes as columns)."""
    vals = []
    for ln in Path(path).read_text().splitlines():
        if ln.startswith("...") or "base-pairs" in ln:
            continue
        s = ln.split("#")[0].split()
        if len(s) == 3:
            vals.append([float(x) for x in s])
    a = np.array(vals).reshape(-1, 4, 3)
    return a[:, 0, :], np.swapaxes(a[:, 1:, :], -1, -2)


def read_out_table(path, title):
    """A parameter table of a 3DNA `.out` report, e.g. title "Local base-pair step
    parameters" or "Local base-pair parameters": (labels, values (n, 6)).
    Rows printed as '----' (undefined) become NaN."""
    lines = Path(path).read_text().splitlines()
    try:
        k = next(i for i, ln in enumerate(lines) if ln.strip() == title)
    except StopIteration:
        raise InputError(f"{path}: no table {title!r}") from None
    labels, rows = [], []
    for ln in lines[k + 2:]:
        s = ln.split()
        if not s or s[0].startswith("~") or s[0] in ("ave.", "s.d.") or s[0].startswith("*"):
            break
        labels.append(s[1])
        rows.append([float("nan") if "---" in x else float(x) for x in s[2:8]])
    return labels, np.array(rows)
