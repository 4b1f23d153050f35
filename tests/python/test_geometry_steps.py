"""Step/base-pair parameters: 3DNA's worked example (tech-details.pdf, printed
numbers), exact round trips frames -> parameters -> frames (property-based),
and analytic cases (pure twist, pure roll, pure tilt, pure translation)."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from mdbridge.geometry import steps
from mdbridge.geometry.basefit import fit_frames
from mdbridge.geometry.rotations import rotation_exp, rotation_log, axis_angle_matrix

# --- 3DNA tech-details (Lu), sections 1-7: GG/CC step of adh026 -----------------
R1 = np.array([[-0.2323, -0.8985, -0.3724], [0.7889, -0.3980, 0.4682], [-0.5689, -0.1851, 0.8013]])
O1 = np.array([15.0378, 0.1221, -4.6088])
R2 = np.array([[-0.6319, -0.6594, -0.4072], [0.3583, -0.7144, 0.6010], [-0.6873, 0.2339, 0.6877]])
O2 = np.array([14.6869, 2.9781, -2.3818])
STEP_PRINTED = [0.3853, -1.4033, 3.3349, 2.9818, 9.7776, 33.5296]


def test_tech_details_step_example():
    """Inputs are printed with 4 decimals, so the outputs carry ~1e-3 noise."""
    p, Rm, om = steps.cehs(R1, O1, R2, O2)
    assert np.allclose(p, STEP_PRINTED, atol=2e-3)
    assert np.allclose(Rm, [[-0.4490, -0.8033, -0.3914], [0.5977, -0.5955, 0.5368],
                            [-0.6642, 0.0071, 0.7475]], atol=3e-4)
    assert np.allclose(om, [14.8624, 1.5501, -3.4953], atol=1e-4)


def test_tech_details_rebuild_example():
    """Section 7: R2 and Rm in the frame of base pair 1 from the six printed parameters."""
    R_rel, o_rel, Rm_rel = steps.step_transform(STEP_PRINTED)
    assert np.allclose(Rm_rel, [[0.9537, -0.2873, 0.0891], [0.2885, 0.9575, -0.0003],
                                [-0.0852, 0.0260, 0.9960]], atol=1e-4)
    assert np.allclose(R_rel, [[0.8204, -0.5436, 0.1775], [0.5524, 0.8336, -0.0006],
                               [-0.1476, 0.0985, 0.9841]], atol=1e-4)
    assert np.allclose(o_rel, [1.0677, -1.2336, 3.2524], atol=1e-4)


def test_tech_details_base_fit_and_pair():
    """Sections 1-4: fit of the standard G onto A_G1 (printed R, o, RMSD), and the
    base-pair parameters of A_G1-B_C8 and A_G2-B_C7."""
    from dna_models.nucleotides import ring_atom_names, standard_ring_coordinates
    order = ["N9", "C8", "N7", "C5", "C6", "N1", "C2", "N3", "C4"]
    E = np.array([[11.417, -2.904, -4.880], [10.759, -1.995, -5.662], [11.469, -0.913, -5.867],
                  [12.638, -1.108, -5.156], [13.759, -0.273, -5.036], [14.767, -0.848, -4.249],
                  [14.663, -2.116, -3.719], [13.625, -2.934, -3.830], [12.625, -2.328, -4.545]])
    E = E[[order.index(a) for a in ring_atom_names("G")]]
    R, o, rms = fit_frames(standard_ring_coordinates("G"), E)
    assert np.allclose(R, [[-0.2331, -0.8862, -0.4004], [0.8249, -0.3983, 0.4012],
                           [-0.5150, -0.2368, 0.8238]], atol=1e-4)
    assert np.allclose(o, [15.1632, -0.0362, -4.4678], atol=1e-4)
    assert rms == pytest.approx(0.0236, abs=1e-4)
    # base frames as printed (strand II un-flipped), base-pair parameters as printed
    RG1 = R
    RC8 = np.array([[-0.2339, 0.9100, 0.3422], [0.7496, 0.3930, -0.5326], [-0.6191, 0.1320, -0.7741]])
    p, Rbp, obp = steps.base_pair_parameters(RG1, o, RC8, [14.9124, 0.2803, -4.7498])
    assert np.allclose(p, [-0.4683, -0.1516, -0.0156, -5.4713, -6.7936, -2.8660], atol=3e-3)
    assert np.allclose(Rbp, R1, atol=2e-4)
    assert np.allclose(obp, O1, atol=1e-4)


def _random_frames(rng, shape):
    R = rotation_exp(rng.normal(size=shape + (3,)) * 2.0)
    o = rng.normal(size=shape + (3,)) * 20.0
    return R, o


def test_round_trip_parameters_frames_parameters_vectorised():
    rng = np.random.default_rng(3)
    shape = (50, 40)                       # e.g. trajectory frames x steps
    p = np.concatenate([rng.normal(0, 2, shape + (3,)),
                        rng.uniform(-60, 60, shape + (2,)),
                        rng.uniform(-170, 170, shape + (1,))], axis=-1)
    Ra, oa = _random_frames(rng, shape)
    Rb, ob = steps.next_frame(Ra, oa, p)
    q = steps.step_parameters(Ra, oa, Rb, ob)
    assert np.abs(q - p).max() < 1e-11
    # and frames -> parameters -> frames
    Rc, oc = steps.next_frame(Ra, oa, q)
    assert np.abs(Rc - Rb).max() < 1e-13 and np.abs(oc - ob).max() < 1e-12


angle = st.floats(-80.0, 80.0, allow_nan=False)
length = st.floats(-5.0, 5.0, allow_nan=False)


@settings(max_examples=300, deadline=None)
@given(st.tuples(length, length, length, angle, angle, st.floats(-175.0, 175.0)),
       st.tuples(*[st.floats(-3.0, 3.0)] * 3))
def test_round_trip_property(p, rv):
    """Any step (bend < 114 deg, |twist| < 175 deg) from any starting frame:
    parameters -> frames -> parameters to 1e-12 (lengths A, angles deg)."""
    p = np.array(p)
    R0 = rotation_exp(np.array(rv))
    o0 = np.array([1.0, -2.0, 3.0])
    Rn, on = steps.next_frame(R0, o0, p)
    assert np.abs(steps.step_parameters(R0, o0, Rn, on) - p).max() < 1e-11


@settings(max_examples=200, deadline=None)
@given(st.tuples(length, length, length, angle, angle, st.floats(-175.0, 175.0)))
def test_base_pair_round_trip_property(p):
    p = np.array(p)
    R_bp = rotation_exp(np.array([0.3, -1.0, 2.0]))
    o_bp = np.array([5.0, 0.0, -1.0])
    R_I, o_I, R_II, o_II = steps.base_frames_from_pair(p, R_bp, o_bp)
    q, R, o = steps.base_pair_parameters(R_I, o_I, R_II, o_II)
    assert np.abs(q - p).max() < 1e-11
    assert np.abs(R - R_bp).max() < 1e-14 and np.abs(o - o_bp).max() < 1e-13


def test_chain_rebuild_round_trip():
    rng = np.random.default_rng(5)
    p = np.concatenate([rng.normal(0, 1, (3, 157, 3)), rng.normal(0, 8, (3, 157, 3))], axis=-1)
    p[..., 2] += 3.38
    p[..., 5] += 34.3
    R, o = steps.frames_from_steps(p)
    assert R.shape == (3, 158, 3, 3)
    q = steps.step_parameters_along(R, o)
    assert np.abs(q - p).max() < 1e-10
    assert np.abs(R @ np.swapaxes(R, -1, -2) - np.eye(3)).max() < 1e-13


@pytest.mark.parametrize("which,expect", [
    ("twist", [0, 0, 0, 0, 0, 30.0]), ("roll", [0, 0, 0, 0, 12.0, 0]),
    ("tilt", [0, 0, 0, -7.0, 0, 0])])
def test_pure_rotations(which, expect):
    """A turn about the z (twist), y (roll) or x (tilt) axis of frame 1 by a known
    angle gives that parameter and nothing else."""
    axis = {"twist": [0, 0, 1], "roll": [0, 1, 0], "tilt": [1, 0, 0]}[which]
    ang = {"twist": 30.0, "roll": 12.0, "tilt": -7.0}[which]
    R2 = axis_angle_matrix(np.array(axis, float), np.radians(ang))
    assert np.allclose(steps.step_parameters(np.eye(3), np.zeros(3), R2, np.zeros(3)), expect, atol=1e-13)


def test_translation_in_mid_frame():
    """Twist 90 deg and displacement (1, 0, 3.4) in the lab: the mid-step frame is
    turned by 45 deg, so shift = cos45, slide = -sin45."""
    R2 = axis_angle_matrix(np.array([0, 0, 1.0]), np.pi / 2)
    p = steps.step_parameters(np.eye(3), np.zeros(3), R2, np.array([1.0, 0, 3.4]))
    assert np.allclose(p, [np.sqrt(0.5), -np.sqrt(0.5), 3.4, 0, 0, 90.0], atol=1e-14)


def test_small_angles_keep_relative_precision():
    """atan2-based angles: a 1e-9 degree roll is recovered to ~1e-22, where
    arccos-based formulas (as in 3DNA) would return 0 or ~1e-6."""
    p = np.array([0, 0, 3.4, 0, 1e-9, 36.0])
    R2, o2 = steps.next_frame(np.eye(3), np.zeros(3), p)
    q = steps.step_parameters(np.eye(3), np.zeros(3), R2, o2)
    assert q[4] == pytest.approx(1e-9, rel=1e-6)


def test_rotation_log_exp_inverse():
    rng = np.random.default_rng(0)
    v = rng.normal(size=(1000, 3))
    v *= (rng.uniform(0, np.pi - 1e-3, 1000) / np.linalg.norm(v, axis=1))[:, None]
    v[:10] *= 1e-12
    assert np.abs(rotation_log(rotation_exp(v)) - v).max() < 1e-12


@pytest.mark.parametrize("base", "ACGT")
def test_fast_horn_fit_equals_svd_fit(base):
    """The vectorised quaternion solver and the Kabsch/SVD solver minimise the
    same function: same frames to round-off on noisy, randomly placed bases."""
    from dna_models.nucleotides import standard_ring_coordinates
    rng = np.random.default_rng(11)
    S = standard_ring_coordinates(base)
    Rt = rotation_exp(rng.normal(size=(2000, 3)) * 2)
    E = np.einsum("kij,nj->kni", Rt, S) + rng.normal(size=(2000, 1, 3)) * 30 \
        + rng.normal(0, 0.3, (2000, len(S), 3))
    R, o, rms = fit_frames(S, E)
    R2, o2, rms2 = fit_frames(S, E, method="svd")
    assert np.abs(R - R2).max() < 1e-12 and np.abs(o - o2).max() < 1e-11
    assert np.abs(rms - rms2).max() < 1e-10
    assert np.abs(np.linalg.det(R) - 1).max() < 1e-13


def test_fit_degenerate_input_falls_back():
    from dna_models.nucleotides import standard_ring_coordinates
    R, o, rms = fit_frames(standard_ring_coordinates("A"), np.zeros((2, 9, 3)))
    assert np.all(np.isfinite(R)) and np.allclose(R @ np.swapaxes(R, -1, -2), np.eye(3))


def test_fit_single_base_shapes_and_exact_rmsd():
    """Unbatched input gives unbatched output, and an exact copy of the standard
    base has RMSD at round-off (peers rely on this to check templates)."""
    from dna_models.nucleotides import standard_ring_coordinates
    S = standard_ring_coordinates("G")
    Rt = rotation_exp(np.array([0.3, 1.0, 2.0]))
    R, o, rms = fit_frames(S, S @ Rt.T + [10.0, 20.0, 30.0])
    assert R.shape == (3, 3) and o.shape == (3,) and np.ndim(rms) == 0
    assert rms < 1e-13 and np.abs(R - Rt).max() < 1e-14
