#!/usr/bin/python3
"""The size of a nicked kilobase ring (docs/thermal.md, "The overdamped rod"): <Rg^2> of the
overdamped rod (solver.time = "brownian", water, 300 K, 10 bp per point) over an ensemble of
exact-sample starts, against a Metropolis Monte Carlo of the discrete worm-like ring with the
same segments and persistence length, run here.

The rod: the paper's uniform DNA (Sec 2.1) closed into a planar ring of --bp base pairs, its
twist stiffness D3 scaled by --twist-scale (1e-2: a nick, the twist free), no contact (a phantom
ring, as the Monte Carlo's). Each seed draws the exact Boltzmann sample of the linearised closed
ring (closed by continuation, docs/thermal.md) and runs --ns; <Rg^2> of the centreline polygon
over the frames after --discard-ns, the error from the scatter of the seeds' means (independent
starts).

The Monte Carlo: N = bp / 10 beads a segment b apart, E / kT = kappa sum (1 - t_i . t_{i+1}),
kappa from the rod's persistence length l_p = D1 / kT per segment, <cos theta> = coth kappa -
1 / kappa = exp(-b / l_p); crankshaft moves (an arc turned about the chord between its ends),
--chains independent chains from the planar ring, --sweeps sweeps, samples every 20 sweeps after
the first half; the error from the scatter of the chains' means.

    /usr/bin/python3 bench/ring_size.py [--bp 1050] [--seeds 64] [--ns 20] [--chains 512]
        [--sweeps 400] [--out bench/results/ring_size.json]
"""
from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from dna_models.units import Units  # noqa: E402
from mdbridge.jsonio import write_json  # noqa: E402
from mdbridge.rod.material.gridfile import write_initial_file  # noqa: E402

RISE_A = 3.4
D_PAPER = (1.21, 1.21, 2.0207)     # the scene's default D (docs/scenes.md, [material])


def kappa_for(b_over_lp: float) -> float:
    """kappa with coth kappa - 1 / kappa = exp(-b / l_p) (bisection)."""
    target, lo, hi = np.exp(-b_over_lp), 1e-6, 1e6
    for _ in range(200):
        mid = np.sqrt(lo * hi)
        if 1 / np.tanh(mid) - 1 / mid < target:
            lo = mid
        else:
            hi = mid
    return float(np.sqrt(lo * hi))


def rg2(x: np.ndarray) -> np.ndarray:
    """Rg^2 of polygons (..., n, 3): the mean square distance of the points from their centre."""
    c = x.mean(axis=-2, keepdims=True)
    return ((x - c) ** 2).sum(axis=-1).mean(axis=-1)


def monte_carlo(n: int, b: float, kappa: float, chains: int, sweeps: int, seed: int = 1):
    """<Rg^2> of the discrete worm-like ring (n beads b apart, joint stiffness kappa kT), and the
    standard error of the chains' means; crankshaft moves, all chains in step."""
    rng = np.random.default_rng(seed)
    phi = 2 * np.pi * np.arange(n) / n
    R = b / (2 * np.sin(np.pi / n))
    x = np.repeat(np.c_[R * np.cos(phi), R * np.sin(phi), np.zeros(n)][None], chains, axis=0)

    def joint_energy(x, k):
        a = x[:, k] - x[:, (k - 1) % n]
        c = x[:, (k + 1) % n] - x[:, k]
        return kappa * (1 - (a * c).sum(-1) / (b * b))

    samples, accepted, moves = [], 0, 0
    for sweep in range(sweeps):
        for _ in range(n):
            i = int(rng.integers(n))
            length = int(rng.integers(2, n - 1))        # beads i+1 .. i+length-1 turn about x_j - x_i
            j = (i + length) % n
            arc = (i + 1 + np.arange(length - 1)) % n
            axis = x[:, j] - x[:, i]
            axis /= np.linalg.norm(axis, axis=1)[:, None]
            angle = rng.uniform(-0.6, 0.6, chains)
            before = joint_energy(x, i) + joint_energy(x, j)
            p = x[:, arc] - x[:, i][:, None]
            k = axis[:, None]
            cos, sin = np.cos(angle)[:, None, None], np.sin(angle)[:, None, None]
            turned = p * cos + np.cross(k, p) * sin + k * (k * p).sum(-1, keepdims=True) * (1 - cos)
            old = x[:, arc].copy()
            x[:, arc] = turned + x[:, i][:, None]
            dE = joint_energy(x, i) + joint_energy(x, j) - before
            reject = rng.random(chains) >= np.exp(-np.clip(dE, 0, None))
            x[reject[:, None].nonzero()[0][:, None], arc[None]] = old[reject]
            accepted += int(chains - reject.sum())
            moves += chains
        if sweep >= sweeps // 2 and sweep % 20 == 0:
            samples.append(rg2(x))
    s = np.asarray(samples)                          # (samples, chains)
    per_chain = s.mean(axis=0)
    return float(per_chain.mean()), float(per_chain.std(ddof=1) / np.sqrt(chains)), accepted / moves, s.shape[0]


def rod_ensemble(bp: int, seeds: list[int], ns: float, discard_ns: float, twist_scale: float, dt_ps: float):
    """<Rg^2> [nm^2] of the Brownian rod ring over exact-sample starts, the seeds' scatter, and the
    persistence length and segment of the rod [nm]."""
    import rodcore
    from mdbridge.rod.scene import write_scene
    u = Units.paper()
    N = bp // 10
    L = bp * RISE_A / u.ell_A
    dt = dt_ps / u.tau_ps
    steps = int(round(ns * 1000 / dt_ps))
    frames = int(round(ns / 10)) + 1               # a frame per 10 ns
    work = Path(tempfile.mkdtemp(prefix="ring_size_"))
    # DNA is straight at rest: its ring starts as the planar circle, pre-stressed, which the sampler
    # does not sample exactly (docs/thermal.md): the run equilibrates it (--discard-ns)
    s = np.arange(N) * L / N
    write_initial_file(work / "ring.h5", s, np.c_[np.zeros((N, 2)), np.ones(N)],
                       np.c_[np.full(N, 2 * np.pi / L), np.zeros((N, 2))])
    scene = {"rod": {"length": L, "points": N, "Gamma0": [0.0, 0.0, 1.0], "Omega0": [0.0, 0.0, 0.0]},
             "material": {"D": [D_PAPER[0], D_PAPER[1], D_PAPER[2] * twist_scale]},
             "initial": {"kind": "file", "path": str(work / "ring.h5")},
             "thermal": {"temperature_K": 300.0, "seed": 1, "friction_translational": "water",
                         "friction_rotational": "water"},
             "solver": {"time": "brownian", "dt": dt},
             "output": {"t_end": steps * dt, "frames": frames, "fields": ["centerline"]}}
    path = work / "scene.toml"
    write_scene(path, scene, comment="bench/ring_size.py")
    means = []
    for seed in seeds:
        out = rodcore.run(str(path), set=[f"thermal.seed={seed}"])
        x = np.asarray(out["centerline"]) * u.ell_A / 10          # nm
        t = np.asarray(out["time"]) * u.tau_ps / 1000
        means.append(float(rg2(x[t >= discard_ns]).mean()))
        print(f"seed {seed}: <Rg^2> {means[-1]:.0f} nm^2; first frames {np.round(rg2(x[:6]))}", flush=True)
    m = np.asarray(means)
    kT = u.kT_to_rod(300.0)
    lp_nm = D_PAPER[0] / kT * u.ell_A / 10
    return float(m.mean()), float(m.std(ddof=1) / np.sqrt(len(m))), lp_nm, L / N * u.ell_A / 10, means


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bp", type=int, default=1050)
    ap.add_argument("--seeds", type=int, default=64)
    ap.add_argument("--ns", type=float, default=20.0)
    ap.add_argument("--discard-ns", type=float, default=10.0)
    ap.add_argument("--twist-scale", type=float, default=1e-2)
    ap.add_argument("--dt-ps", type=float, default=100.0)
    ap.add_argument("--chains", type=int, default=512)
    ap.add_argument("--sweeps", type=int, default=400)
    ap.add_argument("--out", type=Path, default=None)
    a = ap.parse_args(argv)
    rod, rod_err, lp_nm, b_nm, means = rod_ensemble(a.bp, list(range(1, a.seeds + 1)), a.ns, a.discard_ns,
                                                    a.twist_scale, a.dt_ps)
    kappa = kappa_for(b_nm / lp_nm)
    mc, mc_err, acceptance, samples = monte_carlo(a.bp // 10, b_nm, kappa, a.chains, a.sweeps)
    z = (rod - mc) / np.hypot(rod_err, mc_err)
    res = {"bp": a.bp, "points": a.bp // 10, "segment_nm": b_nm, "persistence_length_nm": lp_nm, "kappa": kappa,
           "twist_scale": a.twist_scale, "rod": {"Rg2_nm2": rod, "err": rod_err, "seeds": a.seeds, "ns": a.ns,
                                                 "dt_ps": a.dt_ps,
                                                 "discard_ns": a.discard_ns, "seed_means": means},
           "monte_carlo": {"Rg2_nm2": mc, "err": mc_err, "chains": a.chains, "sweeps": a.sweeps,
                           "samples_per_chain": samples, "acceptance": acceptance},
           "rod_over_mc": rod / mc, "z": z, "gaussian_ring_Rg2_nm2": a.bp * RISE_A / 10 * lp_nm / 6,
           "command": "bench/ring_size.py " + " ".join(argv if argv is not None else sys.argv[1:])}
    print(f"rod <Rg^2> {rod:.0f} +- {rod_err:.0f} nm^2; Monte Carlo {mc:.0f} +- {mc_err:.0f} nm^2 "
          f"(acceptance {acceptance:.2f}); rod / MC {rod / mc:.3f}, z {z:.1f}")
    if a.out:
        write_json(a.out, res)
    return 0


if __name__ == "__main__":
    sys.exit(main())
