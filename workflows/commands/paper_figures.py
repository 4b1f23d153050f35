"""`dnarod paper-figures`: regenerate the paper's Figs 1-7 and the quantitative checks of
docs/reproduction.md from real simulations (rodcore) and the closed-form results."""
from __future__ import annotations

import sys
import time

from dnarod.commands._options import add_output

NAME = "paper-figures"
HELP = "regenerate the paper's Figs 1-7 and the reproduction checks (PNG + JSON)"


def _description():
    from dnarod.paper.registry import TARGETS
    lines = "\n".join(f"  {k:<17} {v[0]}" for k, v in TARGETS.items())
    return f"""\
Regenerate the equivalents of the paper's figures, each from a real rod simulation
(rodcore) or from the closed-form results, with a JSON file of the numbers behind it,
and the quantitative checks tabulated in docs/reproduction.md.

targets (default: all):
{lines}

Every target writes OUT/<target>.json (and a PNG where there is a picture). --quick
uses coarser grids, fewer frames and shorter runs (for tests; the numbers are then
less precise). The full set takes a few minutes on 2 cores (wavespeed is the
longest: 600 ps of the 158-bp scene plus three long runs at different kicks).

examples:
  dnarod paper-figures -o paper_out
  dnarod paper-figures -o /tmp/figs --only fig3 fig6 --quick
"""


DESCRIPTION = None  # filled lazily below (argparse reads it when the parser is built)


def add_arguments(p):
    from dnarod.paper.registry import TARGETS
    p.description = _description()
    add_output(p, metavar="DIR", help="output folder (created)")
    p.add_argument("--only", nargs="+", metavar="TARGET", choices=list(TARGETS),
                   help="make only these targets (see the list above)")
    p.add_argument("--figures", action="store_true", help="only the seven figures (fig1 ... fig7)")
    p.add_argument("--quick", action="store_true", help="coarse and short runs (tests, previews)")


def run(args):
    import matplotlib
    matplotlib.use("Agg")
    from dnarod.paper.registry import FIGURES, TARGETS
    from dnarod import validate
    out = validate.output_folder(args.output)
    names = args.only or (FIGURES if args.figures else list(TARGETS))
    for name in names:
        t0 = time.time()
        TARGETS[name][1](out, args.quick)
        made = ", ".join(sorted(p.name for p in out.glob(f"{name}*") if p.suffix in (".png", ".json")))
        print(f"{name:<17} {time.time() - t0:6.1f} s  {made}", file=sys.stderr)
    return 0
