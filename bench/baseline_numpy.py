#!/usr/bin/python3
"""Baseline: the rod equations as a scientist would first write them.

THIS FILE IS DELIBERATELY AN INDEPENDENT RE-IMPLEMENTATION of paper Eqs 11-14
(numpy derivatives + scipy.integrate.solve_ivp). It shares no code with
rodcore (the C++ solver) on purpose, for two reasons:

1. speed baseline: bench/workprecision.py times it against `rodsim` with the
   same spatial operator, the same integrator (DOP853) and the same tolerances;
2. cross-check: written from the paper, not from rodcore, it must reproduce
   rodsim's result to the integration tolerance
   (tests/python/test_stress_baseline_crosscheck.py).

The equations (dimensionless, internal frame, periodic in s, diagonal C, D, I):

    d gamma/dt = C dGamma/ds + Omega x C(Gamma - Gamma0) - omega x gamma          (11)
    I d omega/dt = D dOmega/ds + Omega x D(Omega - Omega0)
                   + Gamma x C(Gamma - Gamma0) - omega x I omega                   (12)
    d Gamma/dt = d gamma/ds + Omega x gamma - omega x Gamma                       (13)
    d Omega/dt = d omega/ds - omega x Omega                                       (14)

for a uniform intrinsic shape Gamma0, Omega0 (so dGamma0/ds = dOmega0/ds = 0).

The initial state, rod and material are read from frame 0 of a rodsim output
file (HDF5, layout of docs/scenes.md), so both codes start from identical
numbers; the result is written as an .npz with `time` and `y` (T x 12 x N).

    baseline_numpy.py INITIAL.h5 --space spectral --rtol 1e-9 --t-end 100 -o out.npz
"""
import argparse
import sys
import time

WALL0 = time.perf_counter()  # process start (imports included in the wall time)

import h5py  # noqa: E402
import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402


def derivative_fd4(f, h):
    """Paper Sec 5.1: [f(s-2h) - 8 f(s-h) + 8 f(s+h) - f(s+2h)] / 12h, periodic (along the last axis)."""
    return (np.roll(f, 2, axis=-1) - 8 * np.roll(f, 1, axis=-1)
            + 8 * np.roll(f, -1, axis=-1) - np.roll(f, -2, axis=-1)) / (12 * h)


def make_derivative_spectral(N, L):
    """Fourier derivative: ifft(i k fft(f)); the Nyquist mode (even N) is dropped."""
    k = 2 * np.pi * np.fft.rfftfreq(N, d=L / N)
    if N % 2 == 0:
        k[-1] = 0.0
    ik = 1j * k

    def derivative(f):
        return np.fft.irfft(ik * np.fft.rfft(f, axis=-1), n=N, axis=-1)
    return derivative


def make_rhs(N, L, C, D, I, Gamma0, Omega0, space):
    C = np.asarray(C)[:, None]
    D = np.asarray(D)[:, None]
    I = np.asarray(I)[:, None]
    Gamma0 = np.asarray(Gamma0)[:, None]
    Omega0 = np.asarray(Omega0)[:, None]
    if space == "fd4":
        h = L / N

        def dds(f):
            return derivative_fd4(f, h)
    elif space == "spectral":
        dds = make_derivative_spectral(N, L)
    else:
        raise ValueError(f"space must be fd4 or spectral, got {space!r}")

    def rhs(t, yflat):
        y = yflat.reshape(4, 3, N)
        gamma, omega, Gamma, Omega = y
        dy = dds(y)
        dgamma, domega, dGamma, dOmega = dy
        n = C * (Gamma - Gamma0)   # internal force
        m = D * (Omega - Omega0)   # internal moment
        f_gamma = C * dGamma + np.cross(Omega, n, axis=0) - np.cross(omega, gamma, axis=0)
        f_omega = (D * dOmega + np.cross(Omega, m, axis=0) + np.cross(Gamma, n, axis=0)
                   - np.cross(omega, I * omega, axis=0)) / I
        f_Gamma = dgamma + np.cross(Omega, gamma, axis=0) - np.cross(omega, Gamma, axis=0)
        f_Omega = domega - np.cross(omega, Omega, axis=0)
        return np.concatenate([f_gamma, f_omega, f_Gamma, f_Omega]).ravel()
    return rhs


def read_initial(path):
    """Rod, material and the frame-0 state (12 x N, rows gamma1..Omega3) of a rodsim file."""
    with h5py.File(path, "r") as f:
        a = f.attrs
        if "intrinsic" in f:
            raise SystemExit(f"{path}: baseline handles a uniform intrinsic shape only")
        rod = dict(L=float(a["rod.length"]), N=int(a["rod.points"]),
                   Gamma0=np.array(a["rod.Gamma0"]), Omega0=np.array(a["rod.Omega0"]),
                   C=np.array(a["material.C"]), D=np.array(a["material.D"]), I=np.array(a["material.I"]))
        y0 = np.concatenate([np.asarray(f["fields"][name][0]).T
                             for name in ("gamma", "omega", "Gamma", "Omega")])
    return rod, y0


def run(initial, space, method, rtol, atol, t_end, frames):
    rod, y0 = read_initial(initial)
    rhs = make_rhs(rod["N"], rod["L"], rod["C"], rod["D"], rod["I"], rod["Gamma0"], rod["Omega0"], space)
    t_eval = np.linspace(0.0, t_end, frames)
    sol = solve_ivp(rhs, (0.0, t_end), y0.ravel(), method=method, rtol=rtol, atol=atol,
                    t_eval=t_eval, dense_output=False)
    if not sol.success:
        raise SystemExit(f"solve_ivp failed: {sol.message}")
    y = sol.y.T.reshape(frames, 12, rod["N"])
    return sol.t, y, sol.nfev


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("initial", help="rodsim output HDF5 whose frame 0 is the initial state")
    p.add_argument("--space", choices=["fd4", "spectral"], default="spectral")
    p.add_argument("--method", default="DOP853", help="scipy solve_ivp method (default DOP853)")
    p.add_argument("--rtol", type=float, default=1e-9)
    p.add_argument("--atol", type=float, default=None, help="default: = rtol")
    p.add_argument("--t-end", type=float, required=True)
    p.add_argument("--frames", type=int, default=2)
    p.add_argument("-o", "--output", required=True, help="output .npz (time, y[T,12,N], wall_s, nfev)")
    a = p.parse_args(argv)
    t, y, nfev = run(a.initial, a.space, a.method, a.rtol, a.atol if a.atol is not None else a.rtol,
                     a.t_end, a.frames)
    wall = time.perf_counter() - WALL0
    np.savez(a.output, time=t, y=y, wall_s=wall, nfev=nfev)
    print(f"baseline_numpy: {a.space}+{a.method} rtol={a.rtol}: {nfev} RHS evaluations, "
          f"{wall:.3g} s wall (process)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
