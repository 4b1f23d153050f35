"""The analyses' results as typed records: a mode and a mode table (`dnarod modes`,
modes.json), a wave result (the comparison's analysis.json of one run, WaveAnalysis.summary
with the workflow's additions) and a prediction (`dnarod dispersion`, prediction.json).

Each is a dataclass read from and written to its JSON object through mdbridge/jsonio.py
(`JsonRecord`): a key the object lacks is ABSENT, null is None, the keys a record does not
model stay in `extra`, and a file read and written back is the same file, byte for byte
(tests/python/test_results_typed.py holds every committed results file to it). The keys and
their meaning: docs/analysis.md ("Mode spectra") and docs/dispersion.md.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from mdbridge.jsonio import ABSENT, JsonRecord


def _extra() -> Any:
    return field(default_factory=dict, repr=False)


def _order() -> Any:
    return field(default=(), repr=False, compare=False)


@dataclass
class Mode(JsonRecord):
    """One Fourier mode of one kind (bend, twist, stretch): its frequency, damping and
    variance with errors, or the reason it is refused (the numbers then None); its regime
    (oscillating, overdamped, unresolved) and, for an overdamped mode, its relaxation time
    (docs/modes.md, "Overdamped modes"). Files written before the regimes lack those keys."""
    kind: str
    n: int
    k_per_A: Any = ABSENT
    omega_per_ps: Any = ABSENT
    omega_err_per_ps: Any = ABSENT
    omega0_per_ps: Any = ABSENT
    omega0_err_per_ps: Any = ABSENT
    damping_per_ps: Any = ABSENT
    damping_err_per_ps: Any = ABSENT
    Q: Any = ABSENT
    Q_err: Any = ABSENT
    variance: Any = ABSENT
    variance_err: Any = ABSENT
    variance_unit: Any = ABSENT
    oscillator_variance: Any = ABSENT
    oscillator_variance_err: Any = ABSENT
    periods_in_record: Any = ABSENT
    reason: Any = ABSENT
    n_series: Any = ABSENT
    record_ps: Any = ABSENT
    peak_to_background: Any = ABSENT
    common_background: Any = ABSENT
    band_per_ps: Any = ABSENT
    fit: Any = ABSENT
    undamped: Any = ABSENT
    halves: Any = ABSENT
    seeds: Any = ABSENT
    regime: Any = ABSENT
    relaxation_time_ps: Any = ABSENT
    relaxation_time_err_ps: Any = ABSENT
    relaxation: Any = ABSENT
    extra: dict = _extra()
    order: tuple = _order()

    @property
    def measured(self) -> bool:
        """A frequency, not a refusal."""
        return self.reason is None

    @property
    def overdamped(self) -> bool:
        """No frequency, and a relaxation time."""
        return self.regime == "overdamped"


@dataclass
class ModeTable(JsonRecord):
    """modes.json: every mode of the duplex, the drift check, the record and its realisations."""
    modes: list
    drift: Any = ABSENT
    record_ps: Any = ABSENT
    dt_ps: Any = ABSENT
    n_frames: Any = ABSENT
    length_A: Any = ABSENT
    n_bp: Any = ABSENT
    helical_repeat: Any = ABSENT
    realisations: Any = ABSENT
    command: Any = ABSENT
    inputs: Any = ABSENT
    discard_ps: Any = ABSENT
    until_ps: Any = ABSENT
    extra: dict = _extra()
    order: tuple = _order()
    NESTED = {"modes": Mode}

    def measured(self, kind: str | None = None) -> list[Mode]:
        """The modes with a frequency (of KIND if given)."""
        return [m for m in self.modes if m.measured and (kind is None or m.kind == kind)]

    def overdamped(self, kind: str | None = None) -> list[Mode]:
        """The modes with a relaxation time instead (of KIND if given)."""
        return [m for m in self.modes if m.overdamped and (kind is None or m.kind == kind)]


@dataclass
class WaveResult(JsonRecord):
    """One run's wave analysis (WaveAnalysis.summary and, in the comparison, the standing
    mode, the plane, the matched quantities and the run's record)."""
    source: Any = ABSENT
    n_frames: Any = ABSENT
    n_bp: Any = ABSENT
    t_start_ps: Any = ABSENT
    t_end_ps: Any = ABSENT
    length_A: Any = ABSENT
    axis_window_bp: Any = ABSENT
    axis_window_response: Any = ABSENT
    wave_speed_A_per_ps: Any = ABSENT
    wave_speed_err_A_per_ps: Any = ABSENT
    wave_fit: Any = ABSENT
    wave_speed_check_A_per_ps: Any = ABSENT
    wave_check: Any = ABSENT
    planarity: Any = ABSENT
    plane_angle_deg: Any = ABSENT
    max_abs_plane_angle_deg: Any = ABSENT
    in_plane_amplitude_A: Any = ABSENT
    kind: Any = ABSENT
    A_v_A_per_ps: Any = ABSENT
    A_A: Any = ABSENT
    dispersion: Any = ABSENT
    complete: Any = ABSENT
    standing_mode: Any = ABSENT
    wave_quantity: Any = ABSENT
    extra: dict = _extra()
    order: tuple = _order()


@dataclass
class Prediction(JsonRecord):
    """prediction.json: per MD mode the rods' predicted frequencies at the MD's tension, the
    refusals, and the MD's own tension and bend stiffness fitted from its lowest modes."""
    n_bp: Any = ABSENT
    turns: Any = ABSENT
    length_A: Any = ABSENT
    record_ps: Any = ABSENT
    temperature_K: Any = ABSENT
    tension: Any = ABSENT
    rows: Any = ABSENT
    predictions: Any = ABSENT
    paper_rod_box: Any = ABSENT          # where the box row's mass and inertia came from (box_rod.py)
    refused: Any = ABSENT
    cg_rod_reason: Any = ABSENT
    cg_notes: Any = ABSENT
    fit: Any = ABSENT
    definition: Any = ABSENT
    extra: dict = _extra()
    order: tuple = _order()

    def rows_of(self, kind: str) -> list[dict]:
        """The comparison rows of one kind of mode."""
        return [r for r in self.rows if r["kind"] == kind]
