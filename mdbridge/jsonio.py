"""Strict JSON for every result file dnarod writes (results.json, analysis.json,
build.json, the paper checks).

JSON (RFC 8259) has no NaN or Infinity. A non-finite number is written as null
("no value"), never as the bare tokens NaN/Infinity that Python's json emits by
default (other readers reject them) and never as a string (which a reader would
take for text). numpy scalars and arrays become plain numbers and lists.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np


def jsonable(o):
    """O with numpy types turned into Python ones and non-finite floats into None."""
    if isinstance(o, dict):
        return {str(k): jsonable(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [jsonable(v) for v in o]
    if isinstance(o, np.ndarray):
        return jsonable(o.tolist())
    if isinstance(o, (bool, np.bool_)):
        return bool(o)
    if isinstance(o, (np.floating, float)):
        return float(o) if math.isfinite(float(o)) else None
    if isinstance(o, np.integer):
        return int(o)
    if isinstance(o, Path):
        return str(o)
    return o


def dumps(o, indent: int = 1) -> str:
    """Strict JSON text of O (allow_nan=False: a NaN that slipped through is an error)."""
    return json.dumps(jsonable(o), indent=indent, allow_nan=False)


def write_json(path, o, indent: int = 1) -> Path:
    """Write O to PATH whole or not at all: the text goes to PATH.part first, which then
    replaces PATH (a reader never sees half a file)."""
    path = Path(path)
    tmp = path.with_name(path.name + ".part")
    tmp.write_text(dumps(o, indent) + "\n")
    tmp.replace(path)
    return path
