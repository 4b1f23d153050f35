"""checks.json's side-image distance (mdbridge/md/gromacs/checks.py) against brute force.

The fast path (a bounded tree search) and the fallback (unbounded) must both give
the exact smallest distance between an atom and an image across the side walls."""
import numpy as np
import pytest

from mdbridge.md.gromacs import checks


def brute_force(y, box, axis):
    perp = [k for k in range(3) if k != axis]
    best = np.inf
    for a in (-1, 0, 1):
        for b in (-1, 0, 1):
            if a == 0 and b == 0:
                continue
            shift = np.zeros(3)
            shift[perp[0]], shift[perp[1]] = a * box[perp[0]], b * box[perp[1]]
            d = y[:, None, :] - (y[None, :, :] + shift)
            d[..., axis] -= box[axis] * np.round(d[..., axis] / box[axis])  # periodic along the axis
            best = min(best, float(np.linalg.norm(d, axis=-1).min()))
    return best


@pytest.mark.parametrize("bound", [30.0, 1.0])  # 1.0: below the true distance, so the fallback runs
def test_side_image_distance_is_exact(monkeypatch, bound):
    rng = np.random.default_rng(3)
    box = np.array([40.0, 60.0, 45.0])
    axis = 1
    # a chain of atoms 1.5 A apart (the function follows the atom order), wound along the axis
    steps = rng.normal(size=(400, 3))
    steps *= 1.5 / np.linalg.norm(steps, axis=1, keepdims=True)
    y = np.array([20.0, 0.0, 22.0]) + np.cumsum(steps, axis=0)
    y[:, axis] %= box[axis]
    monkeypatch.setattr(checks, "SIDE_SEARCH_A", bound)
    got = checks.min_side_image_distance(y, box, axis)
    want = brute_force(y, box, axis)
    assert want > bound or bound == 30.0   # the fallback case really is one
    assert got == pytest.approx(want, rel=1e-12)
