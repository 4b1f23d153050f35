"""Every workflows/scenes/paper_*.toml is a valid scene that runs (shortened here)."""
import tomllib
from pathlib import Path

import numpy as np
import pytest

from mdbridge.rod.run import run_scene

SCENES = sorted((Path(__file__).resolve().parents[2] / "workflows" / "scenes").glob("paper_*.toml"))


def test_there_are_paper_scenes():
    assert len(SCENES) >= 6


@pytest.mark.parametrize("path", SCENES, ids=lambda p: p.name)
def test_scene_runs(path):
    with open(path, "rb") as f:
        sc = tomllib.load(f)
    sc["output"].update(t_end=min(0.2, sc["output"]["t_end"]), frames=2)
    run = run_scene(sc)
    assert run.time[-1] == pytest.approx(sc["output"]["t_end"])
    assert all(np.all(np.isfinite(v)) for v in run.fields.values())
