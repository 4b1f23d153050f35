"""The 21-bp duplex in water at a set tension (results/water21, written by
`python3 -m dnarod.steps.water results/water21 WORK/T0 WORK/T30`; docs/md.md, "DNA in water: the
21-bp runs").

- The runs are what they claim: CHARMM27 in TIP3P with 150 mM NaCl, semi-isotropic at 0 and 30 pN,
  1000 and 200 ps; the pairs intact in at least 97 % of the pair-frames, the junction and the side
  images checked.
- The coarse-graining's refusal (too few independent frames for a stiffness) is recorded with
  its numbers; the mean step parameters, which need no such floor, are set against published ones.
- Test 2 asks the DNA: the length gained from 0 to 30 pN is resolved from zero.
- The docs quote summary.json, each figure from there, and say what is not met.
"""
import json
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
WATER = ROOT / "results" / "water21"


def load(name):
    return json.loads((WATER / name).read_text())


def doc():
    return " ".join((ROOT / "docs" / "md.md").read_text().split())


def test_the_runs_are_what_they_claim():
    s = load("summary.json")
    assert set(s["runs"]) == {"T0", "T30"}
    for name, T, ps in (("T0", 0.0, 1000.0), ("T30", 30.0, 200.0)):
        r = s["runs"][name]
        assert r["tension_set_pN"] == T and r["length_ps"] == ps
        assert (r["forcefield"], r["water"], r["salt_mM"]) == ("charmm27", "tip3p", 150.0)
        assert r["n_atoms"] == 17002 and r["n_cation"] - r["n_anion"] == 42
        assert r["intact_fraction"] >= 0.97 and r["integrity_ok"] and r["junction_ok"] and r["side_image_ok"]
        g = load(f"{name}/integrity.json")
        assert abs(1.0 - g["open_fraction"] - r["intact_fraction"]) < 1e-12
        c = load(f"{name}/checks.json")
        assert c["solvent"]["axial_tension_pN"] == T and c["times_ps"][1] >= ps - 0.2


def test_the_coarse_graining_refusal_is_recorded_with_its_reason():
    """1 ns is too short for the coarse-graining's 50 independent frames: the refusal, with the
    numbers, is in the summary, not a silent gap."""
    cg = load("summary.json")["runs"]["T0"]["cg"]
    assert "too few frames" in cg["refused"] and "19.1 independent samples" in cg["refused"]


def test_the_stretch_is_resolved():
    st = load("stretch.json")
    assert st["tensions_pN"] == [0.0, 30.0] and st["resolved_from_zero_2_sigma"]
    assert load("summary.json")["stretch"]["with_published_S"]["S_pN"] == 1280.0


def test_the_docs_quote_the_summary():
    s, d = load("summary.json"), doc()
    t0, t30 = s["runs"]["T0"], s["runs"]["T30"]
    assert (f"{100 * t0['intact_fraction']:.1f} % and {100 * t30['intact_fraction']:.1f} % of the pair-frames "
            f"intact") in d
    assert f"{t0['tension_pN']:.0f} +- {t0['tension_err_pN']:.0f} pN at 0 pN set, {t30['tension_pN']:.0f} +- " \
           f"{t30['tension_err_pN']:.0f} at 30" in d
    assert f"about {t0['length_ps_for_sigma_T_max'] / 1000:.0f} ns per tension" in d
    assert not t0["test_1"]["sigma_T_ok"] and "sigma_T <= 3 pN is not met" in d
    st = s["stretch"]
    assert (f"30 pN adds {st['delta_length_nm']:.3f} +- {st['delta_length_err_nm']:.3f} nm ({st['delta_rise_A']:.3f} A "
            f"per step)") in d
    p = st["with_published_S"]
    assert f"S = 1280 +- 70 pN predicts {p['predicted_nm']:.3f} +- {p['predicted_err_nm']:.3f} nm" in d
    assert (f"own box fluctuation, S = {t0['S_isotension_pN']:.0f} +- {t0['S_isotension_err_pN']:.0f} pN, "
            f"{st['predicted_nm']:.3f} nm") in d
    assert (f"force-extension modulus is {st['S_force_extension_pN']:.0f} +- {st['S_force_extension_err_pN']:.0f} "
            f"pN. **Neither agrees") in d
    assert not st["consistent_2_sigma"] and not p["consistent_2_sigma"]
    L = t0["length_blocks_100_ps_nm"]
    assert f"wanders over {min(L):.2f}-{max(L):.2f} nm in 100-ps means" in d
    assert "Coarse-graining refused**: 19 independent frames" in d
    sm = t0["step_means"]
    m, ol = sm["means"], sm["olson1998_same_sequence"]
    assert (f"rise {m['rise']['mean']:.2f} +- {m['rise']['err']:.2f} A, roll {m['roll']['mean']:.1f} +- "
            f"{m['roll']['err']:.1f} deg, slide {m['slide']['mean']:.2f} +- {m['slide']['err']:.2f} A") in d
    assert f"Olson 1998 at our sequence {ol['rise']:.2f}, {ol['roll']:.1f}, {ol['slide']:.2f}" in d
    assert f"The twist, {m['twist']['mean']:.2f} +- {m['twist']['err']:.2f} deg, is the box's" in d
    ap = sm["against_published"]
    assert [ap[f"mean_{k}"]["published"] for k in ("rise", "roll", "slide")] == [3.4, 3.9, -0.18]
    assert "CHARMM27's published 3.4, 3.9, -0.18" in d
    sp = json.loads((ROOT / "bench" / "results" / "water_speed.json").read_text())
    deb, own = (r["md"]["ns_per_day"] for r in sp)
    assert f"{deb:.1f} ns/day with Debian's SSE4.1 gmx, {own:.1f} built" in d and f"{own / deb:.1f}x" in d
    assert f"the 1-ns run {t0['ns_per_day']:.1f} ns/day on two" in d
