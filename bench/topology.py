"""Writhe per frame of a 10.5-kbp closed DNA rod at one point per base pair: the exact
Klenin-Langowski writhe of the whole polygon (polygon_writhe) against the coarsened
one (writhe(x, k): near pairs exact, far ones by the chords of k segments) and
against the polygon through every k-th point alone (chords only), CPU time and error
side by side; and the cost of the other parts of a frame (Lk by crossings, Tw) and of a whole
frame as `dnarod topology` does it (the default of at most 1000 writhe points) and as rodsim
does it for a closed rod (the same without the stride-2k coarsening estimate). All of it runs
the C++ of rodcore/src/topology.cpp (rodcore.topology).

The curve: 10,500 points 3.38 A apart, a toroidal supercoil (a helix of 20 coils wound
on a torus, R = 4000 A, r = 200 A, writhe about -2.7) with the roughness of thermal DNA
below the persistence length: a random closed displacement whose modes k >= L / lp
(lp = 500 A) have transverse amplitudes ~ 1 / k^2 (so the curvature is white noise, as in a
worm-like chain), scaled so that neighbouring edges bend by 0.116 rad rms, the
sqrt(2 h / lp) of a worm-like chain; one curve per seed. Longer-wavelength modes are
left out so that the supercoil stays a supercoil.

CPU time is process time (the machine is shared). Writes results/topology.json.

  nice -n 10 python bench/topology.py [--seeds 1 2 3] [--strides 5 11 21 41]
"""
import argparse
import time
from pathlib import Path

import numpy as np

from dna_models.bdna import RISE_A
from mdbridge.geometry.compiled import rodcore_module
from mdbridge.geometry.topology import (centred_tangents, linking_number, perpendicular_unit, polygon_writhe,
                                        ribbon_topology, twist, writhe)
from mdbridge.jsonio import write_json

N_BP, LP_A, COILS, R_A, r_A = 10_500, 500.0, 20, 4000.0, 200.0


def supercoil(seed: int):
    """The closed curve (N_BP, 3) [A] and a ribbon vector field along it."""
    th = np.arange(N_BP) * 2 * np.pi / N_BP
    c, s = np.cos(COILS * th), np.sin(COILS * th)
    x = np.stack([(R_A + r_A * c) * np.cos(th), (R_A + r_A * c) * np.sin(th), r_A * s], 1)
    rng = np.random.default_rng(seed)
    L = N_BP * RISE_A
    k = np.arange(int(L / LP_A), N_BP // 2)
    coef = rng.standard_normal((2, len(k), 3)) / k[None, :, None] ** 2
    noise = (np.cos(np.outer(th, k)) @ coef[0] + np.sin(np.outer(th, k)) @ coef[1])
    tangent = np.roll(x, -1, 0) - np.roll(x, 1, 0)
    tangent /= np.linalg.norm(tangent, axis=1)[:, None]
    noise -= np.sum(noise * tangent, axis=1)[:, None] * tangent     # transverse, as a bent chain's
    x0 = x.copy()

    def bend_rms(y):
        e = np.roll(y, -1, 0) - y
        e /= np.linalg.norm(e, axis=1)[:, None]
        return np.sqrt(np.mean(np.arccos(np.clip(np.sum(e * np.roll(e, -1, 0), axis=1), -1, 1)) ** 2))
    target = np.sqrt(2 * RISE_A / LP_A)
    scale = 1.0
    for _ in range(30):                       # bend_rms grows ~ linearly in the scale
        y = x0 + scale * noise
        scale *= target / bend_rms(y)
    x = x0 + scale * noise
    x *= L / np.sum(np.linalg.norm(np.roll(x, -1, 0) - x, axis=1))   # contour length N_BP * rise
    # a ribbon turning once per 10.5 bp about the local tangent (the torus normal, turned)
    nu = np.stack([c * np.cos(th), c * np.sin(th), s], 1)
    phase = 2 * np.pi * np.arange(N_BP) / 10.5
    b = np.cross(np.roll(x, -1, 0) - np.roll(x, 1, 0), nu)
    b /= np.linalg.norm(b, axis=1)[:, None]
    d1 = np.cos(phase)[:, None] * nu + np.sin(phase)[:, None] * b
    return x, d1, float(bend_rms(x))


def cpu(f, *a, **k):
    t = time.process_time()
    out = f(*a, **k)
    return out, time.process_time() - t


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--strides", type=int, nargs="+", default=[5, 11, 21, 41])
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results")
    a = ap.parse_args()
    rows = []
    for seed in a.seeds:
        x, d1, bend = supercoil(seed)
        full, t_full = cpu(polygon_writhe, x)
        row = {"seed": seed, "n_points": N_BP, "bend_rms_rad": bend, "Wr_full": full, "cpu_s_full": t_full,
               "coarsened": []}
        for k in a.strides:
            wk, tk = cpu(writhe, x, k)
            chords, tc = cpu(polygon_writhe, x[::k])
            row["coarsened"].append({"stride": k, "points": len(x[::k]), "Wr": wk, "cpu_s": tk,
                                     "error": wk - full, "Wr_coarsening": wk - writhe(x, 2 * k),
                                     "chords_only_error": chords - full, "chords_only_cpu_s": tc})
        r, t_frame = cpu(ribbon_topology, x, d1, None, 11)    # stride 11: 955 points, as the command
        # rodsim's frame of a closed rod: the same without the stride-22 estimate
        _, t_rodsim = cpu(rodcore_module().topology.ribbon_topology, x, d1, None, 11, False)
        t = centred_tangents(x)
        u = perpendicular_unit(d1, t)
        _, t_lk = cpu(linking_number, x, x + 0.25 * RISE_A * u)
        _, t_tw = cpu(twist, t, u)
        row.update(frame={"Lk": r["Lk"], "Tw": r["Tw"], "Wr": r["Wr"],
                          "Lk_minus_Tw_minus_Wr": r["Lk"] - r["Tw"] - r["Wr"],
                          "Lk_minus_Tw_minus_Wr_full_writhe": r["Lk"] - r["Tw"] - full,
                          "cpu_s_frame_stride_11": t_frame, "cpu_s_frame_rodsim": t_rodsim,
                          "cpu_s_Lk": t_lk, "cpu_s_Tw": t_tw})
        rows.append(row)
        f = row["frame"]
        print(f"seed {seed}: Wr {full:.4f} ({t_full:.1f} CPU s, {N_BP} points), bend {bend:.3f} rad; "
              + ", ".join(f"k={c['stride']}: err {c['error']:+.4f} ({c['cpu_s']:.2f} s, dWr "
                          f"{c['Wr_coarsening']:+.4f}; chords only {c['chords_only_error']:+.4f})"
                          for c in row["coarsened"])
              + f"; frame {t_frame:.2f} s (rodsim's {t_rodsim:.2f} s; Lk {t_lk:.3f} s, Tw {t_tw:.4f} s), Lk - Tw - Wr "
                f"{f['Lk_minus_Tw_minus_Wr']:+.4f} (full writhe {f['Lk_minus_Tw_minus_Wr_full_writhe']:+.2e})")
    summary = {}
    for k in a.strides:
        pick = (lambda key: np.array([c[key] for r in rows for c in r["coarsened"] if c["stride"] == k]))
        errs, cpus, chords = pick("error"), pick("cpu_s"), pick("chords_only_error")
        summary[str(k)] = {"max_abs_error": float(np.abs(errs).max()),
                           "rms_error": float(np.sqrt(np.mean(errs ** 2))),
                           "max_abs_Wr_coarsening": float(np.abs(pick("Wr_coarsening")).max()),
                           "chords_only_max_abs_error": float(np.abs(chords).max()),
                           "mean_cpu_s": float(cpus.mean()),
                           "speedup": float(np.mean([r["cpu_s_full"] for r in rows]) / cpus.mean())}
    a.out.mkdir(parents=True, exist_ok=True)
    write_json(a.out / "topology.json", {"curve": __doc__.split("\n\n")[1], "rows": rows, "by_stride": summary})
    print(f"wrote {a.out / 'topology.json'}")


if __name__ == "__main__":
    main()
