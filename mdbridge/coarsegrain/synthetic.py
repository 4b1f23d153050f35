"""Synthetic equilibrium ensembles with a known answer, for tests and benchmarks.

`ar1_steps` draws step parameters from a Gaussian with given per-step means and
6x6 stiffness K (kT units, so the covariance is K^-1) as an AR(1) series in time,
q_t - mu = phi (q_{t-1} - mu) + sqrt(1 - phi^2) L e_t with L L^T = K^-1: stationary,
with integrated autocorrelation time (1 + phi) / (2 (1 - phi)) frames in every
component. `write_trajectory` turns the steps into all-atom frames with the
toolkit's builder (mdbridge.md.builder, 3DNA rebuild) and writes them as a PDB
topology plus a TRR trajectory with Maxwell-Boltzmann velocities at a given
temperature (mdbridge.md.gromacs.velocities: zero momentum, exactly that kinetic
temperature with 3N - 3 degrees of freedom), which MDAnalysis reads like any MD output.
"""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np


def ar1_steps(mean, K, n_frames: int, phi: float, rng: np.random.Generator) -> np.ndarray:
    """(T, n_steps, 6) step parameters; mean (n_steps, 6), K (n_steps, 6, 6) in kT units."""
    mean = np.asarray(mean, dtype=float)
    L = np.linalg.cholesky(np.linalg.inv(np.asarray(K, dtype=float)))     # (n, 6, 6)
    n = mean.shape[0]
    x = np.einsum("nij,nj->ni", L, rng.standard_normal((n, 6)))
    out = np.empty((n_frames, n, 6))
    a = np.sqrt(1.0 - phi * phi)
    for t in range(n_frames):
        x = phi * x + a * np.einsum("nij,nj->ni", L, rng.standard_normal((n, 6)))
        out[t] = mean + x
    return out


def write_trajectory(directory, sequence: str, q: np.ndarray, temperature_K: float | None,
                     rng: np.random.Generator, dt_ps: float = 1.0):
    """Write DIR/duplex.pdb (first frame) and DIR/duplex.trr (all frames; velocities
    drawn from Maxwell-Boltzmann at temperature_K when given). Returns the two paths."""
    import MDAnalysis as mda
    from MDAnalysis.coordinates.memory import MemoryReader

    from mdbridge.md.builder.duplex import build_duplex
    from mdbridge.geometry.steps import frames_from_steps
    from mdbridge.md.pdbio import write_pdb

    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    # build_duplex places every nucleotide's template rigidly in its base-pair frame (3DNA's
    # rebuild): build once, then move each base pair's atoms with its frame
    R0, o0 = frames_from_steps(q[0])
    s0 = build_duplex(sequence, o0, R0)
    n = len(sequence)
    pair = np.where(s0.resids <= n, s0.resids - 1, 2 * n - s0.resids)
    local = np.einsum("aji,aj->ai", R0[pair], s0.coords - o0[pair])      # R^T (x - o)
    pos = []
    for qt in q:
        R, o = frames_from_steps(qt)
        pos.append(o[pair] + np.einsum("aij,aj->ai", R[pair], local))
    pdb = d / "duplex.pdb"
    write_pdb(pdb, s0)
    u = mda.Universe(str(pdb))
    pos_arr = np.array(pos, dtype=np.float32)
    vel = None
    if temperature_K is not None:
        from mdbridge.md.gromacs.velocities import thermal_velocities
        vel = np.array([10.0 * thermal_velocities(u.atoms.masses, temperature_K, int(s))   # nm/ps -> A/ps
                        for s in rng.integers(0, 2**31, len(pos))], dtype=np.float32)
    u.load_new(pos_arr, format=MemoryReader, velocities=vel, dt=dt_ps)
    trr = d / "duplex.trr"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)   # MDAnalysis: box angles of "no box"
        with mda.Writer(str(trr), n_atoms=u.atoms.n_atoms) as w:
            for _ in u.trajectory:
                w.write(u.atoms)
    return pdb, trr


def fast_slow_steps(mean, J_fast, J_slow, n_frames: int, dt_ps: float, tau_fast_ps: float,
                    sigma_slow_ps: float, rng: np.random.Generator) -> np.ndarray:
    """(T, n_steps, 6) step parameters: mean + fast elastic fluctuations (AR(1) of correlation
    time tau_fast_ps, covariance J_fast) + slow smooth episodes (white noise smoothed by a
    Gaussian of width sigma_slow_ps, covariance J_slow), independent per step; J_fast,
    J_slow (6, 6) or (n_steps, 6, 6) compliances in kT units. Their creep compliance is
    J(u) = J_fast (1 - e^{-u / tau_fast}) + J_slow (1 - e^{-u^2 / (4 sigma_slow^2)})
    (exactly at the frame times for the fast part; the slow one's kernel is cut at 5 widths)."""
    mean = np.asarray(mean, dtype=float)
    n = mean.shape[0]
    Lf = np.linalg.cholesky(np.broadcast_to(np.asarray(J_fast, float), (n, 6, 6)))
    Ls = np.linalg.cholesky(np.broadcast_to(np.asarray(J_slow, float), (n, 6, 6)))
    phi = np.exp(-dt_ps / tau_fast_ps)
    a = np.sqrt(1.0 - phi * phi)
    e = rng.standard_normal((n_frames, n, 6))
    f = np.empty_like(e)
    f[0] = e[0]
    for t in range(1, n_frames):
        f[t] = phi * f[t - 1] + a * e[t]
    half = int(np.ceil(5.0 * sigma_slow_ps / dt_ps))
    u = np.arange(-half, half + 1) * dt_ps
    g = np.exp(-0.5 * (u / sigma_slow_ps) ** 2)
    g /= np.sqrt(np.sum(g * g))
    from scipy.signal import fftconvolve
    w = rng.standard_normal((n_frames + 2 * half, n * 6))
    s = fftconvolve(w, g[:, None], mode="valid", axes=0).reshape(n_frames, n, 6)
    return (mean + np.einsum("nij,tnj->tni", Lf, f) + np.einsum("nij,tnj->tni", Ls, s))


def fast_slow_creep(u_ps, J_fast, J_slow, tau_fast_ps: float, sigma_slow_ps: float):
    """The creep compliance of fast_slow_steps at lags u_ps (..., 6, 6)."""
    u = np.asarray(u_ps, dtype=float)[..., None, None]
    return (np.asarray(J_fast) * (1.0 - np.exp(-u / tau_fast_ps))
            + np.asarray(J_slow) * (1.0 - np.exp(-u * u / (4.0 * sigma_slow_ps ** 2))))
