"""Self-contact ([contact], rodcore/src/rodcore/contact.hpp, docs/topology.md) in runs, and
rodsim's per-frame topology of closed rods, against things true independently of the code:

* two pieces of a closed rod driven at each other (a figure-eight whose two strands cross
  at right angles 19.5 rod units = 9.7 nm apart, moving towards each other) do not pass:
  their distance stays near the diameter and the linking number (topology/Lk) stays; the
  control without contact passes through (distance ~0, Lk changes by -2, the signature of
  a strand passage), and rodsim counts and warns about it (topology_jumps);
* the contact force is conservative: an NVE run through the collision conserves the total
  energy, contact included, to 1e-4 of the energy the contact exchanged (control: without
  the contact part the energy changes by all of it);
* at 300 K (Langevin, kinetic temperature measured) a supercoiled figure-eight keeps its
  Lk with contact and loses 2 without. The closure drift of the thermal rod
  (docs/thermal.md, "Closure in a run") opens the ring by up to ~11 grid spacings within
  the 60-ps run; in frames where the seam is that wide the ribbon is not resolved there
  (Lk NaN), so Lk is compared over the frames where it is defined, and the run is short;
* bad [contact] keys are refused before any work, naming the key.
The potential itself (closed-form crossing energy, forces as gradients, cell list against
brute force, the effective-diameter ratio) is tested in tests/cpp/test_physics_contact.cpp.
"""
import functools
import subprocess

import h5py
import numpy as np
import pytest
import rodcore

from dna_models.units import Units

UNITS = Units.paper()
L = 300.0                     # 101 nm, 444 bp
D_NM = 5.0                    # the default effective diameter
D = D_NM * 10.0 / UNITS.ell_A


def figure_eight(N, V, turns=0.0, lift=0.2):
    fields, crossing = _figure_eight(N, V, turns, lift)
    return {k: v.copy() for k, v in fields.items()}, crossing


@functools.lru_cache
def _figure_eight(N, V, turns, lift):
    """Fields (N, 3) of a closed rod of length L along the curve x = cos t, y = sin t cos t,
    z = lift sin t (scaled to length L; its two strands cross at right angles above each
    other at t = pi/2 and 3 pi/2), framed by the parallel-transport frame closed by a
    uniform twist plus `turns` turns, unstretched; lab velocity v_z = -V sin t drives the
    strands at each other. Also the index of the two crossing points."""
    def dx(t):
        return np.stack([-np.sin(t), np.cos(2 * t), lift * np.cos(t)], -1)

    def ddx(t):
        return np.stack([-np.cos(t), -2 * np.sin(2 * t), -lift * np.sin(t)], -1)
    M = 40000
    th = np.arange(M + 1) * 2 * np.pi / M
    speed = np.linalg.norm(dx(th), axis=1)
    s = np.concatenate([[0], np.cumsum(0.5 * (speed[1:] + speed[:-1]))]) * 2 * np.pi / M
    scale = L / s[-1]
    si = np.arange(N) * s[-1] / N
    ti = np.interp(si, s, th)
    for _ in range(4):                      # Newton on s(t) = s_i (Simpson from the table)
        j = np.clip(np.searchsorted(th, ti) - 1, 0, M - 1)
        mid = 0.5 * (th[j] + ti)
        sv = s[j] + (ti - th[j]) / 6 * (np.linalg.norm(dx(th[j]), axis=1)
                                        + 4 * np.linalg.norm(dx(mid), axis=1) + np.linalg.norm(dx(ti), axis=1))
        ti = ti - (sv - si) / np.linalg.norm(dx(ti), axis=1)
    T = dx(th[:-1])
    T /= np.linalg.norm(T, axis=1)[:, None]
    U = np.empty_like(T)                    # parallel transport (minimal rotations), fine grid
    u = np.cross(T[0], [0, 0, 1.0])
    u /= np.linalg.norm(u)
    for k in range(M):
        U[k] = u
        a, b = T[k], T[(k + 1) % M]
        u = u - (b @ u) / (1 + a @ b) * (a + b)
        u = u - (u @ b) * b
        u /= np.linalg.norm(u)
    Delta = np.arctan2(np.cross(U[0], u) @ T[0], U[0] @ u)   # holonomy of the transport
    t3 = dx(ti) / np.linalg.norm(dx(ti), axis=1)[:, None]
    k = np.rint(np.interp(ti, th[:-1], np.arange(M))).astype(int) % M
    D1 = U[k] - np.einsum("ij,ij->i", U[k], t3)[:, None] * t3
    D1 /= np.linalg.norm(D1, axis=1)[:, None]
    phi = (2 * np.pi * turns - Delta) * si / s[-1]
    D2 = np.cross(t3, D1)
    D1 = np.cos(phi)[:, None] * D1 + np.sin(phi)[:, None] * D2
    D2 = np.cross(t3, D1)
    acc = ddx(ti)
    kappa = (acc - np.einsum("ij,ij->i", acc, t3)[:, None] * t3) / (np.linalg.norm(dx(ti), axis=1) ** 2)[:, None]
    kappa /= scale
    Omega = np.stack([-np.einsum("ij,ij->i", kappa, D2), np.einsum("ij,ij->i", kappa, D1),
                      np.full(N, (2 * np.pi * turns - Delta) / L)], 1)
    R = np.stack([D1, D2, t3], 2)
    v = np.stack([0 * ti, 0 * ti, -V * np.sin(ti)], 1)
    fields = {"gamma": np.einsum("nak,na->nk", R, v), "omega": np.zeros((N, 3)),
              "Gamma": np.tile([0, 0, 1.0], (N, 1)), "Omega": Omega}
    return fields, (N // 4, 3 * N // 4)


def strand_distance(X, crossing, N):
    """Smallest distance between the two crossing strands (N/16 points either side)."""
    w = N // 16
    A = X[:, crossing[0] - w:crossing[0] + w]
    B = X[:, crossing[1] - w:crossing[1] + w]
    return np.linalg.norm(A[:, :, None] - B[:, None], axis=-1).min(axis=(1, 2))


# -- a collision, NVE, through rodsim ------------------------------------------------------------

N_NVE = 256


@pytest.fixture(scope="module")
def collision(tmp_path_factory, rodsim):
    """rodsim runs of the driven figure-eight, with and without [contact]: (h5 path, stderr)."""
    tmp = tmp_path_factory.mktemp("collision")
    fields, _ = figure_eight(N_NVE, V=0.1)
    with h5py.File(tmp / "fig8.h5", "w") as f:
        f["s"] = np.arange(N_NVE) * L / N_NVE
        for k, v in fields.items():
            f[f"fields/{k}"] = v
    out = {}
    # with; without; and "soft": a barrier of 1 kT, which the strands cross (the passage guard's case)
    for contact, name, barrier in ((True, "with", 100), (False, "without", None), ("soft", "soft", 1)):
        scene = (f"[rod]\nlength = {L}\npoints = {N_NVE}\n"
                 "[initial]\nkind = \"file\"\npath = \"fig8.h5\"\n"
                 "[solver]\nspace = \"spectral\"\ntime = \"dop853\"\nrtol = 1e-10\natol = 1e-10\n"
                 "[output]\nt_end = 300\nframes = 61\nfields = [\"energy_parts\", \"centerline\"]\n"
                 + (f"[contact]\ndiameter_nm = {D_NM}\nbarrier_kT = {barrier}\n" if contact else ""))
        (tmp / f"{name}.toml").write_text(scene)
        p = subprocess.run([str(rodsim), "run", str(tmp / f"{name}.toml"), "-o", str(tmp / f"{name}.h5"), "-q"],
                           capture_output=True, text=True)
        assert p.returncode == (3 if contact == "soft" else 0), p.stderr
        out[contact] = (tmp / f"{name}.h5", p.stderr)
    return out


def test_the_passage_guard_stops_a_run_whose_contact_lets_a_strand_through(collision):
    """rodcore/src/passage_guard.cpp: the 1-kT barrier lets the driven strands pass; the run stops
    with exit 3 naming the passage, its frames before it kept (complete = 0). The 100-kT run's
    summary says the guard kept Lk (control: the same guard, no passage)."""
    path, stderr = collision["soft"]
    assert "strand passage" in stderr and "linking number went from 1 to -1" in stderr, stderr
    with h5py.File(path) as f:
        assert f.attrs["complete"] == 0 and 0 < len(f["time"]) < 61
    with h5py.File(collision[True][0]) as f:
        note = f.attrs["summary.thermal_note"]
    assert "strand-passage guard: Lk = 1 kept" in (note.decode() if isinstance(note, bytes) else note)


def test_two_pieces_driven_at_each_other_do_not_pass(collision):
    _, crossing = figure_eight(N_NVE, V=0.1)
    res = {}
    for contact, (path, stderr) in collision.items():
        if contact == "soft":
            continue
        with h5py.File(path) as f:
            d = strand_distance(f["centerline"][()], crossing, N_NVE)
            Lk = f["topology/Lk"][()]
            res[contact] = (d, Lk, int(f.attrs["topology_jumps"]), stderr)
    d, Lk, jumps, stderr = res[True]
    assert d[0] > 1.9 * D                               # they start 19.5 apart ...
    assert 0.75 * D < d.min() < 0.9 * D                  # ... and stop near the diameter (measured 0.81 d)
    assert np.all(Lk == Lk[0]) and jumps == 0 and "warning" not in stderr
    d, Lk, jumps, stderr = res[False]                  # control: they pass through each other
    assert d.min() < 0.1 * D
    assert set(np.unique(Lk)) == {Lk[0], Lk[0] - 2} and jumps == 1
    assert "warning" in stderr and "changed 1 time(s)" in stderr


def test_contact_force_is_conservative(collision):
    with h5py.File(collision[True][0]) as f:
        parts = {k: f["energy_parts"][k][()] for k in f["energy_parts"]}
        scene = f.attrs["scene"]
    assert "contact" in parts and "[contact]" in scene
    E = sum(parts.values())
    Ec = parts["contact"]
    assert Ec.max() > 0.1                                # the contact took up 11 % of the energy
    assert np.abs(E - E[0]).max() < 1e-4 * Ec.max()      # measured 2.7e-5
    # Control: the rod's own energy is not conserved through the collision.
    assert np.abs((E - Ec) - E[0]).max() > 0.99 * Ec.max()


# -- 300 K ---------------------------------------------------------------------------------------

def test_lk_kept_at_300K_by_contact_and_lost_without():
    """A supercoiled figure-eight (2 extra turns of twist) at 300 K: Langevin, friction 0.01
    per time unit (weak, so that the drive lasts), velocities drawn at 2 kT (the strains
    start cold and take half), the strands driven at each other at 0.25 rod units (1.3
    A/ps, about twice the thermal speed of one grid point), 60 ps."""
    N = 384
    fields, crossing = figure_eight(N, V=0.25, turns=2.0)
    kT = UNITS.kT_to_rod(300.0)
    h = L / N
    rng = np.random.default_rng(5)
    fields["gamma"] = fields["gamma"] + rng.normal(0, np.sqrt(2 * kT / h), (N, 3))
    fields["omega"] = rng.normal(0, 1, (N, 3)) * np.sqrt(2 * kT / h / np.array([1.0, 1.0, 2.0]))
    res = {}
    for contact in (True, False):
        scene = {"rod": {"length": L, "points": N},
                 "thermal": {"temperature_K": 300, "seed": 2, "sample_initial": False,
                             "friction_translational": 0.01, "friction_rotational": 0.01},
                 "solver": {"time": "langevin", "dt": 0.05, "space": "spectral"},
                 "output": {"t_end": 64, "frames": 41, "fields": ["centerline"]}}
        if contact:
            scene["contact"] = {"diameter_nm": D_NM}
        out = rodcore.run(scene, initial=fields)
        res[contact] = (out["topology"]["Lk"], strand_distance(out["centerline"], crossing, N), out["kinetic_kT"])
    Lk, d, kin = res[True]
    Lk0 = Lk[0]
    defined = ~np.isnan(Lk)
    # the seam opens by up to 11 grid spacings later on (closure drift): 33 of 41 defined
    assert defined[:23].all() and defined.sum() >= 30
    assert np.all(Lk[defined] == Lk0)
    assert d.min() > 0.25 * D                            # measured 0.32 d
    assert 1.0 < np.mean(kin[20:]) / kT < 1.5            # the drive included (measured 1.2)
    Lk, d, _ = res[False]                                # control: a strand passage
    defined = ~np.isnan(Lk)
    assert Lk[0] == Lk0 and np.all(Lk[defined][-5:] == Lk0 - 2)
    assert d.min() < 0.1 * D


# -- bad input -----------------------------------------------------------------------------------

@pytest.mark.parametrize("contact, points, message", [
    ({"diameter": 10.0, "diameter_nm": 5.0}, 256, "contact.diameter_nm"),
    ({"barrier_kT": 0.5}, 256, "contact.barrier_kT"),
    ({"stride": 3}, 256, "contact.stride = 3 does not divide rod.points = 256"),
    ({"stride": 16}, 256, "contact.stride = 16 grid spacings"),
    ({"diameter_nm": 200.0}, 256, "not longer than twice the excluded contour"),
])
def test_bad_contact_settings_are_refused(contact, points, message):
    fields, _ = figure_eight(points, V=0.0)
    with pytest.raises(rodcore.InputError, match=message):
        rodcore.Simulation({"rod": {"length": L, "points": points}, "contact": contact}, initial=fields)
