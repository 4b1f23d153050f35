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


class _Absent:
    """The value of a record's field whose key the JSON object does not hold (null is None)."""
    _instance = None

    def __new__(cls):
        if cls._instance is None:
            cls._instance = super().__new__(cls)
        return cls._instance

    def __repr__(self) -> str:
        return "ABSENT"

    def __bool__(self) -> bool:
        return False


ABSENT = _Absent()


def read_json(path):
    """The JSON value in PATH."""
    return json.loads(Path(path).read_text())


class JsonRecord:
    """A dataclass that is one JSON object of a result file: its fields by key name, each
    ABSENT when the object lacks the key; the keys it does not model kept in `extra`; and the
    keys' order as read, so that `to_json(from_json(d))` is d and the file written back is
    the file read, byte for byte. NESTED maps a field to the JsonRecord class of its value
    (a record, or a list of records).

    A subclass is a @dataclass whose fields after the first few have defaults (ABSENT), and
    which ends with the two bookkeeping fields `extra: dict` and `order: tuple` (a record
    made in code has order () and is written in its fields' order)."""
    NESTED: dict = {}
    extra: dict         # declared again by each subclass (a dataclass field there)
    order: tuple

    @classmethod
    def _keys(cls) -> list[str]:
        from dataclasses import fields
        return [f.name for f in fields(cls) if f.name not in ("extra", "order")]  # type: ignore[arg-type]

    @classmethod
    def from_json(cls, d: dict):
        keys = cls._keys()
        kw: dict = {}
        for k in keys:
            if k in d:
                v = d[k]
                sub = cls.NESTED.get(k)
                if sub is not None and v is not None:
                    v = [sub.from_json(x) for x in v] if isinstance(v, list) else sub.from_json(v)
                kw[k] = v
        kw.update(extra={k: v for k, v in d.items() if k not in keys}, order=tuple(d))
        return cls(**kw)

    def to_json(self) -> dict:
        keys = self._keys()
        order = list(self.order)
        order += [k for k in keys if k not in self.order and getattr(self, k) is not ABSENT]
        order += [k for k in self.extra if k not in self.order]
        out = {}
        for k in order:
            v = getattr(self, k) if k in keys else self.extra[k]
            if v is ABSENT:
                continue
            if isinstance(v, JsonRecord):
                v = v.to_json()
            elif isinstance(v, list) and v and isinstance(v[0], JsonRecord):
                v = [x.to_json() for x in v]
            out[k] = v
        return out

    @classmethod
    def read(cls, path):
        """The record in the JSON file PATH."""
        return cls.from_json(read_json(path))

    def write(self, path) -> Path:
        """PATH as write_json writes it."""
        return write_json(path, self.to_json())
