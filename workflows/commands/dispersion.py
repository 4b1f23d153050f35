"""`dnarod dispersion`: the bend-shear dispersion relation of the paper, Eqs (26)/(39),
as CSV (and the shear/bend ratios of Eq 27 and Fig 5)."""
from __future__ import annotations

import csv
import sys

import numpy as np

from dna_models.errors import InputError
from dnarod import validate

NAME = "dispersion"
HELP = "bend-shear wave frequencies omega_+/- of a straight rod (paper Eqs 26, 39) as CSV"
DESCRIPTION = """\
Frequencies of the large-amplitude bend-shear waves of an intrinsically straight
rod, in the paper's dimensionless units (time tau, length l; Sec 2.2):

  omega_+/-(kappa) = 1/2 { sqrt(kappa^2 (sqrt D1 + 1)^2 + Gamma03^2)
                           +/- sqrt(kappa^2 (sqrt D1 - 1)^2 + Gamma03^2) }   (Eqs 26, 39)

--kappa K ...   untwisted rod (Eq 39, kappa = k) or any modified wavenumber; prints
                kappa,omega_minus,omega_plus
--k K ...       twisted rod with intrinsic twist --Omega03: the modified wavenumbers
                kappa_p = k + Omega03, kappa_m = k - Omega03 (Eq 24) and the four
                branches; prints k,kappa_p,kappa_m,omega_minus_p,omega_plus_p,
                omega_minus_m,omega_plus_m
--ratios        add, per branch, the shear/bend elastic energy ratio of Eq (27),
                Gamma_perp^2 / (D1 Omega_perp^2) = (w^2 - D1 kappa^2)^2 / (D1 kappa^2 Gamma03^2),
                and the amplitude ratio of Fig 5, |Gamma1| / |Omega2| = |w^2 - D1 kappa^2| /
                (|kappa| Gamma03) (from Eqs 40-43; for the twisted rod the same ratio of
                |Gamma_perp| / |Omega_perp| from Eq 24)

A wavenumber may be a number or a range START:STOP:NUM (NUM equally spaced values).
omega_- is the bend branch and omega_+ the shear branch for kappa -> 0; for
kappa -> infinity (and D1 > 1) omega_+ ~ sqrt(D1) kappa is bend and omega_- ~ kappa shear.

examples:
  dnarod dispersion --kappa 0.5 1 2
  dnarod dispersion --kappa 0:10:101 --ratios > fig1_untwisted.csv
  dnarod dispersion --k 0:4:81 --Omega03 1 --ratios
"""


def _wavenumbers(values, flag):
    out = []
    for v in values:
        try:
            if ":" in v:
                a, b, n = v.split(":")
                n = int(n)
                if n < 1:
                    raise ValueError
                out += list(np.linspace(float(a), float(b), n))
            else:
                out.append(float(v))
        except ValueError:
            raise InputError(f"{flag} {v!r}: expected a number or START:STOP:NUM "
                             "(NUM a positive integer)") from None
    if not all(np.isfinite(out)):
        bad = next(v for v in values if not all(np.isfinite(_wavenumbers_of(v))))
        raise InputError(f"{flag} {bad}: not a finite number (wavenumbers must be finite)")
    return np.array(out, float)


def _wavenumbers_of(v: str) -> list:
    if ":" in v:
        a, b, n = v.split(":")
        return list(np.linspace(float(a), float(b), int(n)))
    return [float(v)]


def add_arguments(p):
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--kappa", nargs="+", metavar="K",
                   help="(modified) wavenumbers kappa, dimensionless (1/l)")
    g.add_argument("--k", nargs="+", metavar="K",
                   help="wavenumbers k of a twisted rod (use with --Omega03)")
    p.add_argument("--Gamma03", type=float, default=1.0, help="intrinsic extension Gamma03 (default 1)")
    from dnarod.paper.theory import D1_PAPER
    p.add_argument("--D1", type=float, default=D1_PAPER,
                   help=f"dimensionless bend stiffness D1 = D rho / (I C) (default {D1_PAPER:g}, "
                        "paper Sec 2.2)")
    p.add_argument("--Omega03", type=float, default=None,
                   help="intrinsic twist Omega03 (with --k; default 0)")
    p.add_argument("--ratios", action="store_true",
                   help="also print the Eq (27) energy ratios and the Fig 5 ratios |Gamma1|/|Omega2|")
    p.add_argument("--precision", type=validate.integer(min=1), default=10, help="significant digits (default 10)")


def table(args):
    """(header, rows) of the CSV for parsed arguments."""
    from dnarod.paper import theory
    if args.D1 <= 0 or not np.isfinite(args.D1):
        raise InputError(f"--D1 {args.D1}: must be a positive number")
    if not np.isfinite(args.Gamma03) or args.Gamma03 <= 0:
        raise InputError(f"--Gamma03 {args.Gamma03}: must be a positive number")
    D1, G = args.D1, args.Gamma03
    if args.kappa is not None:
        if args.Omega03 is not None:
            raise InputError("--Omega03 applies to --k (twisted rod); with --kappa give the modified "
                             "wavenumber kappa = k +- Omega03 directly")
        kappa = _wavenumbers(args.kappa, "--kappa")
        cols = {"kappa": kappa}
        for b in ("minus", "plus"):
            cols[f"omega_{b}"] = theory.omega(kappa, b, D1, G)
        if args.ratios:
            for b in ("minus", "plus"):
                cols[f"energy_ratio_{b}"] = theory.energy_ratio(cols[f"omega_{b}"], kappa, D1, G)
            for b in ("minus", "plus"):
                cols[f"shear_bend_{b}"] = theory.shear_bend_amplitude_ratio(cols[f"omega_{b}"], kappa, D1, G)
    else:
        O3 = 0.0 if args.Omega03 is None else args.Omega03
        if not np.isfinite(O3):
            raise InputError("--Omega03 must be finite")
        k = _wavenumbers(args.k, "--k")
        kp, km = theory.modified_wavenumbers(k, O3)
        cols = {"k": k, "kappa_p": kp, "kappa_m": km}
        for pm, kap in (("p", kp), ("m", km)):
            for b in ("minus", "plus"):
                cols[f"omega_{b}_{pm}"] = theory.omega(kap, b, D1, G)
        if args.ratios:
            for pm, kap in (("p", kp), ("m", km)):
                for b in ("minus", "plus"):
                    cols[f"energy_ratio_{b}_{pm}"] = theory.energy_ratio(cols[f"omega_{b}_{pm}"], kap, D1, G)
            for pm, kap in (("p", kp), ("m", km)):
                for b in ("minus", "plus"):
                    cols[f"shear_bend_{b}_{pm}"] = theory.shear_bend_amplitude_ratio(
                        cols[f"omega_{b}_{pm}"], kap, D1, G)
    _check_finite(cols, "--kappa" if args.kappa is not None else "--k")
    header = list(cols)
    rows = np.column_stack([np.broadcast_to(np.asarray(cols[h], float), (len(next(iter(cols.values()))),))
                            for h in header])
    return header, rows


def _check_finite(cols: dict, flag: str) -> None:
    """Every printed number finite, except the ratios at a zero wavenumber (0/0, documented):
    a wavenumber too large for double precision gives inf or nan, refused here."""
    wavenumber = cols.get("kappa", cols.get("k"))
    for name, values in cols.items():
        values = np.asarray(values, float)
        bad = ~np.isfinite(values)
        if name.startswith(("energy_ratio", "shear_bend")):
            q = cols["kappa"] if "kappa" in cols else cols["kappa_" + name.rsplit("_", 1)[1]]
            bad &= np.asarray(q, float) != 0
        if bad.any():
            i = int(np.argmax(bad))
            raise InputError(f"{flag} {wavenumber[i]:g}: {name} = {values[i]} is not a finite number (the "
                             "wavenumber is beyond double precision's range); give smaller wavenumbers")


def run(args):
    header, rows = table(args)
    w = csv.writer(sys.stdout, lineterminator="\n")
    w.writerow(header)
    p = args.precision
    for r in rows:
        # kappa = 0 gives 0/0 in the ratios: printed as inf/nan, which CSV readers accept.
        w.writerow([f"{x:.{p}g}" for x in r])
    return 0
