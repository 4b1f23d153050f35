"""The intact duplex's committed results and the prose of docs/intact.md that quotes them.

- The screen (results/dispersion/intact/screen.json, bench/pair_hold_screen.py): the held
  run keeps every pair closed, the neutral phosphates do not (the 97 % criterion), and the
  full-charge junction frays more than the interior; each figure docs/intact.md prints is
  the file's, to its rounding, with a control on a changed file.
- Twist unwrapped on real records: the twist modes' frame-to-frame increments of every
  screen run (the frayed full-charge one included) are near-Gaussian (Pearson kurtosis at
  most 6), while the committed raw full-charge record, read with 3DNA's branch cut, is not
  (the control that must fail the same criterion).
"""
import copy
import json
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import kurtosis

from mdbridge.analysis.mode_spectra import load_npz

ROOT = Path(__file__).resolve().parents[2]
INTACT = ROOT / "results" / "dispersion" / "intact"
DOC = ROOT / "docs" / "intact.md"


def screen() -> dict:
    return json.loads((INTACT / "screen.json").read_text())


def pct(x: float) -> str:
    return f"{100 * x:.1f} %"


def quotes(s: dict) -> list[str]:
    r = s["runs"]
    out = []
    for k in ("full_charge", "hold_3.3A", "neutral_phosphates", "full_charge_turned_79bp"):
        out += [f"| {pct(r[k]['open_fraction'])} |",
                f"| {pct(r[k]['junction_open_fraction'])} / {pct(r[k]['interior_open_fraction'])} |"]
    for k in ("hold_3.3A", "neutral_phosphates", "full_charge_turned_79bp"):
        v = [x["variance_ratio_median"] for x in r[k]["vs_full_charge"].values()]
        out.append(f"{min(v):.2f}-{max(v):.2f}")
    hb = r["hold_3.3A"]["hbond_distances"]
    out.append(f"intact N1-N3 {hb['N1-N3']['mean_A']:.2f} +- {hb['N1-N3']['sd_A']:.2f} A")
    p99 = [x["p99_A"] for x in hb.values()]
    out.append(f"99th percentiles {min(p99):.2f}-{max(p99):.2f} A")
    j = s["junction_by_site"]["full_charge_turned_79bp"]
    out.append(f"the old junction site was open {pct(j['reference_junction_site_open_fraction'])} of the time, "
               f"the new junction {pct(j['own_junction_open_fraction'])}, the other\n  pairs "
               f"{pct(j['elsewhere_open_fraction'])}")
    g = s["junction_geometry"][0]
    out.append(f"within {np.ceil(10 * g['max_abs_z']) / 10:.1f} standard deviations")
    return out


def test_the_held_run_keeps_every_pair_and_the_neutral_one_does_not():
    r = screen()["runs"]
    assert r["hold_3.3A"]["open_fraction"] <= 0.03          # the criterion: >= 97 % closed
    assert r["neutral_phosphates"]["open_fraction"] > 0.03
    assert r["full_charge"]["open_fraction"] > 0.03
    # the hold changes the closed steps' fluctuations by far less than the neutral phosphates
    for name, v in r["hold_3.3A"]["vs_full_charge"].items():
        assert 0.8 < v["variance_ratio_median"] < 1.1, name
        assert r["neutral_phosphates"]["vs_full_charge"][name]["variance_ratio_median"] > 1.3, name


def test_the_unheld_junction_frays_more_than_the_interior_in_seed_1_and_not_once_turned():
    s = screen()
    r = s["runs"]
    for k in ("full_charge", "neutral_phosphates"):
        assert r[k]["junction_open_fraction"] > 3 * r[k]["interior_open_fraction"], k
    # the sequence turned by 79 bp: neither the old junction's sequence (now inside) nor the
    # new junction frays, while the rest does as much as before
    j = s["junction_by_site"]["full_charge_turned_79bp"]
    assert j["rotation_bp"] == 79 and j["reference_junction_site_pairs"] == [77, 78, 79, 80]
    assert j["reference_junction_site_open_fraction"] < 0.02 and j["own_junction_open_fraction"] < 0.02
    assert j["elsewhere_open_fraction"] > 0.05


def test_docs_quote_the_screen_and_a_changed_file_is_caught():
    text = DOC.read_text()
    s = screen()
    for q in quotes(s):
        assert q in text, q
    bad = copy.deepcopy(s)
    bad["runs"]["hold_3.3A"]["open_fraction"] = 0.02
    assert any(q not in text for q in quotes(bad))


def _increment_kurtosis(path: Path) -> np.ndarray:
    s = load_npz(path)[0]
    inc = np.diff(s.twist, axis=0)
    return kurtosis(np.concatenate([inc.real, inc.imag]), axis=0, fisher=False)


@pytest.mark.parametrize("run", ["screen_hold", "screen_neutral", "screen_plain"])
def test_twist_mode_increments_are_near_gaussian_on_real_records(run):
    k = _increment_kurtosis(INTACT / "screen" / run / "mode_series.npz")
    assert k.max() <= 6.0, k


def test_control_the_raw_full_charge_record_fails_the_same_criterion():
    k = _increment_kurtosis(ROOT / "results" / "dispersion" / "mode_series.npz")
    assert k.min() > 6.0, k
    text = DOC.read_text()
    assert f"against {k.min():.1f}-{k.max():.1f} in the committed" in text


def test_every_full_charge_headline_states_its_open_fraction():
    """The README's full-charge vacuum rows carry the open fraction of the records they come
    from (modes.json of the 5-ns seed 1), to the percent; the intact rows their own."""
    h = json.loads((ROOT / "results" / "headline.json").read_text())
    rows = {r["source"]: r["finding"] for r in h["rows"] if "at equilibrium" in r["finding"]}
    disp = ROOT / "results" / "dispersion"
    of1 = json.loads((disp / "modes.json").read_text())["realisations"][0]["open_fraction"]["mean"]
    assert f"{100 * of1:.0f} % of its pairs open" in rows["results/dispersion/prediction.json"]
    # control: a different fraction is not what the row says
    assert f"{100 * of1 + 3:.0f} % of its pairs open" not in rows["results/dispersion/prediction.json"]
    for r in h["rows"]:
        if "dispersion/" in r["source"] and "intact" not in r["source"]:
            assert "open" in r["finding"] or "frayed" in r["finding"] or "Its tension" in r["finding"], r["finding"]
    intact = [r for r in h["rows"] if r["source"].endswith("intact/summary.json")]
    assert intact and "{seeds.seed1.open_fraction" in intact[0]["value"]


def test_the_held_production_keeps_its_pairs():
    """The intact runs' first segment: at least 99.5 % of pair-frames closed (the screen's
    criterion was 97 %), never far past the rule, the restraint energy as docs/intact.md says."""
    text = DOC.read_text()
    fr, mx, en = [], [], []
    for seed in ("seed1", "seed2"):
        seg = INTACT / seed / "segments" / "seg01"
        d = np.load(seg / "integrity.npz")["n1_n3_A"].astype(float)
        fr.append((d > 3.5).mean())
        mx.append(d.max())
        en.append(np.load(seg / "energies.npz")["restraint_kJ_mol"].mean())
    assert max(fr) < 0.005 and max(mx) < 4.0
    assert f"{100 * max(fr):.1f} % of the pair-frames" in text
    assert f"N1-N3 at most\n{max(mx):.1f} A" in text or f"N1-N3 at most {max(mx):.1f} A" in text
    assert f"held {np.mean(en):.0f} kJ/mol in all" in text


@pytest.mark.parametrize("seed", ["seed1", "seed2"])
def test_the_committed_run_state_is_the_finished_run(seed):
    """The finished run's input and final checkpoint (md.tpr, md.cpt: a longer run goes on from
    them) are the ones md.run.json records (mdbridge/md/gromacs/run.py), built with the pair
    hold, its junction equal to the interior in the run input; md.done says 3.5 ns."""
    from mdbridge.md.gromacs.run import _request
    d = INTACT / "run" / seed
    rec = json.loads((d / "md.run.json").read_text())
    req = _request(d, (d / "md_run.mdp").read_text(), rec["gmx"], rec["steps"])
    assert req["inputs_sha256"] == rec["inputs_sha256"]
    assert rec["steps"] == 1750000                              # 3.5 ns at 2 fs
    assert (d / "md.cpt").stat().st_size > 100000 and (d / "md.tpr").is_file()
    assert json.loads((d / "md.done").read_text())["length_ps"] == 3500.0
    build = json.loads((d / "build.json").read_text())
    assert build["pair_hold"]["n_restraints"] == 395 and build["electrostatics"] == "paper"
    assert [(r["ok"], r["interior_steps_compared"]) for r in build["junction_run_input"]] == [(True, 8), (True, 8)]
    assert build["seed"] == int(seed[-1])


def test_paired_is_not_stacked():
    """docs/intact.md's unstacked fractions and counts, from the held production's first two
    segments (steps.npz) and the committed full-charge coarse-graining's per-step means."""
    from mdbridge.md.integrity import UNSTACKED_RISE_A, stacking_summary
    from mdbridge.md.segments import read_steps
    text = " ".join(DOC.read_text().split())
    fracs, counts = [], []
    for seed in ("seed1", "seed2"):
        r = read_steps([INTACT / seed / "segments" / g / "steps.npz" for g in ("seg01", "seg02")])
        assert r["times_ps"][0] == 0.0 and r["times_ps"][-1] >= 787.0
        fracs.append(stacking_summary(r["q"][:, :, 2], r["times_ps"])["unstacked_fraction"])
        counts.append(int((r["q"][:, :, 2].mean(axis=0) > UNSTACKED_RISE_A).sum()))
    assert f"{100 * fracs[0]:.1f} % and {100 * fracs[1]:.1f} % of the step-frames" in text
    assert f"{counts[0]} and {counts[1]} steps have a mean rise above 4.5 A" in text
    cg = json.loads((ROOT / "results" / "dispersion" / "cg_provisional" / "params.json").read_text())
    full = int(sum(s["mean"][2] > UNSTACKED_RISE_A for s in cg["steps"]))
    assert f"in the committed full-charge run {full} steps do" in text and cg["frames_used"] == 8001
    assert full > max(counts)        # holding the pairs removes part of the kinking, not all


def test_the_segments_so_far_as_the_docs_say():
    """docs/intact.md's "So far": the last reduced segment's end per seed, and the committed
    checkpoint's time (gmx dump -cp), which lies inside that segment: the next one starts there."""
    import subprocess
    from mdbridge.md.gromacs.gmx import find_gmx
    text = " ".join(DOC.read_text().split())
    ends, cpts = [], []
    for seed in ("seed1", "seed2"):
        segs = sorted((INTACT / seed / "segments").glob("seg[0-9][0-9]"))
        t0, t1 = json.loads((segs[-1] / "segment.json").read_text())["times_ps"]
        out = subprocess.run([find_gmx(None), "dump", "-cp", str(INTACT / "run" / seed / "md.cpt")],
                             capture_output=True, text=True, check=True).stdout
        t_cpt = float(next(ln.split("=")[1] for ln in out.splitlines() if ln.startswith("t =")))
        assert t0 < t_cpt <= t1 + 0.5          # within the segment, or at its last frame
        ends.append(t1)
        cpts.append(t_cpt)
    assert (f"segments 1-{len(segs)} of both seeds, 0 to {ends[0]:.0f} ps (seed 1) and {ends[1]:.0f} ps (seed 2)"
            in text)
    assert f"checkpoints at {cpts[0]:.1f} and {cpts[1]:.1f} ps" in text


def test_the_segments_steps_join_evenly_spaced():
    """Every segment's steps.npz lies on one 1-ps grid, so the joined record a coarse-graining
    reads is evenly spaced (its window and lag analyses require it) whatever time a segment
    started at; and the joined steps cover what the segments' integrity covers."""
    from mdbridge.md.segments import read_steps
    for seed in ("seed1", "seed2"):
        segs = sorted((INTACT / seed / "segments").glob("seg[0-9][0-9]"))
        r = read_steps([g / "steps.npz" for g in segs])
        assert np.all(np.diff(r["times_ps"]) == 1.0) and r["times_ps"][0] == 0.0
        assert r["times_ps"][-1] >= json.loads((segs[-1] / "segment.json").read_text())["times_ps"][1] - 1.0
