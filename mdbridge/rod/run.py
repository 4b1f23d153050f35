"""One rod run: a scene run through the compiled `rodcore` module, and its HDF5 file.

`run_scene(scene)` is the only place in Python that runs the rod solver; it maps
rodcore's errors once (bad scene -> InputError, bad numbers -> NumericalError, any
other solver error -> DnarodError, each prefixed by where the scene came from).
`RodRun` holds one run in solver units -- from `run_scene`, from rodcore.run's result
dict (`RodRun.from_result`) or from a `rodsim run` output file (`RodRun.read`) -- and
writes the same layout back (`RodRun.write`). The layout is docs/contracts.md, "Rod
output".

A scene as a dict (read, resolved, edited, written) is mdbridge/rod/scene.py.
"""
from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from dna_models.errors import DnarodError, InputError, NumericalError
from dna_models.units import Units
from mdbridge.geometry.compiled import rodcore_module
from mdbridge.geometry.trajectory import BasePairTrajectory

from .frames import bp_frames_from_rod, bp_lab_velocities, period_vector

FIELDS = ("gamma", "omega", "Gamma", "Omega")
HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"


def is_hdf5(path) -> bool:
    """True for an HDF5 file (its 8-byte signature): a rod output, not an MD structure."""
    p = Path(path)
    if not p.is_file():
        return False
    with open(p, "rb") as f:
        return f.read(8) == HDF5_SIGNATURE


def analytic():
    """rodcore.analytic: the paper's closed forms (dispersion, exact waves), in C++ only."""
    return rodcore_module().analytic


@dataclass
class RodRun:
    """One rod run in solver units (Sec 2.2). fields[name] (T, N, 3) for gamma, omega,
    Gamma, Omega (internal frame); energy (T); energy_parts[name] (T); centerline
    (T, N, 3) and directors (T, N, 3, 3) with directors[t, i, :, k] = d_k (laboratory
    frame). summary: the solver's run summary; attrs: every other attribute of the file
    (scales, resolved scene keys, complete). Arrays a scene did not ask for are None."""
    time: np.ndarray | None
    s: np.ndarray | None
    fields: dict = field(default_factory=dict)
    energy: np.ndarray | None = None
    energy_parts: dict = field(default_factory=dict)
    centerline: np.ndarray | None = None
    directors: np.ndarray | None = None
    summary: dict = field(default_factory=dict)
    attrs: dict = field(default_factory=dict)
    source: str = "rod"

    @property
    def L(self) -> float:
        """Fiducial length (periodic grid s_i = i L / N)."""
        self.require("s")
        assert self.s is not None
        return float(self.s[1] - self.s[0]) * len(self.s)

    @property
    def complete(self) -> bool:
        """False when the run stopped early (rodsim keeps the frames written so far)."""
        return bool(self.attrs.get("complete", 1))

    @property
    def ell_A(self) -> float:
        """The length scale the run was made with (recorded in the file), else dna_models'."""
        return float(self.attrs.get("ell_A", Units.paper().ell_A))

    def units(self) -> Units:
        """dna_models' Units with this file's recorded time and length scales (tau_ps, ell_A;
        the paper's when it records none): what turns this run into ps and A."""
        import dataclasses
        u = Units.paper()
        tau_s = float(self.attrs.get("tau_ps", u.tau_ps)) * 1e-12
        ell_m = float(self.attrs.get("ell_A", u.ell_A)) * 1e-10
        # tau = sqrt(I / C), ell = sqrt(I / rho): keep I, set C and rho
        return dataclasses.replace(u, C=u.I / tau_s ** 2, rho=u.I / ell_m ** 2)

    # -- constructors ------------------------------------------------------
    @classmethod
    def from_result(cls, d, source: str = "rod") -> "RodRun":
        """From rodcore.run's result dict (or any mapping with its keys)."""
        arr = (lambda k: None if d.get(k) is None else np.asarray(d[k]))
        attrs = dict(d.get("scales") or {})
        if d.get("scene") is not None:   # the resolved scene, as rodsim's section.key attributes
            attrs["scene"] = d["scene"]
            for section, table in tomllib.loads(d["scene"]).items():
                for k, v in table.items():
                    if isinstance(v, list):   # numbers only (rodsim records no list of names)
                        if all(isinstance(x, (int, float)) for x in v):
                            attrs[f"{section}.{k}"] = np.asarray(v, float)
                    else:
                        attrs[f"{section}.{k}"] = int(v) if isinstance(v, bool) else v
        return cls(time=np.asarray(d["time"]), s=np.asarray(d["s"]),
                   fields={k: np.asarray(v) for k, v in dict(d.get("fields") or {}).items()},
                   energy=arr("energy"),
                   energy_parts={k: np.asarray(v) for k, v in dict(d.get("energy_parts") or {}).items()},
                   centerline=arr("centerline"), directors=arr("directors"),
                   summary=dict(d.get("summary") or {}), attrs=attrs, source=source)

    @classmethod
    def read(cls, path) -> "RodRun":
        """A `rodsim run` output file (or one `write` made)."""
        import h5py
        path = Path(path)
        if not path.is_file():
            raise InputError(f"{path}: no such rod run (an HDF5 file written by `rodsim run SCENE.toml "
                             f"-o {path.name}`)")
        try:
            with h5py.File(path, "r") as f:
                group = (lambda g: {k: f[g][k][()] for k in f[g]} if g in f else {})
                opt = (lambda k: f[k][()] if k in f else None)
                summary, attrs = {}, {}
                for k, v in f.attrs.items():
                    v = v.decode() if isinstance(v, bytes) else v
                    if k.startswith("summary."):
                        summary[k[len("summary."):]] = v
                    else:
                        attrs[k] = v
                # a dataset the file lacks is None; require() names it when a use needs it
                return cls(time=opt("time"), s=opt("s"), fields=group("fields"),
                           energy=opt("energy"), energy_parts=group("energy_parts"),
                           centerline=opt("centerline"), directors=opt("directors"),
                           summary=summary, attrs=attrs, source=str(path))
        except OSError as e:
            raise InputError(f"{path}: cannot read as HDF5 ({e}); a rod run is the HDF5 file "
                             "`rodsim run SCENE.toml -o ROD.h5` writes (docs/contracts.md)") from None

    def write(self, path) -> None:
        """The same layout rodsim writes (datasets and attributes)."""
        import h5py
        with h5py.File(path, "w") as f:
            f["time"] = np.asarray(self.time, float)
            f["s"] = np.asarray(self.s, float)
            for name, v in self.fields.items():
                f[f"fields/{name}"] = np.asarray(v, float)
            for name, v in self.energy_parts.items():
                f[f"energy_parts/{name}"] = np.asarray(v, float)
            for name in ("energy", "centerline", "directors"):
                v = getattr(self, name)
                if v is not None:
                    f[name] = np.asarray(v, float)
            for k, v in self.attrs.items():
                f.attrs[k] = v
            for k, v in self.summary.items():
                f.attrs[f"summary.{k}"] = v

    # -- use -----------------------------------------------------------------
    def require(self, *names: str) -> None:
        """InputError naming the file and each missing dataset ('fields/Gamma', 'centerline', ...)."""
        def have(n):
            if n.startswith("fields/"):
                return n[len("fields/"):] in self.fields
            return getattr(self, n, None) is not None
        missing = [n for n in names if not have(n)]
        if missing:
            raise InputError(f"{self.source}: " + ", ".join(f"dataset '{n}' missing" for n in missing)
                             + " (a rod output file has 'time' and 's', and the fields the scene's "
                               "output.fields asks for: 'internal', 'centerline', 'directors'; "
                               "docs/contracts.md)")

    def bp_frames(self, n_bp: int):
        """Base-pair frames (R (T, n_bp, 3, 3), origins (T, n_bp, 3) [A]) at s_i = i L / n_bp
        (mdbridge.rod.frames.bp_frames_from_rod)."""
        self.require("centerline", "directors", "time")
        return bp_frames_from_rod(self.centerline, self.directors, n_bp, self.ell_A)

    def bp_lab_velocities(self, n_bp: int, frame: int = 0):
        """(v, w) (n_bp, 3) at output frame FRAME: the base pairs' cross-section velocity
        and angular velocity in the laboratory frame, solver units
        (mdbridge.rod.frames.bp_lab_velocities)."""
        self.require("directors", "fields/gamma", "fields/omega")
        assert self.directors is not None
        return bp_lab_velocities(self.directors[frame], self.fields["gamma"][frame],
                                 self.fields["omega"][frame], n_bp)

    def trajectory(self, n_bp: int, units: Units | None = None) -> BasePairTrajectory:
        """The run's base pairs at s_i = i L / n_bp as a BasePairTrajectory, in A and ps
        (what `BasePairTrajectory.from_rod` returns).

        The period vector is `period()`.
        """
        u = units or Units.paper()
        self.require("time", "s", "centerline", "directors", "fields/Gamma")
        R, origins = bp_frames_from_rod(self.centerline, self.directors, n_bp, u.ell_A)
        return BasePairTrajectory(u.time_to_ps(np.asarray(self.time, float)), origins, R,
                                  u.length_to_A(self.period()), self.source,
                                  {"kind": "rod", "L": self.L, "N": len(np.asarray(self.s)), "n_bp": n_bp})

    def period(self) -> np.ndarray:
        """The period vector r(L) - r(0) of every frame (T, 3) [l]: P = int_0^L T(s) Gamma(s) ds
        (Eq 1: dr/ds = T Gamma) by the periodic trapezoid rule, spectrally accurate for a
        smooth periodic rod; about 0 for a rod closed into a ring (mdbridge.rod.frames.period_vector)."""
        self.require("s", "directors", "fields/Gamma")
        s = np.asarray(self.s, float)
        return period_vector(self.directors, self.fields["Gamma"], s[1] - s[0])

    def until(self, t_end: float) -> "RodRun":
        """The frames with time <= t_end (solver units), the same run otherwise."""
        self.require("time")
        assert self.time is not None
        keep = np.asarray(self.time) <= t_end * (1 + 1e-12) + 1e-300
        cut = (lambda a: None if a is None else np.asarray(a)[keep])
        return RodRun(self.time[keep], self.s, {k: v[keep] for k, v in self.fields.items()},
                      cut(self.energy), {k: v[keep] for k, v in self.energy_parts.items()},
                      cut(self.centerline), cut(self.directors), dict(self.summary),
                      dict(self.attrs), self.source)


def run_scene(scene, *, source=None, initial=None, set=(), output=None, progress=None) -> RodRun:
    """Run SCENE (a dict shaped like the TOML file, TOML text, or a path to a .toml file;
    docs/scenes.md) through rodcore.run. initial: optional dict of (N, 3) arrays
    replacing the [initial] section; set: "section.key=value" overrides; output: also
    write the HDF5 file rodsim would write. source names the scene in error messages.
    progress, if given, is called as progress(t, t_end) (solver time) at every output
    frame: the run then goes through rodcore.Simulation with an observer, and its frames
    are read back from the HDF5 file it writes (the same file rodsim writes)."""
    rodcore = rodcore_module()
    if source is None:
        source = str(scene) if isinstance(scene, Path) else "scene"
    arg = str(scene) if isinstance(scene, Path) else scene
    kwargs = {k: v for k, v in (("initial", initial), ("set", list(set)),
                                ("output", None if output is None else str(output))) if v}
    try:
        if progress is None:
            return RodRun.from_result(rodcore.run(arg, **kwargs), source=source)
        import tempfile
        sim = rodcore.Simulation(arg, **{k: v for k, v in kwargs.items() if k != "output"})
        t_end = float(tomllib.loads(sim.scene)["output"]["t_end"])
        sim.add_observer(lambda frame: progress(float(frame["t"]), t_end))
        with tempfile.TemporaryDirectory(prefix="dnarod-rod-") as tmp:
            path = Path(output) if output is not None else Path(tmp) / "rod.h5"
            sim.add_output(str(path))
            sim.run()
            run = RodRun.read(path)
        run.source = source
        return run
    except FloatingPointError as e:   # rodcore.NumericalError
        raise NumericalError(f"{source}: {e}") from None
    except ValueError as e:           # rodcore.InputError
        raise InputError(f"{source}: {e}") from None
    except RuntimeError as e:         # any other rodcore.Error
        raise DnarodError(f"{source}: rod run failed: {e}") from None
