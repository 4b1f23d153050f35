"""coarse-grain -> dna-rod without hand-set options: a per-step file's rod is closed in a box
of n_bp x its own mean rise (workflows/commands/dna_rod.py). A coarse-grained 21-bp record
had a mean rise of 3.438 A; in the default box of 3.38 A per step its rod was compressed until
the shooting failed, unless --box-A was set by hand. Here an Olson 1998 step file with its
rise moved to 3.438 A: the default box is its own, and the rod in it is far less loaded than
in the 3.38-A box (the control)."""
import json

import numpy as np

from dna_models.units import Units
from dnarod.cli import main
from mdbridge.rod.material.stepfile import read_steps, write_steps

SEQ = "CGCGAATTCGCGCGCGAATTC"


def test_the_mean_rise_sets_the_box(tmp_path):
    assert main(["dna-rod", "--sequence", SEQ, "--params", "olson1998", "-o", str(tmp_path / "a")]) == 0
    sm = read_steps(tmp_path / "a" / "steps.h5")
    sm.step_params[:, 2] += 3.438 - sm.step_params[:, 2].mean()
    write_steps(tmp_path / "cg.h5", sm)
    assert main(["dna-rod", "--sequence", SEQ, "--params", str(tmp_path / "cg.h5"), "-o", str(tmp_path / "own")]) == 0
    own = json.loads((tmp_path / "own" / "rest.json").read_text())
    assert np.isclose(Units.paper().length_to_A(own["box_length"]), 21 * 3.438)
    # the control: the MD's default box, 3.38 A per step, compresses the same rod
    assert main(["dna-rod", "--sequence", SEQ, "--params", str(tmp_path / "cg.h5"), "--box-A", str(21 * 3.38),
                 "-o", str(tmp_path / "md_box")]) == 0
    md_box = json.loads((tmp_path / "md_box" / "rest.json").read_text())
    assert md_box["tension_pN"] < 0 and abs(own["tension_pN"]) < 0.5 * abs(md_box["tension_pN"])
