"""The equilibration stage before the kick: thermostatted MD at the target temperature.

Protocols (build.json "protocol", copied into checks.json):
- "equilibrated" (default): after the restrained minimisation, MD with the
  v-rescale thermostat at T (tau 0.1 ps) from Maxwell-Boltzmann velocities, for
  `ps`; then the rod's velocity field is added to the equilibrated velocities
  and the NVE run starts from there (inputs.build_inputs).
- "paper": no equilibration (paper Sec 6.2): the minimised build with fresh
  thermal velocities plus the rod field; the NVE temperature then falls as
  kinetic energy flows into the potential energy of the built structure.

With `axial_pressure`, the same stage also couples the pressure along the helix
axis only (Parrinello-Rahman, anisotropic, compressibility zero across the
axis, reference pressure 0): the box length along the axis then relaxes to the
length at which the periodic, ligated duplex carries no tension, the duplex's
zero-tension length (mean over the second half of the stage).

Stationarity test (stated in build.json "equilibration.stationary"): the means
of the temperature over the third and the fourth quarter of the stage agree
within twice the standard error of their difference (from 1-ps block means),
and the same for the potential energy.
"""
from __future__ import annotations

from pathlib import Path

from dna_models.errors import InputError
from mdbridge import stats

from .energy import read_energies
from .gmx import run_gmx, run_gmx_with_progress
from .mdp import MdSettings, render_md

PROTOCOLS = ("equilibrated", "paper")

TAU_T_PS = 0.1
TAU_P_PS = 5.0
# Compressibility of the box along the axis: the box is mostly vacuum, so its
# "compressibility" is the duplex's stretch compliance times the box cross-section,
# A / S with a stretch modulus S ~ 1000 pN: 1e-4 bar^-1 per nm^2 of cross-section
# (8.5e-3 /bar for the 5.0 x 17.0 nm^2 158-bp box). Half of that is set: a too soft
# barostat (too large a value) made the 21-bp box swing from 7 to 12 nm and heat to
# 1,300 K; a stiffer one only slows the approach (the mean is unaffected).
COMPRESSIBILITY_PER_BAR_PER_NM2 = 0.5e-4
BLOCK_PS = 1.0
# The barostat makes the box length oscillate (measured: period ~20 ps for the 21-bp
# box with tau-p 5 ps), so the error of its mean uses 5-ps blocks and understates the
# error unless the second half holds several periods; the range is recorded too.
LENGTH_BLOCK_PS = 5.0


def check_protocol(protocol: str, *, temperature_K: float, equilibrate_ps: float, axial_pressure: bool) -> None:
    """The protocol's arguments, checked before anything is built (InputError, in the
    command's spelling)."""
    if protocol not in PROTOCOLS:
        raise InputError(f"protocol {protocol!r}: allowed {', '.join(PROTOCOLS)}")
    if protocol == "equilibrated" and not (temperature_K > 0 and equilibrate_ps > 0):
        raise InputError(f"--temperature {temperature_K:g} K, --equilibrate-ps {equilibrate_ps:g}: the equilibrated "
                         "protocol (the default at --temperature > 0) needs both > 0; to start from the build "
                         "without an equilibration stage, use --protocol paper")
    if axial_pressure and protocol != "equilibrated":
        raise InputError("--axial-pressure acts in the equilibration stage: use --protocol equilibrated")


def axial_compressibility(box_nm, axis: int) -> float:
    """The barostat's compressibility along the axis for this box (see above), 1/bar."""
    across = [float(box_nm[k]) for k in range(3) if k != axis]
    return COMPRESSIBILITY_PER_BAR_PER_NM2 * across[0] * across[1]


def render_equilibration(s: MdSettings, *, ps: float, temperature_K: float, axis: int,
                         axial_pressure: bool, box_nm=(1.0, 1.0, 1.0)) -> str:
    kw: dict = {**s.as_dict(), "thermostat": True, "temperature_K": temperature_K,
                "tau_t_ps": TAU_T_PS, "output_ps": 0.1}
    eq = MdSettings(**kw)
    eq.nsteps = eq.steps_per(ps)
    text = render_md(eq).replace("; dnarod md.mdp:", "; dnarod eq.mdp (equilibration stage):")
    # eq_in.gro carries Maxwell-Boltzmann velocities at T drawn by velocities.py with the
    # build's seed (gen-vel = no, as in md.mdp); constrain the start if there are constraints
    text = text.replace("continuation            = yes", "continuation            = no")
    if axial_pressure:
        comp = ["0"] * 6                     # xx yy zz xy xz yz
        comp[axis] = f"{axial_compressibility(box_nm, axis):.3g}"
        text = text.replace("pcoupl                  = no", "\n".join([
            "; pressure along the helix axis only: the zero-tension length of the duplex",
            "pcoupl                  = Parrinello-Rahman",
            "pcoupltype              = anisotropic",
            f"tau-p                   = {TAU_P_PS}",
            f"compressibility         = {' '.join(comp)}",
            "ref-p                   = 0 0 0 0 0 0",
            "refcoord-scaling        = no"]))
    return text


def stationarity(t, y) -> dict:
    """The stated test on the second half of a series (see module doc; mdbridge.stats
    stationarity): the means of its two quarters (third and fourth of the stage) agree
    within twice their combined standard error (1-ps block means): a two-sided test at ~95 %."""
    return stats.stationarity(t, y, sem=lambda tq, yq: stats.time_block_sem(tq, yq, BLOCK_PS))


def equilibrate(outdir: Path, gmx: str, settings: MdSettings, *, ps: float, temperature_K: float,
                axis: int, axial_pressure: bool, threads: int, box_nm=(1.0, 1.0, 1.0),
                progress=None) -> dict:
    """Run the stage on OUTDIR/eq_in.gro (coordinates, thermal velocities, box); leaves
    eq.gro (x, v, box). progress, if given: progress("equilibration", ps_done, ps, "ps").
    Returns the build.json record."""
    d = Path(outdir)
    (d / "eq.mdp").write_text(render_equilibration(settings, ps=ps, temperature_K=temperature_K,
                                                   axis=axis, axial_pressure=axial_pressure,
                                                   box_nm=box_nm))
    run_gmx(gmx, ["grompp", "-f", "eq.mdp", "-c", "eq_in.gro", "-p", "topol.top", "-o", "eq.tpr",
                  "-po", "eq_out.mdp", "-maxwarn", "0"], d, log_name="gmx_grompp_eq.log")
    run_gmx_with_progress(gmx, ["mdrun", "-v", "-deffnm", "eq", "-nt", str(threads)], d,
                          log_name="gmx_mdrun_eq.log",
                          on_step=None if progress is None else
                          (lambda k: progress("equilibration", k * settings.dt_ps, ps, "ps")))
    e = read_energies(d, gmx, edr="eq.edr")
    t = e["time"]
    rec: dict = {"ps": ps, "thermostat": f"v-rescale, tau-t {TAU_T_PS} ps, ref-t {temperature_K} K",
           "temperature_K": stationarity(t, e["Temperature"]),
           "potential_kJ_mol": stationarity(t, e["Potential"]),
           "test": "means over the 3rd and 4th quarter of the stage differ by less than 2 x "
                   "the standard error of the difference (1-ps block means), for T and E_pot"}
    rec["stationary"] = rec["temperature_K"]["stationary"] and rec["potential_kJ_mol"]["stationary"]
    if axial_pressure:
        key = "Box-" + "XYZ"[axis]
        L = e[key]
        h = t >= t[0] + 0.5 * (t[-1] - t[0])
        rec["axial_pressure"] = {
            "barostat": f"Parrinello-Rahman, anisotropic, compressibility "
                        f"{axial_compressibility(box_nm, axis):.3g} /bar along axis {'xyz'[axis]} and 0 "
                        f"across, ref-p 0, tau-p {TAU_P_PS} ps",
            "box_length_start_nm": float(L[0]),
            "zero_tension_length_nm": float(L[h].mean()),
            "zero_tension_length_se_nm": stats.time_block_sem(t[h], L[h], LENGTH_BLOCK_PS),
            "zero_tension_length_se_doc": f"standard error from {LENGTH_BLOCK_PS:g}-ps block "
                                          "means over the second half; understated unless the "
                                          "half holds several barostat periods (see the range)",
            # the barostat's swing: the mean is trustworthy only over whole periods of it
            "box_length_range_second_half_nm": [float(L[h].min()), float(L[h].max())],
            "box_length_stationarity": stationarity(t, L)}
    return rec
