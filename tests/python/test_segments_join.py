"""Segments of one long MD joined in time (workflows/steps/segments.py).

A run stopped between checkpoints wrote frames past its last checkpoint; the next segment
continues from that checkpoint, so its frames replace them. Known answer: one series cut in
two at t = 10 ps, the first part carrying 3 extra frames of a different continuation past
the cut; the join must equal the original series exactly. Control: a gap between the
segments is refused with the segment named.
"""
import json

import numpy as np
import pytest

from dna_models.errors import InputError
from dnarod.steps.segments import join_segments
from mdbridge.analysis.mode_spectra import ModeSeries, load_npz, save_npz

DT = 0.5


def _series(t, rng):
    n = np.arange(1, 4)
    c = rng.normal(size=(len(t), 3)) + 1j * rng.normal(size=(len(t), 3))
    return ModeSeries(t, n, np.stack([c, c], axis=-1), c * 0.1, c * 0.01, 534.0, 158, 15, "synthetic", "md",
                      rng.uniform(0, 0.01, size=len(t)), {})


def _write(d, s, dist, energies):
    d.mkdir(parents=True)
    save_npz(d / "mode_series.npz", [s])
    np.savez_compressed(d / "integrity.npz", times_ps=s.times_ps, n1_n3_A=dist.astype(np.float16))
    np.savez_compressed(d / "energies.npz", **energies)


def _cut(full, dist, t0, t1, extra, rng):
    keep = (full.times_ps >= t0) & (full.times_ps < t1)
    s = ModeSeries(full.times_ps[keep], full.n, full.bend[keep], full.twist[keep], full.stretch[keep],
                   full.length_A, full.n_bp, full.helical_repeat, full.source, full.kind, full.open_fraction[keep], {})
    d = dist[keep]
    if extra:                                   # frames of another continuation past the checkpoint
        other = _series(full.times_ps[~keep][full.times_ps[~keep] >= t1][:extra], rng)
        s = ModeSeries(np.concatenate([s.times_ps, other.times_ps]), s.n, np.concatenate([s.bend, other.bend]),
                       np.concatenate([s.twist, other.twist]), np.concatenate([s.stretch, other.stretch]),
                       s.length_A, s.n_bp, s.helical_repeat, s.source, s.kind,
                       np.concatenate([s.open_fraction, other.open_fraction]), {})
        d = np.concatenate([d, np.full((extra, d.shape[1]), 9.0)])
    return s, d


def test_join_leaves_out_the_frames_past_a_checkpoint_and_equals_the_whole(tmp_path):
    rng = np.random.default_rng(1)
    t = np.arange(0, 20, DT)
    full = _series(t, rng)
    dist = rng.uniform(2.8, 3.2, size=(len(t), 158))
    dist[5, 7] = 4.0                                     # one open pair in one frame
    segs = []
    for k, (t0, t1, extra) in enumerate(((0, 10, 3), (10, 20, 0))):
        s, d = _cut(full, dist, t0, t1, extra, rng)
        e = {"times_ps": s.times_ps, "tension_pN": np.full(len(s.times_ps), float(k))}
        _write(tmp_path / f"seg{k}", s, d, e)
        segs.append(tmp_path / f"seg{k}")
    summary = join_segments(segs, tmp_path / "out")
    j = load_npz(tmp_path / "out" / "mode_series.npz")[0]
    assert np.array_equal(j.times_ps, t)
    np.testing.assert_allclose(j.twist, full.twist, rtol=1e-6, atol=1e-6)     # float32 in the file
    assert summary["open_fraction_per_pair"][7] == pytest.approx(1 / len(t))
    assert json.loads((tmp_path / "out" / "integrity.json").read_text())["open_fraction"] == pytest.approx(
        1 / (len(t) * 158))
    e = np.load(tmp_path / "out" / "energies.npz")
    assert np.array_equal(e["times_ps"], t) and e["tension_pN"][19] == 0.0 and e["tension_pN"][20] == 1.0


def test_a_gap_between_segments_is_refused(tmp_path):
    rng = np.random.default_rng(2)
    t = np.arange(0, 20, DT)
    full = _series(t, rng)
    dist = rng.uniform(2.8, 3.2, size=(len(t), 158))
    segs = []
    for k, (t0, t1) in enumerate(((0, 8), (10, 20))):
        s, d = _cut(full, dist, t0, t1, 0, rng)
        _write(tmp_path / f"seg{k}", s, d, {"times_ps": s.times_ps})
        segs.append(tmp_path / f"seg{k}")
    with pytest.raises(InputError, match="seg1: its mode frames start at 10 ps"):
        join_segments(segs, tmp_path / "out")
