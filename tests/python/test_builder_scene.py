"""Rod -> all-atom: the scene route of the builder.

A straight, intrinsically twisted rod along lab Y (the paper's Sec 6.1 frame:
d3 = Y, d1 = (sin, 0, cos)(Omega03 s), d2 = (cos, 0, -sin)(Omega03 s), Eq 47)
with 2 turns over 20 base pairs IS ideal B-DNA (rise 3.38 A, twist 36 deg):
the frames handed to the builder must be that helix, its period vector the
box along Y, and the periodic duplex chemically closed. With the real rodcore
module (build/python), the dna_planar scene goes the same way."""
import sys
import types

import numpy as np

from dna_models.units import Units
from mdbridge.md.builder import build_duplex, check_chemistry
from mdbridge.md.builder.scene import frames_from_rod_output
from mdbridge.geometry import step_parameters_along

N_BP, TURNS = 20, 2


def straight_twisted_rod(n_bp=N_BP, turns=TURNS, per_bp=2):
    u = Units.paper()
    L = n_bp * 3.38 / u.length_to_A(1.0)
    N = n_bp * per_bp
    s = np.arange(N) * L / N
    th = 2 * np.pi * turns / L * s
    d1 = np.stack([np.sin(th), 0 * th, np.cos(th)], axis=-1)
    d2 = np.stack([np.cos(th), 0 * th, -np.sin(th)], axis=-1)
    d3 = np.tile([0.0, 1.0, 0.0], (N, 1))
    # at rest, so the three output frames the builder asks for are all the same
    directors = np.tile(np.stack([d1, d2, d3], axis=-1), (3, 1, 1, 1))   # (3, N, 3, 3), last index k
    centerline = np.tile(np.stack([0 * s, s, 0 * s], axis=-1), (3, 1, 1))
    Gamma = np.tile([0.0, 0.0, 1.0], (3, N, 1))
    return {"time": np.array([0.0, 0.5e-6, 1e-6]), "s": s, "centerline": centerline,
            "directors": directors,
            "fields": {"Gamma": Gamma, "Omega": np.tile([0, 0, 2 * np.pi * turns / L], (3, N, 1)),
                       "gamma": 0 * Gamma, "omega": 0 * Gamma}}


def test_rod_frames_are_ideal_bdna_and_close_through_the_box():
    fr = frames_from_rod_output(straight_twisted_rod(), N_BP)
    np.testing.assert_allclose(fr.period, [0, N_BP * 3.38, 0], atol=1e-9)
    np.testing.assert_allclose(fr.box, [0, N_BP * 3.38, 0], atol=1e-9)
    steps = step_parameters_along(fr.R, fr.origins)
    np.testing.assert_allclose(steps, np.tile([0, 0, 3.38, 0, 0, 36.0], (N_BP - 1, 1)), atol=1e-9)
    s = build_duplex("ACGT" * 5, fr.origins, fr.R, periodic_box=fr.box)
    rep = check_chemistry(s)
    assert rep.ok(), str(rep)
    for links in rep.links:
        assert links.junction is not None and abs(links.junction.distance - 1.6) < 0.1


def test_build_dna_scene_command_with_a_stand_in_rodcore(tmp_path, capsys, monkeypatch):
    """The command's glue (scene reading, n_bp from initial.bp, the t = 0 run,
    --periodic box from the rod) with rodcore.run answering the analytic rod."""
    from dnarod.cli import main
    seen = {}

    def run(scene):
        seen.update(scene)
        return straight_twisted_rod()
    monkeypatch.setitem(sys.modules, "rodcore", types.SimpleNamespace(run=run))
    scene = tmp_path / "dna20.toml"
    scene.write_text(f'[initial]\nkind = "dna_planar"\nbp = {N_BP}\nturns = {TURNS}\n'
                     '[output]\nt_end = 100.0\nframes = 50\nfields = ["energy"]\n')
    code = main(["build-dna", "--scene", str(scene), "--seed", "3", "--periodic",
                 "-o", str(tmp_path / "rod.pdb")])
    out = capsys.readouterr().out
    assert code == 0, out
    assert set(seen["output"]["fields"]) >= {"centerline", "directors", "internal"}
    assert "verdict: OK" in out and "junction through the box" in out
    assert f"{N_BP * 3.38:.1f}" in out


def test_real_rodcore_dna_planar(tmp_path):
    import rodcore
    from mdbridge.md.builder.scene import frames_from_scene
    scene = tmp_path / "dna20.toml"
    scene.write_text(f'[initial]\nkind = "dna_planar"\nbp = {N_BP}\nturns = {TURNS}\n'
                     'A_v_A_per_ps = 1.0\n[output]\nt_end = 1.0\nframes = 2\n')
    fr = frames_from_scene(scene)
    assert rodcore is not None
    np.testing.assert_allclose(np.abs(fr.box), [0, N_BP * 3.38, 0], atol=1e-6)
    steps = step_parameters_along(fr.R, fr.origins)
    np.testing.assert_allclose(steps[:, 2], 3.38, atol=1e-6)
    np.testing.assert_allclose(steps[:, 5], 36.0, atol=1e-6)
    rep = check_chemistry(build_duplex("ACGT" * 5, fr.origins, fr.R, periodic_box=fr.box))
    assert rep.ok(), str(rep)
