"""The screen of the ways to keep the 158-bp duplex intact (docs/intact.md).

Each candidate is a short run of the same build (sequence, seed, v-rescale 300 K, 2 fs) as
the full-charge vacuum reference: `--hold-pairs` (flat-bottomed restraints, same force
field) and `--electrostatics neutral-phosphates` (a different force field). For each run,
over one common window of time:

- the open fraction (N1-N3 > 3.5 A) over all pairs, at the junction and in the interior;
- each H-bond kind's distance distribution in the held run, which sets the flat bottoms;
- what it changes in the elasticity: the mean and the variance of each step parameter over
  the steps and frames whose two pairs are closed (a local stiffness is kT over a variance),
  as ratios to the full-charge reference;
- with --hold-pairs, the restraint energy per frame.

    python3 bench/pair_hold_screen.py --reference DIR --candidate NAME=DIR ... \
        --from-ps 20 --to-ps 150 -o results/dispersion/intact/screen.json

The runs may still be going (their md.part.* files are read).
"""
from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

import numpy as np

from dna_models.nucleotides import WATSON_CRICK_HBONDS
from mdbridge.geometry.steps import STEP_NAMES
from mdbridge.jsonio import write_json
from mdbridge.md.integrity import INTACT_CUTOFF_A, PairIntegrity, integrity_summary


def _universe(d: Path):
    import MDAnalysis as mda
    for tpr, xtc in (("md.tpr", "md.xtc"), ("md.part.tpr", "md.part.xtc")):
        if (d / tpr).is_file() and (d / xtc).is_file():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                return mda.Universe(str(d / tpr), str(d / xtc))
    raise SystemExit(f"{d}: no md.tpr + md.xtc nor md.part.tpr + md.part.xtc")


def read_run(d: Path, t0: float, t1: float, stride: int) -> dict:
    """Pair distances, H-bond distances and step parameters of the frames in [t0, t1]."""
    from mdbridge.geometry.structure import BasePairFrames
    from mdbridge.md.builder.duplex import base_pairs
    build = json.loads((d / "build.json").read_text())
    n = int(build["n_bp"])
    u = _universe(d)
    res = {int(r.resid): r for r in u.residues}
    pairs = [(res[i], res[j]) for i, j in base_pairs(n)]
    times = np.array([ts.time for ts in u.trajectory])
    frames = np.flatnonzero((times >= t0 - 1e-6) & (times <= t1 + 1e-6))[::stride]
    hb = PairIntegrity(u, pairs, hbonds=True).run(frames=frames)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bpf = BasePairFrames(u, pairs=base_pairs(n)).run(frames=frames)
    q = bpf.step_parameters(periodic=True)
    return {"times_ps": times[frames], "n1_n3": hb.results.distance_A, "hbond": hb.results.hbond_distance_A,
            "hbond_names": ["-".join(x) for x in hb.hbond_names], "q": q, "build": build, "n_bp": n}


def elasticity(run: dict) -> dict:
    """Mean and variance of each step parameter over the (step, frame)s whose pairs are both
    closed, twist unwrapped in time."""
    from mdbridge.geometry.steps import twist_continuous_in_time
    q = twist_continuous_in_time(run["q"])
    closed = run["n1_n3"] <= INTACT_CUTOFF_A                     # (T, n)
    ok = closed & np.roll(closed, -1, axis=1)                   # step k joins pairs k, k+1
    out = {}
    for j, name in enumerate(STEP_NAMES):
        x = q[..., j]
        m = np.array([x[ok[:, k], k].mean() if ok[:, k].sum() > 2 else np.nan for k in range(x.shape[1])])
        v = np.array([x[ok[:, k], k].var(ddof=1) if ok[:, k].sum() > 2 else np.nan for k in range(x.shape[1])])
        out[name] = {"mean": m, "variance": v}
    out["closed_step_frames"] = float(ok.mean())
    return out


def junction_by_site(runs: dict) -> dict:
    """Is it the junction or its sequence? For every run whose sequence is the reference's
    turned by K base pairs (its pair p is the reference's pair p + K), the open fraction of
    the reference's junction site (now inside the duplex) and of its own junction (now on
    another sequence), against its interior."""
    ref = runs["full_charge"]
    seq0, n = ref["sequence"], len(ref["sequence"])
    out = {}
    for k, r in runs.items():
        seq = r["sequence"]
        turns = [K for K in range(n) if seq0[K:] + seq0[:K] == seq]
        if not turns or turns[0] == 0:
            continue
        K = turns[0]
        per = np.asarray(r["open_fraction_per_pair"])
        site = [(p - K) % n for p in (n - 2, n - 1, 0, 1)]       # the reference junction's pairs
        own = [n - 2, n - 1, 0, 1]
        rest = np.setdiff1d(np.arange(n), site + own)
        out[k] = {"rotation_bp": K, "reference_junction_site_pairs": site,
                  "reference_junction_site_open_fraction": float(per[site].mean()),
                  "own_junction_open_fraction": float(per[own].mean()),
                  "elsewhere_open_fraction": float(per[rest].mean())}
    return out


def junction_geometry(d: Path) -> dict:
    """The junction step's parameters after the restrained minimisation (DIR/em_whole.gro),
    as z-scores against the interior steps' spread."""
    import MDAnalysis as mda
    from mdbridge.geometry.structure import BasePairFrames
    from mdbridge.md.builder.duplex import base_pairs
    n = int(json.loads((d / "build.json").read_text())["n_bp"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        u = mda.Universe(str(d / "em_whole.gro"))
        bpf = BasePairFrames(u, pairs=base_pairs(n)).run()
    q = bpf.step_parameters(periodic=True)[0]              # (n, 6); step n-1 is the junction
    inner = q[:-1]
    z = (q[-1] - inner.mean(axis=0)) / inner.std(axis=0)
    return {"md_dir": str(d), "junction_step": q[-1].tolist(), "interior_mean": inner.mean(axis=0).tolist(),
            "interior_sd": inner.std(axis=0).tolist(), "z": dict(zip(STEP_NAMES, z.tolist())),
            "max_abs_z": float(np.abs(z).max())}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reference", required=True, type=Path, help="the full-charge vacuum run")
    ap.add_argument("--candidate", action="append", default=[], metavar="NAME=DIR")
    ap.add_argument("--from-ps", type=float, default=20.0)
    ap.add_argument("--to-ps", type=float, required=True)
    ap.add_argument("--stride", type=int, default=2, help="every STRIDE-th frame")
    ap.add_argument("--junction-geometry", type=Path, action="append", default=[], metavar="DIR",
                    help="a build whose junction step after minimisation is compared with its interior")
    ap.add_argument("-o", "--out", type=Path, required=True)
    a = ap.parse_args(argv)
    runs = {"full_charge": a.reference}
    runs.update({c.split("=", 1)[0]: Path(c.split("=", 1)[1]) for c in a.candidate})
    data = {k: read_run(d, a.from_ps, a.to_ps, a.stride) for k, d in runs.items()}
    el = {k: elasticity(r) for k, r in data.items()}
    out: dict = {"command": "python3 bench/pair_hold_screen.py " + " ".join(sys.argv[1:] if argv is None else argv),
                 "window_ps": [a.from_ps, a.to_ps], "runs": {}}
    for k, r in data.items():
        s = integrity_summary(r["n1_n3"], r["times_ps"])
        rec = {"md_dir": str(runs[k]), "frames": len(r["times_ps"]),
               "times_ps": [float(r["times_ps"][0]), float(r["times_ps"][-1])],
               "electrostatics": r["build"].get("electrostatics"), "pair_hold": r["build"].get("pair_hold"),
               "open_fraction": s["open_fraction"],
               "open_fraction_last_frame": s["open_fraction_time"][-1],
               "junction_open_fraction": s["junction_open_fraction"],
               "interior_open_fraction": s["interior_open_fraction"],
               "most_open_pairs": np.argsort(s["open_fraction_per_pair"])[::-1][:10].tolist(),
               "open_fraction_per_pair": s["open_fraction_per_pair"],
               "sequence": r["build"]["sequence"],
               "closed_step_frames": el[k]["closed_step_frames"]}
        names = np.array(r["hbond_names"])
        hb = {}
        for nm in sorted(set(names)):
            x = r["hbond"][:, names == nm]
            hb[nm] = {"mean_A": float(x.mean()), "sd_A": float(x.std()),
                      "p99_A": float(np.percentile(x, 99)), "fraction_above_3.3_A": float((x > 3.3).mean())}
        rec["hbond_distances"] = hb
        if k != "full_charge":
            rec["vs_full_charge"] = {}
            for name in STEP_NAMES:
                ratio = el[k][name]["variance"] / el["full_charge"][name]["variance"]
                dmean = el[k][name]["mean"] - el["full_charge"][name]["mean"]
                good = np.isfinite(ratio)
                rec["vs_full_charge"][name] = {
                    "variance_ratio_median": float(np.median(ratio[good])),
                    "variance_ratio_mean": float(np.mean(ratio[good])),
                    "variance_ratio_sem": float(np.std(ratio[good], ddof=1) / np.sqrt(good.sum())),
                    "mean_shift_median": float(np.median(dmean[good])), "steps": int(good.sum())}
        out["runs"][k] = rec
    out["junction_by_site"] = junction_by_site(out["runs"])
    out["junction_geometry"] = [junction_geometry(d) for d in a.junction_geometry]
    out["hbond_pairs"] = {p: ["-".join(x) for x in WATSON_CRICK_HBONDS[p]] for p in WATSON_CRICK_HBONDS}
    write_json(a.out, out)
    for k, rec in out["runs"].items():
        print(f"{k}: open {rec['open_fraction']:.3f} (junction {rec['junction_open_fraction']:.3f}, interior "
              f"{rec['interior_open_fraction']:.3f}); " + "; ".join(
                  f"{n} var x{v['variance_ratio_median']:.2f}" for n, v in rec.get("vs_full_charge", {}).items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
