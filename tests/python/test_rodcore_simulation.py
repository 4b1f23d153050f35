"""The Python rodcore.Simulation object: construct from a
scene, step it, read the state, attach callbacks, evaluate the RHS. Truths:
the exact twisted-rod wave (Eq 24, written out in test_rodcore_module.py),
energy conservation, and the one-shot rodcore.run() of the same scene (the
Simulation must give the same bits however it is stepped: its steps are
never shortened to stop at a requested time)."""
import math

import h5py
import numpy as np
import pytest

from test_rodcore_module import exact_wave, wave_scene

import rodcore

A = 0.3  # exact_wave's default amplitude


def wave_initial(N=32):
    s = np.arange(N) * 2 * math.pi / N
    fields, w = exact_wave(s, 0.0, A=A)
    return s, fields, w


def test_stepping_in_pieces_equals_one_run():
    _, init, _ = wave_initial()
    sc = wave_scene(t_end=1.0, frames=5)
    ref = rodcore.run(sc, initial=init)
    sim = rodcore.Simulation(sc, initial=init)
    got = []
    sim.add_observer(lambda f: got.append(f))
    for t in (0.1, 0.37, 0.37, 0.8, 1.0):  # not the frame times; one repeated
        sim.step_to(t)
        assert sim.time == t
    assert [f["t"] for f in got] == list(ref["time"])
    for k, f in enumerate(got):
        for name in ("gamma", "omega", "Gamma", "Omega"):
            assert f["fields"][name].tobytes() == ref["fields"][name][k].tobytes(), (k, name)
        assert f["energy"] == ref["energy"][k]
    for name in ("gamma", "omega", "Gamma", "Omega"):
        assert sim.state[name].tobytes() == ref["fields"][name][-1].tobytes()
    s = sim.summary()
    # Same steps; the extra requested times cost only dense-output stages.
    assert (s["steps"], s["rejected"]) == (ref["summary"]["steps"], ref["summary"]["rejected"])
    assert s["rhs_evaluations"] >= ref["summary"]["rhs_evaluations"]
    # Control: a step cut at t = 0.37 (the scene ends there, then goes on) is
    # a different run: equal to the tolerance, not to the bit.
    cut = rodcore.Simulation(dict(sc, output=dict(sc["output"], t_end=0.37, frames=2)), initial=init)
    cut.step_to(0.37)
    cut.step_to(1.0)
    assert cut.y.tobytes() != sim.y.tobytes()
    np.testing.assert_allclose(cut.y, sim.y, rtol=0, atol=1e-9)


def test_state_between_frames_is_the_exact_wave():
    s, init, w = wave_initial()
    sim = rodcore.Simulation(wave_scene(t_end=2.0, frames=2), initial=init)
    E0 = sim.energy()
    for t in (0.123, 0.9, 1.7):
        sim.step_to(t)
        exact, _ = exact_wave(s, t, A=A)
        for name in ("gamma", "omega", "Gamma", "Omega"):
            np.testing.assert_allclose(sim.state[name], exact[name], rtol=0, atol=1e-9, err_msg=f"{name} t={t}")
        assert abs(sim.energy() - E0) <= 1e-10 * abs(E0)
    assert sim.y.shape == (12 * 32,)
    assert np.array_equal(sim.y.reshape(12, 32)[6], sim.state["Gamma"][:, 0])  # row Gamma1
    parts = sim.energy_parts()
    assert math.isclose(sum(parts.values()), sim.energy(), rel_tol=1e-14)


def test_callback_sees_every_frame_and_can_stop_the_run():
    _, init, _ = wave_initial()
    sc = wave_scene(t_end=1.0, frames=7, fields=("internal", "energy", "centerline"))
    sim = rodcore.Simulation(sc, initial=init)
    seen = []
    sim.add_observer(lambda f: seen.append((f["index"], f["t"], f["centerline"].shape)))
    summary = sim.run()
    assert [i for i, _, _ in seen] == list(range(7))
    assert [t for _, t, _ in seen] == [sim.frame_time(k) for k in range(7)]
    assert seen[-1][1] == 1.0 and all(shape == (32, 3) for *_, shape in seen)
    assert sim.frames_delivered == 7 and summary["steps"] > 0

    class Stop(Exception):
        pass

    def stop_at_3(f):
        if f["index"] == 3:
            raise Stop("enough")

    sim2 = rodcore.Simulation(sc, initial=init)
    sim2.add_observer(stop_at_3)
    with pytest.raises(Stop):
        sim2.run()
    assert sim2.frames_delivered == 3


def test_numpy_initial_fields_equal_the_file_path(tmp_path):
    s, init, _ = wave_initial()
    ic = tmp_path / "ic.h5"
    with h5py.File(ic, "w") as f:  # the documented initial.kind = "file" layout (docs/scenes.md)
        f["s"] = s
        for name, v in init.items():
            f[f"fields/{name}"] = v
    sc = wave_scene(t_end=0.5, frames=3)
    from_file = rodcore.Simulation(dict(sc, initial={"kind": "file", "path": str(ic)}))
    from_arrays = rodcore.Simulation(sc, initial=init)
    for sim in (from_file, from_arrays):
        sim.step_to(0.5)
    assert from_file.y.tobytes() == from_arrays.y.tobytes()
    assert 'kind = "file"' in from_arrays.scene and "initial= arrays" in from_arrays.scene


def test_rhs_is_the_time_derivative_of_the_exact_wave():
    s, init, w = wave_initial()
    sim = rodcore.Simulation(wave_scene(), initial=init)
    t, h = 0.4, 1e-4
    exact, _ = exact_wave(s, t, A=A)
    plus, _ = exact_wave(s, t + h, A=A)
    minus, _ = exact_wave(s, t - h, A=A)
    f = sim.rhs(exact)
    for name in ("gamma", "omega", "Gamma", "Omega"):
        d_dt = (plus[name] - minus[name]) / (2 * h)  # O(h^2) = 1e-8 relative
        np.testing.assert_allclose(f[name], d_dt, rtol=0, atol=2e-8, err_msg=name)
    flat = sim.rhs(np.concatenate([exact[n].T.ravel() for n in ("gamma", "omega", "Gamma", "Omega")]))
    assert flat.shape == (12 * 32,) and np.array_equal(flat.reshape(12, 32)[6], f["Gamma"][:, 0])
    # Control: the rest state of this rod (Gamma = Gamma0, Omega = Omega0) does not move.
    rest = {n: np.zeros((32, 3)) for n in ("gamma", "omega", "Gamma", "Omega")}
    rest["Gamma"][:, 2] = 1.0
    rest["Omega"][:, 2] = 1.0
    assert all(np.abs(v).max() < 1e-14 for v in sim.rhs(rest).values())
    with pytest.raises(ValueError, match="12 N"):
        sim.rhs(np.zeros(5))


def test_add_output_writes_what_run_writes(tmp_path):
    _, init, _ = wave_initial()
    sc = wave_scene(t_end=0.5, frames=4)
    rodcore.run(sc, initial=init, output=tmp_path / "run.h5")
    sim = rodcore.Simulation(sc, initial=init)
    sim.add_output(tmp_path / "sim.h5")
    sim.run()
    with h5py.File(tmp_path / "run.h5") as a, h5py.File(tmp_path / "sim.h5") as b:
        assert b.attrs["complete"] == 1
        for name in ("time", "s", "energy", "fields/gamma", "fields/Gamma", "fields/omega", "fields/Omega"):
            assert a[name][()].tobytes() == b[name][()].tobytes(), name


def test_bad_step_requests_are_value_errors():
    _, init, _ = wave_initial()
    sim = rodcore.Simulation(wave_scene(), initial=init)
    sim.step_to(0.5)
    with pytest.raises(ValueError, match="current time"):
        sim.step_to(0.2)
    with pytest.raises(ValueError, match="callable"):
        sim.add_observer(3)
