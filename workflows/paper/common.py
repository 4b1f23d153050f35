"""Shared bits of the figure and check modules: output files and small numerics."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from mdbridge.jsonio import write_json as _write_json


def plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as pyplot
    return pyplot


def write_json(path: Path, data: dict) -> Path:
    return _write_json(path, data, indent=2)


def save(fig, path: Path, dpi: int = 90) -> Path:
    fig.savefig(path, dpi=dpi)
    plt().close(fig)
    return Path(path)


def finish(fig, ax, path: Path, xlabel: str, ylabel: str, title: str, legend: int = 8) -> Path:
    """The figures' common ending: axis labels, a small title, legend, layout, save."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=legend)
    fig.tight_layout()
    return save(fig, path)


def mode_amplitude(u: np.ndarray, m: int) -> np.ndarray:
    """Complex amplitude c_m(t) of Fourier mode m of u (T, N) on a uniform periodic grid:
    u = sum_m Re(c_m e^{i 2 pi m s / L}) for m >= 1."""
    u = np.asarray(u, float)
    return 2.0 / u.shape[-1] * np.fft.fft(u, axis=-1)[..., m].conj()


def fit_frequencies(t, signals, guesses):
    """Least-squares fit of real signals (S, T) to sum_j a_sj cos(w_j t) + b_sj sin(w_j t)
    with frequencies w_j shared by all signals; starts from `guesses`. Returns the
    frequencies (sorted as the guesses) and the rms residual / rms signal."""
    from scipy.optimize import least_squares
    t = np.asarray(t, float)
    Y = np.atleast_2d(np.asarray(signals, float))

    def design(w):
        return np.column_stack([f(wj * t) for wj in w for f in (np.cos, np.sin)])

    def resid(w):
        A = design(w)
        coef = np.linalg.lstsq(A, Y.T, rcond=None)[0]
        return (A @ coef - Y.T).ravel()

    sol = least_squares(resid, np.asarray(guesses, float), xtol=1e-14, ftol=1e-14, gtol=1e-14)
    rel = np.sqrt(np.mean(sol.fun ** 2)) / max(np.sqrt(np.mean(Y ** 2)), 1e-300)
    return sol.x, float(rel)


def find_frequencies(t, signals, n: int, tol: float = 1e-5, extra: int = 2):
    """Frequencies of a sum of n (or up to n + extra) sinusoids shared by signals (S, T):
    start from the n largest spectral peaks, fit (fit_frequencies); while the fit leaves
    more than tol of the signal, add the largest peak of the residual and refit (a weak
    component hidden next to a strong one is found this way). Returns (w, rel)."""
    t = np.asarray(t, float)
    Y = np.atleast_2d(np.asarray(signals, float))
    w, rel = fit_frequencies(t, Y, spectral_peaks(t, Y, n))
    while rel > tol and len(w) < n + extra:
        A = np.column_stack([g for wj in w for g in (np.cos(wj * t), np.sin(wj * t))])
        R = Y.T - A @ np.linalg.lstsq(A, Y.T, rcond=None)[0]
        w, rel = fit_frequencies(t, Y, np.append(w, spectral_peaks(t, R.T, 1)))
    return w, rel


def spectral_peaks(t, signals, n_peaks: int, pad: int = 8):
    """Frequencies of the n_peaks largest local maxima of the summed power spectrum
    (Hann window, zero-padded FFT) of real signals (S, T) sampled uniformly at t."""
    t = np.asarray(t, float)
    Y = np.atleast_2d(np.asarray(signals, float))
    dt = t[1] - t[0]
    n = len(t) * pad
    win = np.hanning(len(t))
    P = np.sum([np.abs(np.fft.rfft((y - y.mean()) * win, n)) ** 2 for y in Y], axis=0)
    f = 2 * np.pi * np.fft.rfftfreq(n, dt)
    idx = [i for i in range(1, len(P) - 1) if P[i] >= P[i - 1] and P[i] > P[i + 1]]
    idx = sorted(idx, key=lambda i: -P[i])[:n_peaks]
    return np.sort(f[idx])
