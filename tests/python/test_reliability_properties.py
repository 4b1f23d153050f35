"""Property-based checks (hypothesis) that extend the round trips of
tests/python/test_geometry_steps.py with two exact symmetries of 3DNA's step
parameters (Lu & Olson 2003, CEHS scheme) that hold for any pair of frames:
  * invariance under a global rigid motion (the parameters are expressed in
    the mid-step frame, which moves with the pair), and
  * reversal: reading the step from frame 2 to frame 1 gives the negated
    parameters (same mid-step frame, inverse rotation, opposite displacement)."""
import numpy as np
from hypothesis import given, settings, strategies as st

from mdbridge.geometry import steps
from mdbridge.geometry.rotations import rotation_exp

length = st.floats(-4.0, 4.0)
angle = st.floats(-60.0, 60.0)
step = st.tuples(length, length, st.floats(0.0, 8.0), angle, angle, st.floats(-175.0, 175.0))
rotvec = st.tuples(*[st.floats(-3.0, 3.0)] * 3)
shift = st.tuples(*[st.floats(-1e3, 1e3)] * 3)


@settings(max_examples=150, deadline=None)
@given(step, rotvec, rotvec, shift)
def test_step_parameters_are_invariant_under_rigid_motion(p, rv0, rvQ, t):
    R1 = rotation_exp(np.array(rv0))
    o1 = np.array([0.5, -1.0, 2.0])
    R2, o2 = steps.next_frame(R1, o1, np.array(p))
    Q, t = rotation_exp(np.array(rvQ)), np.array(t)
    a = steps.step_parameters(R1, o1, R2, o2)
    b = steps.step_parameters(Q @ R1, Q @ o1 + t, Q @ R2, Q @ o2 + t)
    scale = 1.0 + np.abs(t).max()  # translations lose digits to |t|
    assert np.abs(a[:3] - b[:3]).max() < 1e-10 * scale
    assert np.abs(a[3:] - b[3:]).max() < 1e-9 * scale


@settings(max_examples=150, deadline=None)
@given(step, rotvec)
def test_reversed_step_has_negated_parameters(p, rv0):
    R1 = rotation_exp(np.array(rv0))
    o1 = np.array([3.0, 1.0, -2.0])
    R2, o2 = steps.next_frame(R1, o1, np.array(p))
    forward = steps.step_parameters(R1, o1, R2, o2)
    backward = steps.step_parameters(R2, o2, R1, o1)
    assert np.abs(forward + backward).max() < 1e-9
