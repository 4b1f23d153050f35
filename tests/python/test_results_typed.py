"""The typed results (mdbridge/analysis/results.py) against the files they type: every
committed results file that is a mode table or a prediction is read through its record and
written back byte for byte; a wave result written by the analysis goes the same way; the
records' fields are the files' numbers. Controls: a changed number, a changed key order and
a lost key each change the file written."""
from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from mdbridge.analysis.results import Mode, ModeTable, Prediction, WaveResult
from mdbridge.jsonio import ABSENT, write_json

ROOT = Path(__file__).resolve().parents[2]


def kind_of(d) -> type | None:
    """The record type of a results file's object, by the keys that define it."""
    if not isinstance(d, dict):
        return None
    if {"modes", "realisations", "drift"} <= set(d):
        return ModeTable
    if {"rows", "predictions", "refused"} <= set(d):
        return Prediction
    if {"wave_speed_A_per_ps", "wave_fit", "planarity"} <= set(d):
        return WaveResult
    return None


COMMITTED = sorted((p, kind_of(json.loads(p.read_text()))) for p in (ROOT / "results").rglob("*.json"))
TYPED = [(p, k) for p, k in COMMITTED if k is not None]


def test_the_committed_results_hold_mode_tables_and_predictions():
    kinds = {k for _, k in TYPED}
    assert {ModeTable, Prediction} <= kinds and len(TYPED) >= 10, TYPED


@pytest.mark.parametrize("path, kind", TYPED, ids=[str(p.relative_to(ROOT)) for p, _ in TYPED])
def test_committed_file_reads_and_writes_back_identically(path, kind, tmp_path):
    rec = kind.read(path)
    assert not rec.extra, f"{path}: keys the record does not model: {sorted(rec.extra)}"
    out = rec.write(tmp_path / "back.json")
    assert out.read_bytes() == path.read_bytes()


@pytest.mark.parametrize("path", [p for p, k in TYPED if k is ModeTable], ids=lambda p: p.name)
def test_a_mode_tables_fields_are_its_numbers(path):
    d = json.loads(path.read_text())
    t = ModeTable.read(path)
    assert len(t.modes) == len(d["modes"]) and t.n_bp == d["n_bp"] and t.record_ps == d["record_ps"]
    for m, e in zip(t.modes, d["modes"]):
        assert isinstance(m, Mode) and (m.kind, m.n, m.omega_per_ps, m.reason) == (e["kind"], e["n"],
                                                                                    e["omega_per_ps"], e["reason"])
        assert (m.seeds is ABSENT) == ("seeds" not in e)
    assert len(t.measured()) == sum(e["reason"] is None for e in d["modes"])


def test_a_wave_result_written_by_the_analysis_round_trips(tmp_path):
    from mdbridge.analysis import WaveAnalysis
    from mdbridge.analysis.synthetic import helix_trajectory
    L = 158 * 3.38
    t = np.arange(0.0, 60.0, 1.0)
    traj, _ = helix_trajectory(t, lambda x, tt: 2.0 * np.cos(2 * np.pi * x / L - 0.05 * tt))
    s = WaveAnalysis(traj, n_boot=20).run().summary()
    write_json(tmp_path / "analysis.json", s)
    assert kind_of(json.loads((tmp_path / "analysis.json").read_text())) is WaveResult
    w = WaveResult.read(tmp_path / "analysis.json")
    assert not w.extra and w.n_bp == 158 and w.wave_speed_A_per_ps == pytest.approx(s["wave_speed_A_per_ps"])
    assert w.write(tmp_path / "back.json").read_bytes() == (tmp_path / "analysis.json").read_bytes()


def test_a_record_made_in_code_is_written_in_its_fields_order(tmp_path):
    m = Mode("bend", 1, omega_per_ps=0.01, reason=None, extra={"note": "x"})
    assert list(m.to_json()) == ["kind", "n", "omega_per_ps", "reason", "note"]


def test_control_changes_are_seen(tmp_path):
    path = next(p for p, k in TYPED if k is ModeTable)
    t = ModeTable.read(path)
    first = t.modes[0]
    for changed in (dataclasses.replace(t, modes=[dataclasses.replace(first, n=first.n + 1)] + t.modes[1:]),
                    dataclasses.replace(t, order=tuple(reversed(t.order))),
                    dataclasses.replace(t, modes=[dataclasses.replace(first, record_ps=ABSENT)] + t.modes[1:])):
        assert changed.write(tmp_path / "changed.json").read_bytes() != path.read_bytes()
