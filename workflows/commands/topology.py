"""`dnarod topology`: linking number, twist and writhe per frame of rod runs and MD
folders (mdbridge.rod.topology, mdbridge.md.topology; docs/topology.md)."""
from __future__ import annotations

from pathlib import Path

NAME = "topology"
HELP = "linking number, twist and writhe per frame of rod HDF5 files and MD folders"
DESCRIPTION = """\
Lk, Tw and Wr (Lk = Tw + Wr) of every frame of each PATH, written to
DIR/topology.json (per PATH: time_ps, Lk, Tw, Wr, and Lk_minus_Tw_minus_Wr_max).

  a rod HDF5 file (rodsim run; needs output.fields "centerline" and "directors",
      and "internal" for a periodic rod): the centreline and the ribbon along d1
      perpendicular to the tangent; the writhe of a ring coarsened to at most
      --writhe-points blocks (Klenin-Langowski: near pairs exact, far ones by chords)
  an MD folder (dnarod build-md: md.tpr + md.xtc, else conf.gro): Lk of the two
      C1' strands, Tw and Wr about the axis averaged over one helical turn

A rod closed into a ring and a DNA ring have the usual Lk, Tw, Wr. A box-periodic
rod or duplex (ligated across the box, as build-md makes it) gets the convention
of docs/topology.md: the box axis closed far away without twist; Tw and Wr are
per period, Wr relative to the straight box axis.

The decomposition must hold: a frame with |Lk - Tw - Wr| >= 0.5 (the integer Lk
is not what twist and writhe add to: an under-resolved rod, a melted duplex) is
an error, after the file is written.

examples:
  dnarod topology ring.h5 -o topo
  dnarod topology rod/Av5/rod.h5 md/Av5_seed1 -o topo --writhe-points 2000
"""


def add_arguments(p):
    from dnarod import validate
    from dnarod.commands._options import add_output
    p.add_argument("paths", nargs="+", metavar="PATH", help="rod HDF5 files and MD folders")
    add_output(p, metavar="DIR", help="output folder (DIR/topology.json)")
    p.add_argument("--writhe-points", type=validate.integer(min=8), default=None, metavar="M",
                   help="the writhe of a closed rod coarsened to at most M blocks (default 1000: "
                        "0.02 CPU s and within 0.04 of the exact writhe at 10.5 kbp)")


def _inputs(paths, writhe_points):
    """(path, kind, reader) of each PATH, everything checked before any work starts."""
    from mdbridge.md.realisation import open_realisation
    from mdbridge.rod.topology import WRITHE_POINTS, writhe_stride
    writhe_stride(1, WRITHE_POINTS if writhe_points is None else writhe_points)
    out = []
    for p in map(Path, paths):
        r = open_realisation(p)
        if r.run is not None:
            r.run.require("time", "s", "centerline", "directors")
        out.append((p, r.kind, r.run))
    return out


def run(args):
    import numpy as np

    from dna_models.errors import NumericalError
    from mdbridge.jsonio import write_json
    from mdbridge.md.topology import md_topology
    from mdbridge.rod.topology import WRITHE_POINTS, rod_topology

    points = WRITHE_POINTS if args.writhe_points is None else args.writhe_points
    from dnarod import validate
    inputs = _inputs(args.paths, args.writhe_points)
    out = validate.output_folder(args.output, command="topology")
    results, bad = {}, []
    for path, kind, run_ in inputs:
        r = rod_topology(run_, points) if kind == "rod" else md_topology(path)
        Lk, Tw, Wr = (np.asarray(r[k], float) for k in ("Lk", "Tw", "Wr"))
        residual = np.abs(Lk - Tw - Wr)
        r = dict(kind=kind, **r, Lk_minus_Tw_minus_Wr_max=float(residual.max()),
                 Lk_changes=int(np.count_nonzero(np.diff(Lk))),
                 convention="closed" if r["closed"] else "box-periodic: per period, axis closed far away "
                                                        "without twist (docs/topology.md)")
        results[str(path)] = r
        if residual.max() >= 0.5:
            f = int(residual.argmax())
            bad.append(f"{path}: frame {f} (t = {r['time_ps'][f]:.3f} ps) has Lk = {Lk[f]:.0f} but Tw + Wr = "
                       f"{Tw[f] + Wr[f]:.3f}")
        # each frame's Lk, Tw and Wr together: the first and the last
        print(f"{path}: {kind}, {'closed' if r['closed'] else 'box-periodic'}, {len(Lk)} frames; "
              f"first frame Lk {Lk[0]:.0f}, Tw {Tw[0]:.4f}, Wr {Wr[0]:.4f}; "
              f"last frame Lk {Lk[-1]:.0f}, Tw {Tw[-1]:.4f}, Wr {Wr[-1]:.4f}; "
              f"max |Lk - Tw - Wr| {residual.max():.2e}")
    write_json(out / "topology.json", {"format": "dnarod-topology/1", "paths": results})
    print(f"wrote {out / 'topology.json'}")
    if bad:
        raise NumericalError("Lk = Tw + Wr fails (|Lk - Tw - Wr| >= 0.5): " + "; ".join(bad)
                             + ". A rod: raise rod.points or --writhe-points; an MD duplex: are the strands "
                               "still paired? (docs/topology.md)")
    return 0
