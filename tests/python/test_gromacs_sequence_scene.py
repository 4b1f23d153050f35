"""`dnarod build-md` on a sequence-dependent scene (`dnarod dna-rod`): the all-atom
duplex is the scene's DNA, placed on the closed rest state's base-pair frames.

Truths: the sequence the material file records (written by dna-rod from the given
one); the rod's own t = 0 frames (rodcore's reconstruction of the rest state); the
3DNA step parameters of the built atoms (mdbridge.geometry, re-analysed from
conf.gro, the periodic junction included); grompp's acceptance of the files."""
import json
import subprocess

import h5py
import numpy as np
import pytest

from dna_models.sequence import random_sequence
from mdbridge.geometry.steps import step_parameters_along

N_BP = 21


@pytest.fixture(scope="module")
def built(gmx, tmp_path_factory):
    from dnarod.cli import main
    d = tmp_path_factory.mktemp("seqmd")
    assert main(["dna-rod", "--random", str(N_BP), "--seed", "1", "--params", "olson1998", "--t-end-ps", "1",
                 "-o", str(d / "rod")]) == 0
    assert main(["build-md", str(d / "rod" / "scene.toml"), "-o", str(d / "md"), "--temperature", "0",
                 "--ps", "0.2", "--threads", "1", "--gmx", str(gmx)]) == 0
    return d


def _rod_steps(d):
    """Step parameters of the rod's base pairs at t = 0 (closing step included): the
    frames rodcore reconstructs from the closed rest state, the closing frame being
    frame 0 moved by the period vector P = int d_k Gamma_k ds."""
    import rodcore
    out = rodcore.run(str(d / "rod" / "scene.toml"), set=["output.t_end=0.01", "output.frames=2",
                                                          'output.fields=["internal","centerline","directors"]'])
    r, D, G = out["centerline"][0], out["directors"][0], out["fields"]["Gamma"][0]
    N = len(out["s"])
    P = np.einsum("ixk,ik->x", D, G) * (out["s"][1] - out["s"][0])
    from dna_models.units import Units
    ell = Units.paper().ell_A
    stride = N // N_BP
    R, o = D[::stride], r[::stride] * ell
    R = np.concatenate([R, R[:1]])
    o = np.concatenate([o, o[:1] + P * ell])
    return step_parameters_along(R, o), np.linalg.norm(P) * ell


def test_built_duplex_is_the_scenes_dna_on_its_rest_frames(built, gmx):
    d = built
    b = json.loads((d / "md" / "build.json").read_text())
    seq = random_sequence(N_BP, seed=1)
    with h5py.File(d / "rod" / "material.h5") as f:
        assert f.attrs["sequence"] == seq
    assert b["sequence"] == seq and b["sequence_source"] == "the scene's material file"
    # grompp accepts the files (run here again, on its own)
    p = subprocess.run([str(gmx), "grompp", "-f", "md.mdp", "-c", "conf.gro", "-p", "topol.top", "-o", "check.tpr",
                        "-po", "check_out.mdp"], cwd=d / "md", capture_output=True, text=True)
    assert p.returncode == 0, p.stderr[-2000:]
    # 3DNA step parameters of the built atoms (periodic: the junction step too) against the rod's
    from mdbridge.md.gromacs.inputs import _frames_of_gro
    o, R = _frames_of_gro(d / "md" / "conf.gro", N_BP)
    box = np.array(b["box_nm"]) * 10.0
    md_steps = step_parameters_along(R, o, box=np.concatenate([box, [90.0, 90.0, 90.0]]), periodic=True)
    rod_steps, period_A = _rod_steps(d)
    assert b["box_nm"][1] * 10 == pytest.approx(period_A, abs=1e-6)   # the helix along lab Y, one period
    err = np.abs(md_steps - rod_steps)
    # the builder's precision (docs/builder.md: rigid templates on the frames, frames
    # re-analysed to ~0.01 A / 0.1 deg): 0.03 A and 0.3 deg per step parameter
    assert err[:, :3].max() < 0.03 and err[:, 3:].max() < 0.3, (err[:, :3].max(), err[:, 3:].max())
    # control: the rod's steps are the sequence's, far from uniform B-DNA (so this can fail)
    uniform = np.array([0.0, 0.0, 3.38, 0.0, 0.0, 360 / 10.5])
    assert np.abs(md_steps - uniform)[:, 3:].max() > 3.0


def test_build_md_refuses_a_different_sequence(built, tmp_path, capsys):
    from dnarod.cli import main
    assert main(["build-md", str(built / "rod" / "scene.toml"), "-o", str(tmp_path / "x"), "--sequence",
                 "A" * N_BP, "--temperature", "0", "--ps", "0.2"]) == 2
    assert "differs from the sequence of" in capsys.readouterr().err
