"""The MD's defaults, in one place.

`dnarod build-md` and `dnarod run-md` (workflows/commands/) show them as their option
defaults, mdbridge/md/build.py (`BuildRequest`) and inputs.build_inputs take them as
keyword defaults, and mdp.MdSettings as its field defaults. Why each value: docs/md.md
("md.mdp (and why)", "Energy conservation, measured").

Two choices differ between the command and the mdp settings, on purpose:
- cut-offs: MdSettings() is the paper's setting (plain cut-offs, the force jumps at
  1 nm); the command builds with the smooth ones (potential and force zero at the
  cut-off), which conserve energy in NVE;
- threads: the command minimises and equilibrates on BUILD_THREADS threads,
  build_inputs on one unless told.
"""
from __future__ import annotations

# the system (paper Sec 6.2)
FORCEFIELD = "charmm27"
ELECTROSTATICS = "paper"             # the force field's full charges (charges.py)
TEMPERATURE_K = 300.0                # thermal velocities, thermostat and equilibration
CUTOFF_NM = 1.0                      # the paper's 10 A cut-off, electrostatics and vdW

# the integrator
DT_PS = 0.001                        # without constraints: X-H bonds (period ~10 fs) need 1 fs
DT_CONSTRAINED_PS = 0.002            # with constraints = "h-bonds"
CONSTRAINTS = "none"
LINCS_ORDER = 4                      # GROMACS's defaults; 8 / 2 measured in docs/md.md
LINCS_ITER = 1
PAPER_CUTOFFS = "paper"              # MdSettings(): the cut-offs as the paper states them
COMMAND_CUTOFFS = "smooth"           # build-md: potential and force vanish at the cut-off
TAU_T_PS = 1.0                       # v-rescale coupling time when a thermostat is asked for
OUTPUT_PS = 1.0                      # coordinates and energies every OUTPUT_PS

# water (build-md --solvent; solvent.py, mdp.py)
SOLVENT = "vacuum"                   # the paper's setting
SALT_MM = 0.0                        # salt on top of the neutralising counterions, mM
PME_FOURIER_SPACING_NM = 0.12        # GROMACS's default grid spacing
LATERAL_PRESSURE_BAR = 1.0           # across the helix axis (and along it at zero tension)
WATER_COMPRESSIBILITY_PER_BAR = 4.5e-5   # the barostat's time scale only: C-rescale samples the right ensemble
TAU_P_PS = 2.0                       # C-rescale coupling time

# the build (build-md)
MD_PS = 600.0                        # the MD length the box is sized for (the paper's run)
EQUILIBRATE_PS = 20.0                # the v-rescale stage of the "equilibrated" protocol
MARGIN_A = 10.0                      # extra box margin across the axis
BUILD_THREADS = 2                    # minimisation and equilibration (build-md)

# the run (run-md)
CHECKPOINT_MIN = 2.0                 # wall-clock minutes between checkpoints: a kill loses at most this


def default_dt_ps(constraints: str) -> float:
    """The time step a build gets when none is given: 2 fs with h-bond constraints, else 1 fs."""
    return DT_CONSTRAINED_PS if constraints == "h-bonds" else DT_PS


def default_protocol(temperature_K: float) -> str:
    """"equilibrated" (a thermostatted stage before the rod's velocities are added) at a
    temperature above 0 K, else "paper" (no equilibration, as in the paper)."""
    return "equilibrated" if temperature_K > 0 else "paper"
