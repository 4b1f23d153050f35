"""checks.json's side-image distance (mdbridge/md/gromacs/checks.py) against brute force.

The face-slab search must give the exact smallest distance between an atom and an image
across the side walls, whether the first slabs already hold the closest pair (a compact
chain far from its images) or must widen (a chain whose atoms reach across the box)."""
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


@pytest.mark.parametrize("axis, n_atoms, step_A", [(1, 400, 1.5), (0, 400, 1.5), (2, 600, 4.0)])
def test_side_image_distance_is_exact(axis, n_atoms, step_A):
    rng = np.random.default_rng(3 + axis)
    box = np.array([40.0, 60.0, 45.0])
    # a chain of atoms step_A apart (the function follows the atom order), wound along the axis;
    # 4-A steps make it wander across the box, so the slabs must widen
    steps = rng.normal(size=(n_atoms, 3))
    steps *= step_A / np.linalg.norm(steps, axis=1, keepdims=True)
    y = np.array([20.0, 10.0, 22.0]) + np.cumsum(steps, axis=0)
    y[:, axis] %= box[axis]
    got = checks.min_side_image_distance(y, box, axis)
    want = brute_force(y, box, axis)
    assert got == pytest.approx(want, rel=1e-12)
