"""The Ornstein-Uhlenbeck noise model of a fitted mode amplitude (mdbridge/analysis/mode_noise.py)
against independent truths: the explicit correlation matrix, and the (s, tau) put into
synthetic OU noise."""
import numpy as np

from mdbridge.analysis.mode_noise import draw_ou, fit_ou_noise, ou_apply


def test_ou_apply_is_the_correlation_matrix():
    """R X by the forward/backward recursion equals the explicit exp(-|t_i - t_j| / tau) X,
    on non-uniform times; white noise (tau = 0) is the identity."""
    rng = np.random.default_rng(0)
    t = np.cumsum(rng.uniform(0.5, 2.0, 60))
    X = rng.standard_normal((60, 3))
    R = np.exp(-np.abs(t[:, None] - t[None, :]) / 7.0)
    assert np.allclose(ou_apply(t, 7.0, X), R @ X, rtol=0, atol=1e-12)
    assert np.array_equal(ou_apply(t, 0.0, X), X)


def test_reml_recovers_the_noise_put_in():
    """20 OU series (s = 2 A, tau = 10 ps, 400 frames of 1 ps) with an offset column projected
    out: the REML s and tau scatter about the true values within their sampling error
    (mean within 4 standard errors of the mean), and no series is taken for white noise."""
    rng = np.random.default_rng(4)
    t = np.arange(400.0)
    z = draw_ou(rng, t, 2.0, 10.0, 20)
    ones = np.ones((len(t), 1), complex)
    fits = [fit_ou_noise(t, zi - zi.mean(), np.concatenate([ones, 1j * ones], axis=1)) for zi in z]
    for key, true in (("noise_rms_A", 2.0), ("noise_tau_ps", 10.0)):
        v = np.array([f[key] for f in fits])
        assert abs(v.mean() - true) < 4 * v.std(ddof=1) / np.sqrt(len(v)), (key, v.mean(), v.std(ddof=1))
    assert min(f["noise_tau_ps"] for f in fits) > 3.0   # never mistaken for white noise
