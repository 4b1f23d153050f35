"""Verify by code that each ring junction carries exactly the terms of an interior step.

A strand closed across the periodic boundary must be chemically identical to
an infinite strand: the bonded terms that couple its last residue to its first
must be the same, term for term, as those that couple residue i to residue
i+1 inside the strand. We compare, per kind (bonds, pairs, angles, proper and
improper dihedrals, cmap), the multiset of atom-name patterns
((name, 0|1), ...) where 0 marks the 5' residue of the step and 1 the 3' one.
For charmm27 an interior DNA step has 1 bond (O3'-P), 4 angles, 7 proper
dihedrals and 7 pairs (19 terms).
"""
from __future__ import annotations

from collections import Counter

import numpy as np

from dna_models.units import ANGSTROM_PER_NM as NM

from .topology import Molecule

KINDS = ("bonds", "pairs", "angles", "proper_dihedrals", "improper_dihedrals", "cmap")


def _terms_by_step(mol: Molecule, steps: list[tuple[int, int]]) -> list[dict[str, Counter]]:
    """For each step (a, b) (a 5' of b): per kind, the Counter of term patterns that
    involve atoms of both residues a and b and of no other residue. One pass over all
    terms (a 158-bp strand has ~10^4 of them)."""
    index = {step: n for n, step in enumerate(steps)}
    out: list[dict[str, Counter]] = [{k: Counter() for k in KINDS} for _ in steps]
    resnr = mol.resnr
    for kind, terms in mol.terms.items():
        if not terms:
            continue
        atoms = np.asarray(terms) - 1
        res = resnr[atoms]                                   # (n_terms, n_atoms)
        lo, hi = res.min(axis=1), res.max(axis=1)
        two = np.all((res == lo[:, None]) | (res == hi[:, None]), axis=1) & (lo != hi)
        for t in np.flatnonzero(two):
            r = set(res[t].tolist())
            step = next((st for st in ((lo[t], hi[t]), (hi[t], lo[t])) if st in index), None)
            if step is None or set(step) != r:
                continue
            a = step[0]
            pattern = tuple((mol.atomname[i], 0 if resnr[i] == a else 1) for i in atoms[t])
            # a term and its reverse are the same interaction
            out[index[step]][kind][min(pattern, pattern[::-1])] += 1
    return out


def junction_report(mol: Molecule) -> dict:
    """Compare the last->first junction of a cyclic strand with every interior step.

    Returns counts per kind for the junction and the interior steps, and ok=True only
    if the junction's term patterns equal those of every interior step."""
    res = mol.residues
    if len(res) < 3:
        return {"molecule": mol.name, "ok": False, "reason": "fewer than 3 residues"}
    steps = [(int(a), int(b)) for a, b in zip(res[:-1], res[1:])] + [(res[-1], res[0])]
    per_step = _terms_by_step(mol, steps)
    interior, junction = per_step[:-1], per_step[-1]
    ref = interior[0]
    interior_uniform = all(step == ref for step in interior)
    counts = {k: sum(junction[k].values()) for k in KINDS}
    interior_counts = {k: sum(ref[k].values()) for k in KINDS}
    ok = interior_uniform and junction == ref and counts["bonds"] == 1
    mismatch = []
    if not ok:
        for k in KINDS:
            missing = ref[k] - junction[k]
            extra = junction[k] - ref[k]
            if missing or extra:
                mismatch.append({"kind": k, "missing": [list(p) for p in missing],
                                 "extra": [list(p) for p in extra]})
    return {"molecule": mol.name, "first_residue": res[0], "last_residue": res[-1],
            "junction_counts": counts, "interior_counts": interior_counts,
            "junction_total": sum(counts.values()), "interior_uniform": interior_uniform,
            "ok": ok, "mismatch": mismatch}


def o3p_links(x_nm, resid, names, n_bp: int, box_nm) -> dict:
    """Minimum-image O3'(i)-P(i+1) lengths in A: the two junction links and the interior range."""
    box = np.asarray(box_nm, float)
    where = {(int(r), str(a)): k for k, (r, a) in enumerate(zip(resid, names))}
    out = {}
    for strand, first, last in (("I", 1, n_bp), ("II", n_bp + 1, 2 * n_bp)):
        lengths = []
        for r in range(first, last + 1):
            nxt = first if r == last else r + 1
            d = x_nm[..., where[(nxt, "P")], :] - x_nm[..., where[(r, "O3'")], :]
            d = d - box * np.round(d / box)
            lengths.append(np.linalg.norm(d, axis=-1) * NM)
        L = np.array(lengths)          # (n_bp, [T])
        out[strand] = {"junction_A": L[-1], "interior_A": L[:-1]}
    return out


def _offset(r: int, a: int, n_res: int) -> int:
    """Residue r relative to residue a on a ring of n_res residues, in (-n_res/2, n_res/2]."""
    d = (r - a) % n_res
    return d - n_res if d > n_res // 2 else d


def step_signature(mol, a: int) -> dict:
    """Everything mdrun computes for the step from residue a to a + 1 (cyclic) of a dump's
    moltype (tpr_dump.MolType), in names and residue offsets relative to a, free of atom
    numbers: the two residues' atoms (name, type, charge, mass), the exclusions of their
    atoms, and every interaction that touches both, with its resolved parameters."""
    n_res = len(mol.resname)
    res = {a % n_res, (a + 1) % n_res}
    mine = [i for i, r in enumerate(mol.resind) if r in res]

    def tag(i):
        return (mol.atomname[i], _offset(mol.resind[i], a, n_res))
    atoms = sorted((tag(i), mol.type[i], round(mol.charge[i], 6), round(mol.mass[i], 4)) for i in mine)
    excls = sorted((tag(i), tuple(sorted(tag(j) for j in mol.excls.get(i, ())))) for i in mine)
    terms = []
    for kind, ft, at in mol.interactions:
        rs = {mol.resind[i] for i in at}
        if res <= rs:
            pattern = tuple(tag(i) for i in at)
            terms.append((kind, ft, min(pattern, pattern[::-1])))
    return {"resnames": (mol.resname[a % n_res], mol.resname[(a + 1) % n_res]),
            "atoms": atoms, "exclusions": excls, "interactions": sorted(terms)}


def junction_parameters(dump) -> list[dict]:
    """Per strand (moltype) of a dump (tpr_dump.Dump): the junction step (last residue ->
    first) against every interior step with the same two bases, on everything mdrun
    computes (step_signature; interactions compared by their resolved parameters, since
    equal functype indices are equal parameters). ok: the junction equals every such step,
    and there is at least one to compare with."""
    out = []
    for mol in dump.moltypes:
        n_res = len(mol.resname)
        junction = step_signature(mol, n_res - 1)
        same = [a for a in range(n_res - 1)
                if (mol.resname[a], mol.resname[a + 1]) == junction["resnames"]]
        differing: dict[str, list[int]] = {}
        for a in same:
            sig = step_signature(mol, a)
            for k in ("atoms", "exclusions", "interactions"):
                if sig[k] != junction[k]:
                    differing.setdefault(k, []).append(a)
        n_terms = len(junction["interactions"])
        out.append({"molecule": mol.name, "junction_bases": "-".join(junction["resnames"]),
                    "interior_steps_compared": len(same), "n_interactions": n_terms,
                    "n_exclusion_lists": len(junction["exclusions"]),
                    "differs_from_steps": differing,
                    "ok": bool(same) and not differing})
    return out
