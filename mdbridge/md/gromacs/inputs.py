"""Assemble DIR/conf.gro, topol.top (+ .itp), md.mdp, em.mdp and build.json.

Order matters and is the reason for this module:
1. the builder's whole (unwrapped) duplex, moved into the box planned from the rod;
2. pdb2gmx with ring closure (topology.py), then the junction check (junction.py):
   a build whose strands are not closed exactly like an interior step stops here;
3. electrostatics variant (charges.py), base restraints (posres.py): the DNA's topology,
   the same in vacuum and in water; then, in water, the solvent and ions after the DNA
   (solvent.py), and, if asked, the Watson-Crick pairs held closed (pair_hold.py);
4. optional restrained minimisation (em.mdp), unwrapped against the input;
5. velocities LAST, on the final coordinates: thermal + rod rigid-body field;
6. a grompp run on md.mdp proves the inputs are accepted before anyone waits on them;
   in water its run input also gives the checks of solvent_checks.py.
"""
from __future__ import annotations

import dataclasses
import json
import platform
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dna_models.errors import DnarodError, InputError
from dna_models.units import ANGSTROM_PER_NM, Units
from mdbridge.jsonio import write_json

from . import charges, defaults, posres
from .box import BoxPlan
from .clashes import CLASH_A, closest_contact
from .gmx import find_gmx, gmx_version, run_gmx, run_gmx_with_progress
from .gro import Gro, read_gro, write_gro
from .junction import junction_parameters, junction_report, o3p_links
from .equilibrate import check_protocol, equilibrate
from .mdp import MdSettings, render_em, render_md, read_mdp_value
from .pair_hold import PairHold, add_pair_hold
from .rod import RodInitial
from .solvent import Solvent, check_medium, solvate
from .solvent_checks import (dna_first_check, file_digests, ion_count_check, total_charge_check,
                             water_in_duplex_check)
from .topology import parse_itp, run_pdb2gmx, write_pdb2gmx_input
from .tpr_dump import dump_tpr
from .velocities import (base_pair_of_residue, kinetic_temperature, rigid_body_velocities,
                         thermal_velocities)

NM = ANGSTROM_PER_NM  # Angstrom per nm (dna_models.units)
PROTOCOL_DOC = ("equilibrated: v-rescale stage at T, then rod velocities added to the "
                "equilibrated ones, then NVE; paper: no equilibration (paper Sec 6.2)")
RESIDUE_TO_BASE_PAIR = ("strand I residue k -> pair k; strand II residue r -> pair 2n+1-r "
                        "(1-based, 3DNA numbering)")


def structure_chains(structure, shift_A) -> list[dict]:
    """The builder's Structure (strand I then II, each 5'->3') as pdb2gmx input chains."""
    chains = []
    x = np.asarray(structure.coords, float) + np.asarray(shift_A, float)
    for strand, cid in (("I", "A"), ("II", "B")):
        idx = np.flatnonzero(structure.strands == strand)
        residues: list[tuple] = []
        for k in idx:
            r = int(structure.resids[k])
            if not residues or residues[-1][0] != r:
                residues.append((r, str(structure.resnames[k]), []))
            residues[-1][2].append((str(structure.names[k]), tuple(x[k])))
        chains.append({"id": cid, "residues": residues})
    return chains


def _unwrap_against(x_nm, ref_nm, box_nm):
    d = x_nm - ref_nm
    return ref_nm + d - box_nm * np.round(d / box_nm)


def _frames_of_gro(gro_path: Path, n_bp: int):
    """Base-pair frames of a built structure, re-analysed with mdbridge.geometry (3DNA)."""
    import MDAnalysis as mda
    from mdbridge.md.builder.duplex import base_pairs
    from mdbridge.geometry.structure import BasePairFrames
    u = mda.Universe(str(gro_path))
    pairs = base_pairs(n_bp)
    with warnings.catch_warnings():   # a single .gro frame has no time step: irrelevant here
        warnings.simplefilter("ignore", UserWarning)
        bp = BasePairFrames(u, pairs=pairs).run()
    return np.asarray(bp.results.origins)[0], np.asarray(bp.results.R)[0]


def frame_deviation(o1, R1, o2, R2, box_A=None) -> dict:
    """Largest origin distance (A) and rotation angle (deg) between two sets of frames."""
    d = np.asarray(o2) - np.asarray(o1)
    if box_A is not None:
        b = np.asarray(box_A, float)
        d = d - b * np.round(d / b)
    rel = np.einsum("nji,njk->nik", R1, R2)
    cosang = np.clip((np.trace(rel, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
    ang = np.degrees(np.arccos(cosang))
    return {"max_origin_A": float(np.linalg.norm(d, axis=1).max()),
            "rms_origin_A": float(np.sqrt((np.linalg.norm(d, axis=1) ** 2).mean())),
            "max_angle_deg": float(ang.max()), "rms_angle_deg": float(np.sqrt((ang ** 2).mean()))}


def build_inputs(outdir: Path, structure, rod: RodInitial, box: BoxPlan, *, sequence: str,
                 forcefield: str = defaults.FORCEFIELD, electrostatics: str = defaults.ELECTROSTATICS,
                 temperature_K: float = defaults.TEMPERATURE_K, seed: int = 0,
                 settings: MdSettings | None = None, minimize: bool = False, gmx: str | None = None,
                 threads: int = 1, protocol: str = "paper", equilibrate_ps: float = defaults.EQUILIBRATE_PS,
                 axial_pressure: bool = False, meta: dict | None = None, progress=None,
                 description: str = "periodic duplex", lb_nm: float | None = None,
                 hold_pairs: PairHold | None = None, solvent: Solvent | None = None) -> dict:
    """Write every MD input into OUTDIR and return the content of build.json.
    gmx: as find_gmx (the given path, else $DNAROD_GMX, else the project's build, else PATH).

    protocol "paper": thermal + rod velocities on the (minimised) build;
    "equilibrated": a thermostatted stage of equilibrate_ps first (equilibrate.py),
    optionally with the axis-only barostat, then rod velocities added.
    progress, if given, is called as progress(stage, done, total, unit) while the
    minimisation ("minimisation", steps) and the equilibration ("equilibration", ps) run
    (workflows/progress.py, Stages, draws it).
    hold_pairs: flat-bottomed restraints keep the Watson-Crick pairs closed (pair_hold.py);
    they act in the minimisation, the equilibration and the run alike.
    solvent: water and ions around the duplex (solvent.py), PME; settings.axial_tension_pN
    then holds the duplex at that tension (the helix axis must be the box's z)."""
    gmx = find_gmx(gmx)
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    for stale in ("build.json", "md.done", "checks.json"):
        (outdir / stale).unlink(missing_ok=True)
    md = _medium_settings(settings or MdSettings(), solvent, box, axial_pressure)
    _check_choices(protocol, temperature_K, equilibrate_ps, axial_pressure, len(sequence), rod.n_bp)
    n = rod.n_bp
    shift = np.asarray(box.shift_A, float)
    box_nm = np.asarray(box.box_A, float) / NM

    top = _topology(outdir, gmx, structure, shift, box_nm, forcefield, electrostatics, lb_nm)     # 1-3
    g, masses, water = _solvate(outdir, gmx, top, box_nm, md, forcefield, solvent, seed)
    held = None if hold_pairs is None else add_pair_hold(outdir / "topol.top", top.mols, n, hold_pairs)
    (outdir / "em.mdp").write_text(render_em(md))
    (outdir / "md.mdp").write_text(render_md(md))
    x_nm, em = _minimise(outdir, gmx, g, box_nm, n, threads, progress) if minimize else (g.x.copy(), None)  # 4
    x_nm, box_nm, v_th, eq = _thermal_velocities(                                           # 5
        outdir, gmx, md, g, masses, x_nm, box_nm, protocol=protocol, temperature_K=temperature_K,
        seed=seed, equilibrate_ps=equilibrate_ps, axis=box.axis, axial_pressure=axial_pressure, threads=threads,
        progress=progress)
    v_rod = _write_conf(outdir, g, x_nm, v_th, box_nm, rod, shift, top.gro.n_atoms,
                        f"dnarod {description} {n} bp, {forcefield}, "
                        f"{'vacuum' if solvent is None else solvent.model}, T={temperature_K} K, seed={seed}")
    contact, frames_t0, links = _t0_checks(outdir, top, x_nm[:top.gro.n_atoms], box_nm, rod, shift, box.box_A)
    junction_run_input, charge = _grompp_check(outdir, gmx, [m.name for m in top.mols])      # 6
    if water is not None:
        water["checks"] = _solvent_checks(outdir, top, water, charge, forcefield)

    info = {
        "sequence": sequence, "n_bp": n, "seed": seed, "temperature_K": temperature_K,
        "forcefield": forcefield, "electrostatics": electrostatics,
        "pair_hold": held,
        "electrostatics_doc": charges.__doc__.strip(),
        **_charge_record(top),
        "solvent": water,
        "units": Units.paper().as_dict(),
        "box": box.as_dict(), "box_nm": box_nm.tolist(),
        "md_settings": md.as_dict(),
        "junctions": top.junctions,
        "junction_run_input": junction_run_input,
        "junction_O3P_t0_A": {s: {"junction": float(d["junction_A"]), "interior_min": float(d["interior_A"].min()),
                                  "interior_max": float(d["interior_A"].max())} for s, d in links.items()},
        "frames_t0_vs_rod": frames_t0,
        "closest_nonbonded_contact": contact,
        "velocities": _velocity_record(masses, v_th, v_rod, temperature_K, equilibrated=eq is not None),
        "minimization": em,
        "protocol": protocol,
        "protocol_doc": PROTOCOL_DOC,
        "equilibration": eq,
        "residue_to_base_pair": RESIDUE_TO_BASE_PAIR,
        "gmx": {"path": gmx, "version": gmx_version(gmx)},
        "host": platform.node(),
        "files": ["conf.gro", "topol.top"] + [p.name for p in top.itps] + ["md.mdp", "em.mdp", "build.json"],
    }
    info.update(meta or {})
    write_json(outdir / "build.json", info)
    return info


def _check_choices(protocol, temperature_K, equilibrate_ps, axial_pressure, n_sequence, n_bp):
    check_protocol(protocol, temperature_K=temperature_K, equilibrate_ps=equilibrate_ps,
                   axial_pressure=axial_pressure)
    if n_sequence != n_bp:
        raise InputError(f"sequence has {n_sequence} bases but the rod has {n_bp} base pairs")
    if temperature_K < 0:
        raise InputError(f"--temperature {temperature_K}: must be >= 0 K")


@dataclass
class _Topology:
    """The verified topology: one molecule per strand (after the electrostatics variant and
    the base restraints) and pdb2gmx's coordinates in the topology's atom order."""
    itps: list
    mols: list
    junctions: list
    gro: Gro
    masses: np.ndarray


def _topology(outdir: Path, gmx, structure, shift, box_nm, forcefield, electrostatics, lb_nm=None) -> _Topology:
    """Steps 1-3: the duplex moved into the box, pdb2gmx with ring closure, the junction
    check, the electrostatics variant and the base restraints. lb_nm: pdb2gmx's -lb; by
    default larger than any distance in the structure (the periodic duplex's ends are a
    box apart); a ring closed in space needs it only across its closing step (ring.py:
    2 nm closes it, 0.3 nm does not), and pdb2gmx's time grows with -lb (a 336-bp strand:
    6 min at 68 nm, 80 s at 0.3 nm, on the loaded 2 cores)."""
    pdb = outdir / "duplex_in.pdb"
    write_pdb2gmx_input(pdb, structure_chains(structure, shift), forcefield)
    if lb_nm is None:
        lb_nm = float(np.max(box_nm)) * 2.0 + 1.0
    top = run_pdb2gmx(gmx, pdb, outdir, forcefield, lb_nm=lb_nm)
    mols = [parse_itp(p) for p in top["itps"]]
    junctions = [junction_report(m) for m in mols]
    bad = [j for j in junctions if not j["ok"]]
    if len(mols) != 2 or bad:
        raise DnarodError("ring closure failed: the junction terms of "
                          + ", ".join(j["molecule"] for j in bad or junctions)
                          + " differ from an interior step's: "
                          + json.dumps(bad or junctions, indent=1)[:3000])
    for p, m in zip(top["itps"], mols):
        charges.apply_electrostatics(p, electrostatics)
        posres.add_base_restraints(p, m)
    mols = [parse_itp(p) for p in top["itps"]]
    masses = np.concatenate([m.mass for m in mols])
    g = read_gro(top["gro"])
    names_itp: list[str] = sum((m.atomname for m in mols), [])
    if g.n_atoms != len(masses) or g.name != names_itp:
        raise DnarodError(f"{top['gro']}: atoms differ from the topology's ({g.n_atoms} vs {len(masses)})")
    return _Topology(itps=top["itps"], mols=mols, junctions=junctions, gro=g, masses=masses)


def _minimise(outdir: Path, gmx, g: Gro, box_nm, n_bp: int, threads: int, progress):
    """Step 4: restrained steepest descent (em.mdp) from pdb2gmx's coordinates. Returns the
    minimised coordinates, whole (unwrapped against the input), and the build.json record."""
    x_nm = g.x.copy()
    em_in = Gro("dnarod: before minimisation", g.resid, g.resname, g.name, x_nm, None, box_nm)
    write_gro(outdir / "em_in.gro", em_in)
    run_gmx(gmx, ["grompp", "-f", "em.mdp", "-c", "em_in.gro", "-r", "em_in.gro", "-p",
                  "topol.top", "-o", "em.tpr", "-po", "em_out.mdp", "-maxwarn", "0"], outdir,
            log_name="gmx_grompp_em.log")
    em_steps = int(read_mdp_value((outdir / "em.mdp").read_text(), "nsteps") or 0)
    # -v: mdrun's step reports ("Step= k", 0-based: k + 1 steps made) drive the progress;
    # it stops earlier once converged
    run_gmx_with_progress(gmx, ["mdrun", "-v", "-deffnm", "em", "-nt", str(threads)], outdir,
                          log_name="gmx_mdrun_em.log",
                          on_step=None if progress is None else
                          (lambda k: progress("minimisation", k + 1, em_steps, "steps")))
    x_em = _unwrap_against(read_gro(outdir / "em.gro").x, x_nm, box_nm)
    o0, R0 = _frames_of_gro(outdir / "em_in.gro", n_bp)
    write_gro(outdir / "em_whole.gro",
              Gro("dnarod: after minimisation (whole)", g.resid, g.resname, g.name, x_em, None, box_nm))
    o1, R1 = _frames_of_gro(outdir / "em_whole.gro", n_bp)
    em = {"frames_moved": frame_deviation(o0, R0, o1, R1),
          "max_atom_displacement_A": float(np.linalg.norm(x_em - x_nm, axis=1).max() * NM),
          "log": "em.log"}   # in the build folder (written elsewhere, then moved)
    em.update(_em_summary(outdir / "gmx_mdrun_em.log"))
    if not em["converged"]:
        warnings.warn(f"{outdir}/em.log: the restrained minimisation did not reach Fmax < "
                      "500 kJ/mol/nm; check closest_nonbonded_contact in build.json", stacklevel=3)
    return x_em, em


def _thermal_velocities(outdir: Path, gmx, settings, g: Gro, masses, x_nm, box_nm, *, protocol,
                        temperature_K, seed, equilibrate_ps, axis, axial_pressure, threads, progress):
    """Step 5a, the thermal part of the velocities: fresh Maxwell-Boltzmann ones (protocol
    "paper"), or those at the end of a thermostatted stage (protocol "equilibrated", which
    also moves the atoms and, with the axial barostat, the box). Returns (x_nm, box_nm,
    v_thermal, the equilibration's build.json record or None)."""
    if protocol != "equilibrated":
        return x_nm, box_nm, thermal_velocities(masses, temperature_K, seed), None
    write_gro(outdir / "eq_in.gro", Gro("dnarod: before equilibration", g.resid, g.resname,
                                        g.name, x_nm, thermal_velocities(masses, temperature_K,
                                                                         seed), box_nm))
    eq = equilibrate(outdir, gmx, settings, ps=equilibrate_ps, temperature_K=temperature_K,
                     axis=axis, axial_pressure=axial_pressure, threads=threads,
                     box_nm=box_nm, progress=progress)
    g_eq = read_gro(outdir / "eq.gro")
    box_nm = g_eq.box
    x_nm = _unwrap_against(g_eq.x, x_nm, box_nm)
    if not eq["stationary"]:
        warnings.warn(f"{outdir}/eq.edr: temperature or potential energy still trends over the "
                      f"second half of the {equilibrate_ps:g}-ps equilibration (build.json: "
                      "equilibration); use a longer --equilibrate-ps", stacklevel=3)
    return x_nm, box_nm, g_eq.v, eq


def _write_conf(outdir: Path, g: Gro, x_nm, v_th, box_nm, rod: RodInitial, shift, n_dna: int, title: str):
    """Step 5b, velocities LAST on the final coordinates: thermal + for every atom of base
    pair i the rod cross-section's rigid-body velocity (the first N_DNA atoms; water and
    ions get none: the rod's motion is the DNA's); writes conf.gro and velocities_rod.npy
    and returns the rod part."""
    bp = base_pair_of_residue(g.resid[:n_dna], rod.n_bp)
    v_rod = np.zeros_like(x_nm)
    v_rod[:n_dna] = rigid_body_velocities(x_nm[:n_dna] * NM, bp, rod.origins_A + shift, rod.gamma_lab_A_ps,
                                          rod.omega_lab_rad_ps)
    write_gro(outdir / "conf.gro", Gro(title, g.resid, g.resname, g.name, x_nm, v_th + v_rod, box_nm))
    np.save(outdir / "velocities_rod.npy", v_rod)
    return v_rod


def _t0_checks(outdir: Path, top: _Topology, x_nm, box_nm, rod: RodInitial, shift, box_A):
    """The t = 0 geometry: the closest non-bonded contact (a warning below CLASH_A), the
    built structure's base-pair frames against the rod's, the junctions' O3'-P links."""
    g = top.gro
    contact = closest_contact(x_nm * NM, box_nm * NM, top.mols, g.name, g.resid)
    if contact["min_distance_A"] is not None and contact["min_distance_A"] < CLASH_A:
        warnings.warn(f"{outdir}/conf.gro: {contact['n_below_clash']} atom pairs closer than "
                      f"{CLASH_A} A (closest {contact['atoms']} at {contact['min_distance_A']:.2f} A)"
                      "; MD will blow up from these contacts: build with --minimize",
                      stacklevel=3)
    o_b, R_b = _frames_of_gro(outdir / "conf.gro", rod.n_bp)
    frames_t0 = frame_deviation(rod.origins_A + shift, rod.R, o_b, R_b, box_A)
    links = o3p_links(x_nm, g.resid, g.name, rod.n_bp, box_nm)
    return contact, frames_t0, links


def _grompp_check(outdir: Path, gmx, dna_molecules: list[str]) -> tuple[list[dict], dict]:
    """Step 6: grompp proves the inputs are accepted, and the run input it makes shows the
    ligation junction equal, in everything mdrun computes, to the interior steps with the
    same bases (junction.py junction_parameters, on the DNA's molecules; its outputs are not
    kept). Returns that report and the run input's total charge (solvent_checks.py)."""
    run_gmx(gmx, ["grompp", "-f", "md.mdp", "-c", "conf.gro", "-p", "topol.top", "-o",
                  "grompp_check.tpr", "-po", "grompp_check.mdp", "-maxwarn", "0"], outdir,
            log_name="gmx_grompp_check.log")
    try:
        dump = dump_tpr(gmx, outdir / "grompp_check.tpr")
        dump.moltypes = [m for m in dump.moltypes if m.name in dna_molecules]
        report = junction_parameters(dump)
        charge = total_charge_check(outdir / "grompp_check.tpr")
    finally:
        for p in ("grompp_check.tpr", "grompp_check.mdp"):
            (outdir / p).unlink(missing_ok=True)
    bad = [r for r in report if r["differs_from_steps"]]
    if bad:
        raise DnarodError(f"{outdir}: the ligation junction differs from interior steps with the same "
                          f"bases in the run input: {json.dumps(bad)}")
    return report, charge


def _medium_settings(settings: MdSettings, solvent: Solvent | None, box: BoxPlan, axial_pressure: bool):
    """The settings in the build's medium: PME in water; an axial tension (solvent.py
    check_medium) needs the helix on the box's z (semi-isotropic coupling keeps x and y
    together) and gets the box's cross-section for its reference pressure."""
    check_medium(solvent, axial_tension_pN=settings.axial_tension_pN, thermostat=settings.thermostat,
                 axial_pressure=axial_pressure)
    if solvent is None:
        return dataclasses.replace(settings, solvated=False)
    if settings.axial_tension_pN is None:
        return dataclasses.replace(settings, solvated=True)
    if box.axis != 2:
        raise InputError(f"--axial-tension-pN: the helix axis must be the box's z (semi-isotropic pressure "
                         f"coupling), it is {'xyz'[box.axis] if box.axis is not None else 'none'}")
    area = float(box.box_A[0] * box.box_A[1]) / NM ** 2
    return dataclasses.replace(settings, solvated=True, lateral_area_nm2=area)


def _solvate(outdir: Path, gmx, top: _Topology, box_nm, settings: MdSettings, forcefield: str,
             solvent: Solvent | None, seed: int) -> tuple[Gro, np.ndarray, dict | None]:
    """Step 3b: water and ions after the DNA (solvent.py); returns the solvated structure,
    every atom's mass (from a run input grompp makes of it) and build.json's "solvent"
    record, with the digests of the DNA's .itp files as the vacuum build has them. In
    vacuum: the DNA, its masses and None."""
    if solvent is None:
        return top.gro, top.masses, None
    import MDAnalysis as mda
    from ..forcefields import forcefield as registered
    ff = registered(forcefield)
    digests = file_digests(top.itps)
    charge = float(sum(m.charge.sum() for m in top.mols))
    vacuum = render_md(dataclasses.replace(settings, solvated=False, axial_tension_pN=None))
    dna = dataclasses.replace(top.gro, box=np.asarray(box_nm, float))   # the planned box, not pdb2gmx's
    g, rec = solvate(outdir, gmx, dna, ff=ff, solvent=solvent, charge_e=charge, ions_mdp=vacuum, seed=seed)
    write_gro(outdir / "solvated_ions.gro", g)
    (outdir / "masses.mdp").write_text(vacuum)
    run_gmx(gmx, ["grompp", "-f", "masses.mdp", "-c", "solvated_ions.gro", "-p", "topol.top", "-o", "masses.tpr",
                  "-po", "masses_out.mdp", "-maxwarn", "0"], outdir, log_name="gmx_grompp_masses.log")
    with warnings.catch_warnings():     # a .tpr read for its topology only: no coordinates wanted
        warnings.simplefilter("ignore", UserWarning)
        masses = np.asarray(mda.Universe(str(outdir / "masses.tpr")).atoms.masses, float)
    for p in ("masses.tpr", "masses_out.mdp", "masses.mdp"):
        (outdir / p).unlink(missing_ok=True)
    rec["dna_itp_sha256"] = digests
    rec["n_atoms"] = int(g.n_atoms)
    return g, masses, rec


def _solvent_checks(outdir: Path, top: _Topology, water: dict, charge: dict, forcefield: str) -> dict:
    """build.json "solvent.checks" (solvent_checks.py) on the final conf.gro and run input."""
    from ..forcefields import forcefield as registered
    ff = registered(forcefield)
    conf = read_gro(outdir / "conf.gro")
    w = ff.water(water["model"])
    checks: dict = {
        "total_charge": charge,
        "ion_counts": ion_count_check(conf, water, cation=ff.cation.residue, anion=ff.anion.residue,
                                      salt_mM=water["salt_mM"]),
        "water_in_duplex": water_in_duplex_check(conf, w.residue),
        "dna_topology": dna_first_check(outdir / "topol.top", conf, top.gro, [m.name for m in top.mols],
                                        water["dna_itp_sha256"], {w.residue, ff.cation.molecule, ff.anion.molecule},
                                        {w.residue, ff.cation.residue, ff.anion.residue}),
    }
    checks["ok"] = all(c["ok"] for c in checks.values())
    if not checks["ok"]:
        raise DnarodError(f"{outdir}: a check of the solvated build failed: "
                          + json.dumps({k: v for k, v in checks.items() if k != "ok" and not v["ok"]})[:3000])
    return checks


def _charge_record(top: _Topology) -> dict:
    total_charge = float(sum(m.charge.sum() for m in top.mols))
    q_res = np.concatenate([np.bincount(m.resnr - m.resnr.min(), weights=m.charge)[
        np.unique(m.resnr - m.resnr.min())] for m in top.mols])
    return {"total_charge_e": round(total_charge, 4) or 0.0, "n_atoms": int(top.gro.n_atoms),
            "nucleotide_charge_range_e": [round(float(q_res.min()), 4), round(float(q_res.max()), 4)]}


def _velocity_record(masses, v_th, v_rod, temperature_K, equilibrated: bool) -> dict:
    v = v_th + v_rod
    return {
        "rule": ("v = equilibrated (end of the v-rescale stage, eq.gro)" if equilibrated else
                 "v = thermal (Maxwell-Boltzmann, COM removed, rescaled to exactly T with "
                 "3N-3 dof)") + " + gamma_lab(s_i) + omega_lab(s_i) x (x - r(s_i)) for every atom "
                "of both nucleotides of base pair i",
        "thermal_temperature_K": float(kinetic_temperature(masses, v_th, 3 * len(masses) - 3))
        if temperature_K > 0 else 0.0,
        "rod_max_speed_nm_ps": float(np.linalg.norm(v_rod, axis=1).max()),
        "total_momentum_amu_nm_ps": (masses[:, None] * v).sum(axis=0).tolist(),
        "rod_momentum_amu_nm_ps": (masses[:, None] * v_rod).sum(axis=0).tolist(),
        # comm-mode = Linear removes this at the first step (md.mdp)
        "rod_com_velocity_nm_ps": ((masses[:, None] * v_rod).sum(axis=0) / masses.sum()).tolist(),
    }


def _em_summary(log: Path) -> dict:
    import re
    text = Path(log).read_text()
    out: dict[str, bool | int | float] = {}
    m = re.search(r"converged to Fmax < (\S+) in (\d+) steps", text)
    if m:
        out.update(converged=True, steps=int(m.group(2)))
    else:
        out["converged"] = False
    m = re.search(r"Maximum force\s*=\s*(\S+)", text)
    if m:
        out["final_Fmax_kJ_mol_nm"] = float(m.group(1))
    m = re.search(r"Potential Energy\s*=\s*(\S+)", text)
    if m:
        out["final_potential_kJ_mol"] = float(m.group(1))
    return out
