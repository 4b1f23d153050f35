"""md.mdp and em.mdp: the paper's setting (Sec 6.2) as GROMACS parameters.

Paper: CHARMM22/27 nucleic acids, no water, no counterions, electrostatics
cut off at 10 A, NVE, strands ligated across the periodic boundary. Choices
that the paper leaves open are explained where they are made."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import asdict, dataclass

from . import defaults


@dataclass
class MdSettings:
    """The mdp settings; their defaults are the paper's setting (defaults.py)."""
    nsteps: int = 0                 # set by run-md (--ps / --steps); 0 = grompp check only
    dt_ps: float = defaults.DT_PS   # 1 fs: no constraints, best NVE energy conservation
    constraints: str = defaults.CONSTRAINTS  # "h-bonds" allows dt 2 fs (2x faster, small drift cost)
    cutoff_nm: float = defaults.CUTOFF_NM    # paper: 10 A electrostatics cut-off; vdW the same
    temperature_K: float = defaults.TEMPERATURE_K  # thermostat target, only used with thermostat=True
    thermostat: bool = False        # NVE by default: the rod is Hamiltonian (paper Sec 6.2)
    tau_t_ps: float = defaults.TAU_T_PS
    output_ps: float = defaults.OUTPUT_PS  # coordinates (xtc) and energies every output_ps
    epsilon_r: float = 1.0
    # "paper": plain cut-offs as the paper states them (Coulomb shifted = reaction-field
    # with eps_rf = 1, vdW potential-shift, rlist 1.1 nm); the force jumps at the cut-off.
    # "smooth": reaction-field with eps_rf = 0 (infinity) and vdW force-switch from
    # SWITCH_NM to the cut-off, rlist 1.2 nm: potential AND force vanish at the cut-off,
    # which is what makes NVE conserve energy (docs/md.md, energy conservation table).
    cutoffs: str = defaults.PAPER_CUTOFFS
    lincs_order: int = defaults.LINCS_ORDER
    lincs_iter: int = defaults.LINCS_ITER
    # True: the ligated duplex, bonded to its own periodic image; False: a molecule closed
    # in space (a minicircle) in a box large enough that it never meets its images
    periodic_molecules: bool = True
    # water and ions around the duplex (solvent.py): PME electrostatics instead of the cut-off
    # Coulomb of the paper's vacuum; the vdW treatment stays the `cutoffs` one
    solvated: bool = False
    # None: a fixed box. A tension (pN) along the helix axis (box z): semi-isotropic C-rescale
    # at 1 bar across and ref_p_z = 1 - 10 T / A (tension.py ref_p_axis_bar), A the box's
    # cross-section at the build (lateral_area_nm2)
    axial_tension_pN: float | None = None
    lateral_area_nm2: float = 0.0
    tau_p_ps: float = defaults.TAU_P_PS

    def steps_per(self, ps: float) -> int:
        return max(1, int(round(ps / self.dt_ps)))

    def as_dict(self) -> dict:
        return asdict(self)


CUTOFFS = (defaults.PAPER_CUTOFFS, defaults.COMMAND_CUTOFFS)
SWITCH_NM = 0.8                     # vdW force-switch start of the "smooth" cut-offs
SMOOTH_RLIST_NM = 1.2


def rlist_nm(s: MdSettings) -> float:
    return SMOOTH_RLIST_NM if s.cutoffs == "smooth" else s.cutoff_nm + 0.1


def _pme_lines(s: MdSettings, vdw: list[str]) -> list[str]:
    return [
        "; water and counterions: the system is neutral, so long-range electrostatics by PME",
        "coulombtype             = PME",
        f"rcoulomb                = {s.cutoff_nm}",
        f"epsilon-r               = {s.epsilon_r}",
        f"fourierspacing          = {defaults.PME_FOURIER_SPACING_NM}",
        "pme-order               = 4",
        "ewald-rtol              = 1e-5",
    ] + vdw


def _cutoff_lines(s: MdSettings) -> list[str]:
    if s.solvated and s.cutoffs in CUTOFFS:
        return _pme_lines(s, [ln for ln in _cutoff_lines(dataclasses.replace(s, solvated=False))
                              if ln.startswith(("vdw", "rvdw"))])
    if s.cutoffs == "paper":
        return [
            "; plain cut-off Coulomb (paper: 10 A cut-off, no long-range electrostatics).",
            "; Under Verlet this is reaction-field with epsilon-rf = 1, i.e. shifted Coulomb;",
            "; PME is impossible anyway: the duplex carries net charge and there are no ions.",
            "coulombtype             = Cut-off",
            f"rcoulomb                = {s.cutoff_nm}",
            f"epsilon-r               = {s.epsilon_r}",
            "vdwtype                 = Cut-off",
            "vdw-modifier            = Potential-shift",
            f"rvdw                    = {s.cutoff_nm}",
        ]
    if s.cutoffs == "smooth":
        return [
            "; the paper's 10 A cut-off with potential AND force going to zero at it:",
            "; reaction-field with epsilon-rf = 0 (infinite: conducting beyond rc) and a",
            "; force-switched vdW; a force jump at rc heats NVE (docs/md.md)",
            "coulombtype             = Reaction-field",
            f"rcoulomb                = {s.cutoff_nm}",
            f"epsilon-r               = {s.epsilon_r}",
            "epsilon-rf              = 0",
            "vdwtype                 = Cut-off",
            "vdw-modifier            = Force-switch",
            f"rvdw-switch             = {SWITCH_NM}",
            f"rvdw                    = {s.cutoff_nm}",
        ]
    raise ValueError(f"cutoffs = {s.cutoffs!r}; allowed: {', '.join(CUTOFFS)}")


def _common(s: MdSettings) -> list[str]:
    medium = "water and ions" if s.solvated else "vacuum"
    return [
        f"; {medium}, periodic in x, y, z; the strands are bonded to their own periodic image"
        if s.periodic_molecules else
        "; vacuum, periodic in x, y, z; the ring is closed in space and the box keeps its images out of reach",
        "pbc                     = xyz",
        f"periodic-molecules      = {'yes' if s.periodic_molecules else 'no'}",
        "cutoff-scheme           = Verlet",
    ] + _cutoff_lines(s) + [
        "nstlist                 = 10",
    ]


def render_md(s: MdSettings) -> str:
    out_steps = s.steps_per(s.output_ps)
    lines = [
        "; dnarod md.mdp: all-atom MD of the " + ("periodic, ligated duplex" if s.periodic_molecules
                                                  else "closed minicircle") + " (see docs/md.md)",
        "integrator              = md",
        f"dt                      = {s.dt_ps}",
        f"nsteps                  = {s.nsteps}",
        "; velocities come from conf.gro (thermal + rod rigid-body field); never regenerate",
        "gen-vel                 = no",
        # With constraints, let mdrun constrain the start: the built X-H lengths and the
        # velocities along X-H bonds are removed (the thermal part keeps ~T on the
        # remaining degrees of freedom); without it the first steps dump that energy.
        f"continuation            = {'yes' if s.constraints == 'none' else 'no'}",
        f"constraints             = {s.constraints}",
        "constraint-algorithm    = lincs",
        f"lincs-order             = {s.lincs_order}",
        f"lincs-iter              = {s.lincs_iter}",
        "; centre-of-mass translation removed (GROMACS warns that rounding otherwise builds",
        "; it up); the rod's planar wave carries no net momentum, build.json reports what",
        "; the rod field's COM velocity is, i.e. what this removes at step 0",
        "comm-mode               = Linear",
        "nstcomm                 = 100",
        f"nstxout-compressed      = {out_steps}",
        "compressed-x-precision  = 10000",
        f"nstenergy               = {out_steps}",
        f"nstcalcenergy           = {math.gcd(out_steps, 100)}",
        f"nstlog                  = {out_steps}",
        "nstvout                 = 0",
        "nstfout                 = 0",
        # A fixed 0.1 nm pair-list buffer: GROMACS would size the buffer from the
        # initial temperature, which is ~0 K for a build at 0 K that then heats up.
        "verlet-buffer-tolerance = -1",
        f"rlist                   = {rlist_nm(s)}",
    ] + _common(s)
    if s.thermostat:
        lines += ["tcoupl                  = V-rescale", "tc-grps                 = System",
                  f"tau-t                   = {s.tau_t_ps}", f"ref-t                   = {s.temperature_K}"]
    else:
        lines += ["tcoupl                  = no"]
    lines += pressure_lines(s)
    return "\n".join(lines) + "\n"


def pressure_lines(s: MdSettings) -> list[str]:
    """A fixed box, or the axial tension's barostat: semi-isotropic C-rescale (GROMACS >= 2021;
    it samples the isothermal-isobaric ensemble and its box fluctuations, which carry the
    q = 0 stretch; Berendsen suppresses them; anisotropic C-rescale is not in GROMACS 2022,
    hence the helix on z), 1 bar across, ref_p_z from the tension (tension.py)."""
    if s.axial_tension_pN is None:
        return ["pcoupl                  = no"]
    from .tension import ref_p_axis_bar
    p_z = ref_p_axis_bar(s.axial_tension_pN, s.lateral_area_nm2)
    return [
        f"; axial tension {s.axial_tension_pN:g} pN: P_zz = P_xy - T / A_xy with A_xy = {s.lateral_area_nm2:.4f} nm^2",
        "pcoupl                  = C-rescale",
        "pcoupltype              = semiisotropic",
        f"tau-p                   = {s.tau_p_ps}",
        f"compressibility         = {defaults.WATER_COMPRESSIBILITY_PER_BAR} {defaults.WATER_COMPRESSIBILITY_PER_BAR}",
        f"ref-p                   = {defaults.LATERAL_PRESSURE_BAR} {p_z:.6f}",
        "refcoord-scaling        = com",
    ]


def render_em(s: MdSettings, *, posres_define: str = "-DPOSRES_BASES", nsteps: int = 5000,
              emtol: float = 500.0) -> str:
    lines = [
        "; dnarod em.mdp: steepest descent that removes backbone clashes while the",
        "; base heavy atoms are held by position restraints (posre_bases_*.itp)",
        f"define                  = {posres_define}",
        "integrator              = steep",
        f"nsteps                  = {nsteps}",
        f"emtol                   = {emtol}",
        "emstep                  = 0.001",
        "constraints             = none",
        "comm-mode               = None",
        "refcoord-scaling        = no",
        "nstenergy               = 10",
    ] + _common(s) + ["tcoupl                  = no", "pcoupl                  = no"]
    return "\n".join(lines) + "\n"


def read_mdp_value(mdp_text: str, key: str) -> str | None:
    key = key.lower().replace("_", "-")
    for ln in mdp_text.splitlines():
        ln = ln.split(";")[0]
        if "=" in ln and ln.split("=")[0].strip().lower().replace("_", "-") == key:
            return ln.split("=", 1)[1].strip()
    return None
