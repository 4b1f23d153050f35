"""The per-step DNA file (`format = "dnarod-steps/1"`, HDF5, DNA units).

One file carries a DNA's shape and material per base-pair step and its mass
and inertia per base pair (RULES of the project, shared with the
coarse-graining code):

    sequence      str            strand I, 5'->3', n_bp letters A/C/G/T
    closed        bool           periodic, ligated: n_steps = n_bp, the last step
                                 joins base pair n_bp to base pair 1
    step_params   (n_steps, 6)   shift, slide, rise [A], tilt, roll, twist [deg] (3DNA)
    stiffness     (n_steps, 6, 6) same order; kT/A^2, kT/(A deg), kT/deg^2;
                                 step energy 1/2 dp^T F dp [kT], symmetric positive definite
    temperature_K float          the kT of `stiffness`
    mass          (n_bp,)        amu
    inertia       (n_bp, 3, 3)   amu A^2, about the base-pair origin, base-pair axes, SPD
    source        str            citation or provenance
    step_params_err, stiffness_err   optional, same shapes (standard errors)

`read_steps` validates everything and names the file and dataset in its errors.
"""
from __future__ import annotations

from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from dna_models.sequence import ALPHABET

FORMAT = "dnarod-steps/1"
_SYM_RTOL = 1e-9


@dataclass
class StepMaterial:
    sequence: str
    closed: bool
    step_params: np.ndarray
    stiffness: np.ndarray
    temperature_K: float
    mass: np.ndarray
    inertia: np.ndarray
    source: str
    step_params_err: np.ndarray | None = field(default=None)
    stiffness_err: np.ndarray | None = field(default=None)

    @property
    def n_bp(self) -> int:
        return len(self.sequence)

    @property
    def n_steps(self) -> int:
        return self.n_bp if self.closed else self.n_bp - 1

    def validate(self, where: str = "StepMaterial") -> "StepMaterial":
        """Check shapes, numbers and letters; return self with float arrays. InputError otherwise."""
        _validate(self, where)
        return self


def _spd_check(A, where, name, sym_tol=_SYM_RTOL):
    scale = np.max(np.abs(A), axis=(-1, -2))
    asym = np.max(np.abs(A - np.swapaxes(A, -1, -2)), axis=(-1, -2))
    bad = np.nonzero(asym > sym_tol * np.maximum(scale, 1e-300))[0]
    if len(bad):
        raise InputError(f"{where}: dataset '{name}' is not symmetric at index {bad[0]} "
                         f"(max |A - A^T| = {asym[bad[0]]:.3g}); allowed: symmetric positive definite matrices")
    ev = np.linalg.eigvalsh(0.5 * (A + np.swapaxes(A, -1, -2)))[..., 0]
    bad = np.nonzero(ev <= 0)[0]
    if len(bad):
        raise InputError(f"{where}: dataset '{name}' is not positive definite at index {bad[0]} "
                         f"(smallest eigenvalue {ev[bad[0]]:.3g}); allowed: symmetric positive definite matrices")


def _array(where, name, value, shape):
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{where}: dataset '{name}' is not numeric") from None
    if a.shape != shape:
        raise InputError(f"{where}: dataset '{name}' has shape {' x '.join(map(str, a.shape)) or 'scalar'}, "
                         f"expected {' x '.join(map(str, shape))}")
    bad = np.argwhere(~np.isfinite(a))
    if len(bad):
        raise InputError(f"{where}: dataset '{name}' has a non-finite value ({a[tuple(bad[0])]}) at index "
                         f"{list(map(int, bad[0]))}")
    return a


def _validate(sm: StepMaterial, where: str):
    seq = sm.sequence
    if not isinstance(seq, str) or not seq:
        raise InputError(f"{where}: dataset 'sequence' must be a non-empty string of A, C, G, T")
    for k, ch in enumerate(seq, start=1):
        if ch not in ALPHABET:
            raise InputError(f"{where}: dataset 'sequence': letter {ch!r} at position {k} is not a DNA base "
                             "(allowed: A, C, G, T, upper case)")
    sm.closed = bool(sm.closed)
    n_bp, n = sm.n_bp, sm.n_steps
    if n < 1:
        raise InputError(f"{where}: an open duplex needs at least 2 base pairs (dataset 'sequence' has {n_bp})")
    sm.step_params = _array(where, "step_params", sm.step_params, (n, 6))
    sm.stiffness = _array(where, "stiffness", sm.stiffness, (n, 6, 6))
    _spd_check(sm.stiffness, where, "stiffness")
    T = float(_array(where, "temperature_K", sm.temperature_K, ()))
    if not T > 0:
        raise InputError(f"{where}: dataset 'temperature_K' = {T}; allowed: a temperature > 0 K")
    sm.temperature_K = T
    sm.mass = _array(where, "mass", sm.mass, (n_bp,))
    if np.any(sm.mass <= 0):
        i = int(np.argmin(sm.mass))
        raise InputError(f"{where}: dataset 'mass' = {sm.mass[i]} at index {i}; allowed: > 0 amu")
    sm.inertia = _array(where, "inertia", sm.inertia, (n_bp, 3, 3))
    _spd_check(sm.inertia, where, "inertia")
    if not isinstance(sm.source, str):
        raise InputError(f"{where}: dataset 'source' must be a string (citation or provenance)")
    if sm.step_params_err is not None:
        sm.step_params_err = _array(where, "step_params_err", sm.step_params_err, (n, 6))
    if sm.stiffness_err is not None:
        sm.stiffness_err = _array(where, "stiffness_err", sm.stiffness_err, (n, 6, 6))


def write_steps(path, sm: StepMaterial) -> Path:
    """Write `sm` (validated first) to the HDF5 file `path`."""
    import h5py
    sm.validate(f"write_steps({path})")
    path = Path(path)
    with h5py.File(path, "w") as f:
        f.attrs["format"] = FORMAT
        f.attrs["units"] = ("step_params: A (shift, slide, rise), deg (tilt, roll, twist); stiffness: "
                            "kT/A^2, kT/(A deg), kT/deg^2 at temperature_K; mass: amu; inertia: amu A^2")
        f["sequence"] = sm.sequence
        f["closed"] = np.bool_(sm.closed)
        f["temperature_K"] = float(sm.temperature_K)
        f["source"] = sm.source
        for name in ("step_params", "stiffness", "mass", "inertia", "step_params_err", "stiffness_err"):
            a = getattr(sm, name)
            if a is not None:
                f[name] = np.asarray(a, dtype=float)
    return path


def read_steps(path) -> StepMaterial:
    """Read and validate a per-step DNA file; InputError naming the file and dataset otherwise."""
    import h5py
    where = f"step file '{path}'"
    try:
        f = h5py.File(path, "r")
    except (OSError, FileNotFoundError) as e:
        raise InputError(f"{where}: cannot open as HDF5 ({e})") from None
    with f:
        fmt = f.attrs.get("format")
        if isinstance(fmt, bytes):
            fmt = fmt.decode()
        if fmt != FORMAT:
            raise InputError(f"{where}: attribute 'format' is {fmt!r}; allowed: {FORMAT!r}")
        vals: dict = {}
        for fl in fields(StepMaterial):
            name = fl.name
            if name not in f:
                if name.endswith("_err"):
                    vals[name] = None
                    continue
                raise InputError(f"{where}: dataset '{name}' missing (required: sequence, closed, step_params, "
                                 "stiffness, temperature_K, mass, inertia, source)")
            v = f[name][()]
            if isinstance(v, bytes):
                v = v.decode()
            vals[name] = v
    if not isinstance(vals["sequence"], str):
        raise InputError(f"{where}: dataset 'sequence' must be a string of A, C, G, T")
    c = np.asarray(vals["closed"])
    if c.shape != () or c.dtype.kind not in "bi":
        raise InputError(f"{where}: dataset 'closed' must be a scalar boolean")
    vals["closed"] = bool(c)
    if not isinstance(vals["source"], str):
        raise InputError(f"{where}: dataset 'source' must be a string")
    return StepMaterial(**vals).validate(where)
