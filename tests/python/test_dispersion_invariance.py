"""`python -m dnarod.steps.dispersion invariance` (workflows/steps/dispersion.py): runs that
differ from a reference in one setting, mode by mode, with the bend modes n >= 3 pooled.

Synthetic modes.json records with a known relative shift: the pooled mean must be that shift,
its error the inverse-variance one of the stated errors; an unresolved mode (reason set)
must not enter; a bad NAME=FILE is an input error (exit 2)."""
import json

import numpy as np
import pytest

from dnarod.steps import dispersion as step


def _modes(path, omega, err, refuse=()):
    modes = [{"kind": k, "n": n, "omega_per_ps": None if (k, n) in refuse else omega(k, n),
              "omega_err_per_ps": None if (k, n) in refuse else err(k, n),
              "reason": "no peak" if (k, n) in refuse else None}
             for k in ("bend", "twist", "stretch") for n in range(1, 9)]
    path.write_text(json.dumps({"modes": modes}))
    return path


def test_pooled_shift_is_the_known_one(tmp_path):
    shift = 0.02
    ref = _modes(tmp_path / "ref.json", lambda k, n: 0.01 * n, lambda k, n: 0.0002 * n)
    run = _modes(tmp_path / "run.json", lambda k, n: 0.01 * n * (1 + shift), lambda k, n: 0.0003 * n,
                 refuse={("bend", 5)})
    rec = step.compare_runs({"ref": ref, "run": run}, "ref", tmp_path / "inv.json")
    pooled = rec["pooled_bend_n3"]["run"]
    assert pooled["modes"] == 5                       # bend n = 3, 4, 6, 7, 8 (n = 5 refused)
    assert pooled["mean"] == pytest.approx(shift, rel=1e-12)
    rel_err = np.hypot(0.02, 0.03 / (1 + shift))   # each mode: the reference 2 %, the run 3 % of 1 / (1 + shift)
    assert pooled["err"] == pytest.approx(rel_err / np.sqrt(5), rel=1e-9)
    assert pooled["chi2"] == pytest.approx(0.0, abs=1e-18)
    assert json.loads((tmp_path / "inv.json").read_text())["rows"][0]["run_omega_per_ps"] == pytest.approx(0.0102)
    # per kind, z = (run - ref) / combined error: for every n the shift over 0.01 n sqrt(0.02^2 + 0.03^2)
    by_kind = rec["differences_by_kind"]["run"]
    z = shift / np.hypot(0.02, 0.03)
    assert by_kind["bend"]["dof"] == 7 and by_kind["bend"]["n"] == [1, 2, 3, 4, 6, 7, 8]
    assert by_kind["twist"]["chi2"] == pytest.approx(8 * z ** 2, rel=1e-9)


def test_bad_pair_is_an_input_error(tmp_path, capsys):
    assert step.main(["invariance", "ref", "-o", str(tmp_path / "x.json")]) == 2
    assert "NAME=FILE" in capsys.readouterr().err
    assert not (tmp_path / "x.json").exists()
