"""Initial velocities: a thermal Maxwell-Boltzmann part plus the rod's motion.

Paper Sec 6.2: "random initial velocities representing a temperature of 300 K
were first assigned ... and then the desired sinusoidal velocity along the
length of the rod ... was added to the thermal velocities". We add, for every
atom of base pair i (BOTH nucleotides of the pair: base, sugar and phosphate),
the rigid-body velocity of the rod's cross-section at s_i = i L / n_bp:

    v_atom = gamma_lab(s_i) + omega_lab(s_i) x (x_atom - r(s_i)),

gamma_lab = sum_k gamma_k d_k, omega_lab = sum_k omega_k d_k (lab = directors
. internal components), converted to physical units by dna_models.units.
Only the thermal part has its centre-of-mass motion removed: the rod's own
momentum is physics.
"""
from __future__ import annotations

import numpy as np

from dna_models.units import ANGSTROM_PER_NM, BOLTZMANN_KJ_PER_MOL_K

# Boltzmann constant in GROMACS units: kJ mol^-1 K^-1 (the exact SI 2019 k_B N_A, as GROMACS 2022 uses)
KB_KJ_MOL_K = BOLTZMANN_KJ_PER_MOL_K
A_PER_PS_TO_NM_PER_PS = 1.0 / ANGSTROM_PER_NM


def thermal_velocities(masses_amu, temperature_K: float, seed: int) -> np.ndarray:
    """Maxwell-Boltzmann velocities (nm/ps) with zero total momentum, rescaled so that
    their kinetic temperature with 3N - 3 degrees of freedom is exactly temperature_K.

    The exact rescale (as gmx grompp's gen-vel does) makes the requested temperature
    a fact of the file rather than a sample of it; 0 K gives all zeros."""
    m = np.asarray(masses_amu, dtype=float)
    n = len(m)
    if temperature_K <= 0.0:
        return np.zeros((n, 3))
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(n, 3)) * np.sqrt(KB_KJ_MOL_K * temperature_K / m)[:, None]
    v -= (m[:, None] * v).sum(axis=0) / m.sum()
    return v * np.sqrt(temperature_K / kinetic_temperature(m, v, n_dof=3 * n - 3))


def kinetic_temperature(masses_amu, v_nm_ps, n_dof: int) -> float:
    """2 KE / (n_dof k_B), KE in kJ/mol with masses in g/mol and v in nm/ps."""
    m = np.asarray(masses_amu, dtype=float)
    ke = 0.5 * float((m[:, None] * np.asarray(v_nm_ps) ** 2).sum())
    return 2.0 * ke / (n_dof * KB_KJ_MOL_K)


def rigid_body_velocities(x_A, bp_index, origins_A, gamma_lab_A_ps, omega_lab_rad_ps) -> np.ndarray:
    """Velocity (nm/ps) of every atom moving with the cross-section of its base pair.

    x_A (N,3) atom positions (whole, Angstrom); bp_index (N,) 0-based base pair of each
    atom; origins_A (n_bp,3) = r(s_i); gamma_lab (n_bp,3) A/ps; omega_lab (n_bp,3) rad/ps."""
    x = np.asarray(x_A, dtype=float)
    i = np.asarray(bp_index, dtype=int)
    lever = x - np.asarray(origins_A)[i]
    v_A_ps = np.asarray(gamma_lab_A_ps)[i] + np.cross(np.asarray(omega_lab_rad_ps)[i], lever)
    return v_A_ps * A_PER_PS_TO_NM_PER_PS


def base_pair_of_residue(resids, n_bp: int) -> np.ndarray:
    """0-based base pair index of residues numbered as the builder does (3DNA's
    convention): strand I residue k (1..n) is in pair k; strand II residue r
    (n+1..2n) is in pair 2n + 1 - r."""
    r = np.asarray(resids, dtype=int)
    if np.any(r < 1) or np.any(r > 2 * n_bp):
        bad = int(r[(r < 1) | (r > 2 * n_bp)][0])
        raise ValueError(f"residue number {bad} outside 1..{2 * n_bp} for {n_bp} base pairs")
    return np.where(r <= n_bp, r - 1, 2 * n_bp - r)
