"""An MD build of a minicircle: the all-atom DNA ring on the base-pair frames of a rod ring
(`dnarod minicircle`; docs/builder.md, "Rings closed in space").

1. The rod ring at one output frame on its base pairs (gromacs/rod.py rod_initial_from_run,
   as build-md samples it: base pair i on grid point i N / n_bp, no interpolation).
2. The duplex built on those frames with each strand closed in space (build_duplex(...,
   ring=True): strand I's last O3' bonded to its first P, strand II likewise) and its
   O3'-P links closed and checked (builder/backbone.py).
3. The linking number of the two built strands, as C1' and as P polygons
   (mdbridge.geometry.topology.linking_number, both ordered along strand I), must be the
   rod's: the DNA ring is the same topological object as the rod ring.
4. The GROMACS inputs (gromacs/inputs.py build_inputs, as for the periodic duplex, with
   periodic-molecules = no in a box that keeps every image beyond the cut-off:
   gromacs/box.py plan_ring_box); pdb2gmx closes both strands into rings because each
   strand's last O3' lies within -lb of its first P, and the junction check proves the
   closing step carries exactly an interior step's bonded terms. The C1' Lk of the written
   conf.gro (mdbridge.md.topology, the path `dnarod topology` reads) must again be the rod's.
5. The atoms must be usable: rigid nucleotide templates on a bent, sheared rod put atoms of
   neighbouring nucleotides on top of each other, so the ring is minimised (restrained, as
   build-md --minimize) unless asked not to, and conf.gro's closest non-bonded pairs
   (gromacs/clashes.py: any atoms closer than CLASH_A, heavy atoms closer than HEAVY_CLASH_A)
   are stated; a clash is an error naming the pair and the fix, after build.json is written.
"""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from dna_models.errors import DnarodError
from dna_models.units import ANGSTROM_PER_NM
from mdbridge.geometry.topology import linking_number
from mdbridge.rod.run import RodRun

from .builder import build_duplex
from .builder.backbone import check_structure_links
from .builder.duplex import base_pairs
from .gromacs import defaults
from .gromacs.box import plan_ring_box
from .gromacs.clashes import clashes, contact_words
from .gromacs.inputs import build_inputs
from .gromacs.mdp import MdSettings
from .gromacs.rod import rod_initial_from_run
from .topology import md_topology

STRAND_ATOMS = ("C1'", "P")
RING_LB_NM = 2.0    # pdb2gmx -lb (nm): spans the closing step of a ring, not the ring (see inputs._topology)


def strand_polygons(structure, atom: str):
    """(strand I, strand II) positions (n, 3) of ATOM, point k of both in base pair k
    (base_pairs), so both run along strand I."""
    n = len(np.unique(structure.resids)) // 2
    pairs = base_pairs(n)
    x = np.asarray(structure.coords, float)
    return (x[[structure.index(i, atom) for i, _ in pairs]], x[[structure.index(j, atom) for _, j in pairs]])


def strand_linking(structure) -> dict:
    """Linking number of the two strands of a built ring, per atom kind (C1', P)."""
    return {a: linking_number(*strand_polygons(structure, a)) for a in STRAND_ATOMS}


def ring_settings(temperature_K: float, md_ps: float = defaults.MD_PS) -> MdSettings:
    """The MD settings of build-md's command defaults, for a ring closed in space."""
    dt = defaults.default_dt_ps(defaults.CONSTRAINTS)
    return MdSettings(dt_ps=dt, cutoffs=defaults.COMMAND_CUTOFFS, temperature_K=temperature_K,
                      nsteps=int(round(md_ps / dt)), periodic_molecules=False)


def build_ring_md(run: RodRun, sequence: str, output, *, Lk: int, frame: int = -1,
                  temperature_K: float = defaults.TEMPERATURE_K, seed: int = 0, minimize: bool = True,
                  protocol: str = "paper", equilibrate_ps: float = defaults.EQUILIBRATE_PS,
                  margin_A: float = defaults.MARGIN_A, forcefield: str = defaults.FORCEFIELD,
                  electrostatics: str = defaults.ELECTROSTATICS, gmx: str | None = None,
                  threads: int = defaults.BUILD_THREADS, meta: dict | None = None, say=print) -> dict:
    """Build the all-atom ring on the rod ring RUN at output frame FRAME into OUTPUT and return
    build.json's content; Lk is the rod's linking number, which the strands must carry."""
    n_bp = len(sequence)
    output = Path(output)
    settings = ring_settings(temperature_K)
    rod, centerline = rod_initial_from_run(run, n_bp, frame=frame)
    box = plan_ring_box(centerline[frame][None], rod.origins_A, rod_run_ps=0.0,
                        cutoff_A=settings.cutoff_nm * ANGSTROM_PER_NM, margin_A=margin_A)
    structure = build_duplex(sequence, rod.origins_A, rod.R, ring=True, close_backbone=True)
    links = check_structure_links(structure, where=f"the ring on the rod's frame {frame}")
    strands_Lk = strand_linking(structure)
    bad = {a: v for a, v in strands_Lk.items() if v != Lk}
    if bad:
        raise DnarodError(f"the built strands link {bad} times, the rod ring {Lk} times: the all-atom ring "
                          "is not the rod's (docs/builder.md, 'Rings closed in space')")
    say(f"built {n_bp}-bp ring: strands' Lk {strands_Lk} = the rod's; O3'-P links "
        f"{links.min():.3f}-{links.max():.3f} A; box {np.round(box.box_A, 1).tolist()} A; pdb2gmx, grompp ...")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        info = build_inputs(output, structure, rod, box, sequence=sequence, forcefield=forcefield,
                            electrostatics=electrostatics, temperature_K=temperature_K, seed=seed,
                            settings=settings, minimize=minimize, gmx=gmx, threads=threads, protocol=protocol,
                            equilibrate_ps=equilibrate_ps, description="minicircle", lb_nm=RING_LB_NM,
                            meta={"ring": True, "rod_frame": frame, "rod_Lk": Lk, "strands_Lk_built": strands_Lk,
                                  "O3P_links_built_A": [float(links.min()), float(links.max())], **(meta or {})})
    for w in caught:     # the clash warning is step 5's error below; the others are said
        if "closer than" not in str(w.message):
            say(f"warning: {w.message}")
    gro = md_topology(output)
    info["strands_Lk_conf_gro"] = int(gro["Lk"][0])
    info["conf_gro_topology"] = {k: float(gro[k][0]) for k in ("Tw", "Wr", "Wr_bp_centres", "bp_per_turn")}
    contact = info["closest_nonbonded_contact"]
    from mdbridge.jsonio import write_json
    write_json(output / "build.json", info)
    if info["strands_Lk_conf_gro"] != Lk:
        raise DnarodError(f"{output}/conf.gro: its C1' strands link {info['strands_Lk_conf_gro']} times, the rod "
                          f"ring {Lk} times")
    t = info["conf_gro_topology"]
    if abs(Lk - t["Tw"] - t["Wr"]) >= 0.5:      # `dnarod topology`'s rule (docs/topology.md)
        raise DnarodError(f"{output}/conf.gro: Lk = {Lk} but Tw + Wr = {t['Tw'] + t['Wr']:.3f} about the one-turn "
                          "axis of its C1' strands: not a duplex ring (docs/topology.md)")
    em = info.get("minimization")
    say(("minimised: " + ("converged" if em["converged"] else "NOT converged") if em else "not minimised")
        + f"; conf.gro: {contact_words(contact)}")
    if clashes(contact):
        fix = ("minimise it (leave out --no-minimize)" if not em else
               "the restrained minimisation (base heavy atoms held) did not separate them: a rod state with "
               "less bend and shear per base pair (more --points-per-bp, a longer --relax-ps) or no atoms "
               "(--no-atoms)")
        raise DnarodError(f"{output}/conf.gro: the atoms clash ({contact_words(contact)}): MD would blow up "
                          f"from these contacts; {fix} (build.json: closest_nonbonded_contact)")
    return info
