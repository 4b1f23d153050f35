"""The MD analysis pairs the bases as built, so a pair that frays during the run
does not stop it (the 600-ps main job stopped on exactly this: 5 of 158 pairs open).

The tiny comparison's MD (tiny_run fixture) is copied, one base of strand I is pulled
8 A out of its pair in every frame, and `dnarod.steps.analyse md` must still analyse
it. Control: pairing by distance on the same trajectory fails."""
import shutil
import warnings

import numpy as np
import pytest

from dna_models.errors import InputError


def test_md_analysis_survives_a_frayed_pair(tiny_run, tmp_path):
    import MDAnalysis as mda
    from mdbridge.analysis import BasePairTrajectory
    from dnarod.steps.analyse import analyse_md
    out = tiny_run[0]
    md = next((out / "md").iterdir())
    frayed = tmp_path / "md"
    shutil.copytree(md, frayed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        u = mda.Universe(str(frayed / "md.tpr"), str(frayed / "md.xtc"))
        base = u.select_atoms("resid 5 and not (name P OP1 OP2 O1P O2P O5' C5' C4' O4' C3' O3' C2' C1' "
                              "H5' H5'' H4' H3' H2' H2'' H1')")
        assert base.n_atoms > 5
        with mda.Writer(str(tmp_path / "frayed.xtc"), u.atoms.n_atoms) as w:
            for _ in u.trajectory:
                base.positions = base.positions + np.array([8.0, 0.0, 0.0])
                w.write(u.atoms)
    shutil.move(tmp_path / "frayed.xtc", frayed / "md.xtc")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        u2 = mda.Universe(str(frayed / "md.tpr"), str(frayed / "md.xtc"))
        with pytest.raises(InputError, match="unpaired"):     # the control: pairing by distance
            BasePairTrajectory.from_universe(u2)
    s = analyse_md(out / "rod" / "Av5" / "scene.toml", frayed, tmp_path / "analysis", n_boot=5)
    assert s["n_bp"] == 21 and s["bp_intact_fraction_min"] < 1.0
