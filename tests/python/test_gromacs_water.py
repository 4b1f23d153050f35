"""The periodic, ligated duplex in water (build-md --solvent, --salt-mM, --axial-tension-pN),
built for real with GROMACS on the 21-bp Table 1 rod of test_gromacs_build.py turned onto
lab Z, against a vacuum build of the same DNA; every check has a control that must fail.

The numbers the checks are held to come from here: the ion counts from the rule written
out by hand (N_salt = round(N_water C / 55.32 M) plus 42 counterions for 21 bp at -1 e per
nucleotide), the tension formulas from 1 pN/nm^2 = 10 bar, the charges from the run input."""
from __future__ import annotations

import json
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest

from dna_models.errors import InputError
from mdbridge.md.build import BuildRequest
from mdbridge.md.builder import build_duplex
from mdbridge.md.gromacs.box import plan_box
from mdbridge.md.gromacs.gro import read_gro, write_gro
from mdbridge.md.gromacs.inputs import build_inputs
from mdbridge.md.gromacs.mdp import MdSettings, read_mdp_value, render_md
from mdbridge.md.gromacs.rod import rotate_rod
from mdbridge.md.gromacs.solvent import Solvent, ion_counts, solvent_of
from mdbridge.md.gromacs.solvent_checks import (dna_first_check, ion_count_check, total_charge_check,
                                                water_in_duplex_check)
from mdbridge.md.gromacs import tension
from test_gromacs_build import table1_rod

N_BP = 21
SALT_MM = 150.0
TENSION_PN = 30.0
SEED = 5
# its junction steps (C-G on strand I, C-G on strand II: GGGATCGATGCCTGCAACGTC) occur inside too,
# so the junction check has interior steps to compare with
SEQUENCE = "GACGTTGCAGGCATCGATCCC"
# cyclic permutation (a proper rotation): lab Y -> Z, Z -> X, X -> Y
Q = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def _make(d: Path, gmx: str, solvent: Solvent | None, settings: MdSettings):
    rod = table1_rod(N_BP, 2)
    swing = rod.origins_A[None] + np.array([[[0, 0, 8.0]], [[0, 0, -8.0]]])
    rod, centerline = rotate_rod(rod, np.concatenate([rod.origins_A[None], swing]), Q)
    seq = SEQUENCE
    st = build_duplex(seq, rod.origins_A, rod.R, periodic_box=rod.closure_length_A * Q[:, 1])
    box = plan_box(centerline, rod.origins_A, rod.closure_length_A, rod_run_ps=1.0)
    assert box.axis == 2
    t0 = time.time()
    info = build_inputs(d, st, rod, box, sequence=seq, temperature_K=300.0, seed=SEED, settings=settings,
                        gmx=gmx, solvent=solvent, protocol="paper")
    return info, time.time() - t0


@pytest.fixture(scope="module")
def vacuum(gmx, tmp_path_factory):
    d = tmp_path_factory.mktemp("vacuum")
    info, _ = _make(d, gmx, None, MdSettings(nsteps=10))
    return d, info


@pytest.fixture(scope="module")
def water(gmx, tmp_path_factory):
    d = tmp_path_factory.mktemp("water")
    info, seconds = _make(d, gmx, Solvent("tip3p", SALT_MM),
                          MdSettings(nsteps=10, thermostat=True, axial_tension_pN=TENSION_PN))
    print(f"water build: {seconds:.0f} s, {info['solvent']['n_atoms']} atoms")
    return d, info


# --- the build ---------------------------------------------------------------------------

def test_the_solvated_build_records_its_checks(water):
    d, info = water
    checks = info["solvent"]["checks"]
    assert checks["ok"] and all(checks[k]["ok"] for k in ("total_charge", "ion_counts", "water_in_duplex",
                                                          "dna_topology"))
    assert (d / "conf.gro").is_file() and info["md_settings"]["solvated"]


def test_the_run_input_is_neutral(water, gmx):
    d, _ = water
    subprocess.run([gmx, "grompp", "-f", "md.mdp", "-c", "conf.gro", "-p", "topol.top", "-o", "t.tpr",
                    "-po", "t.mdp"], cwd=d, check=True, capture_output=True)
    import MDAnalysis as mda
    u = mda.Universe(str(d / "t.tpr"))
    assert abs(u.atoms.charges.sum()) < 1e-3
    assert abs(u.atoms[:water[1]["n_atoms"]].charges.sum() + 2 * N_BP) < 1e-3   # the DNA: -1 e per nucleotide


def test_ion_counts_follow_the_rule_by_hand(water):
    d, info = water
    g = read_gro(d / "conf.gro")
    n_water = info["solvent"]["ions"]["n_water_for_salt"]
    n_salt = round(n_water * SALT_MM / 1000 / (996.5 / 18.015))
    assert g.resname.count("NA") == n_salt + 2 * N_BP
    assert g.resname.count("CL") == n_salt
    assert g.resname.count("SOL") // 3 == n_water - 2 * n_salt - 2 * N_BP
    # ~150 mM in the water's volume: about 1 salt pair per 370 waters
    assert n_salt == pytest.approx(n_water / 369, abs=1.0)


def test_ion_count_rule_against_hand_values():
    assert ion_counts(5532, 100.0, -42.0)["n_cation"] == 10 + 42       # 5532 x 0.1 / 55.315 = 10.0
    assert ion_counts(5532, 100.0, -42.0)["n_anion"] == 10
    assert (ion_counts(1000, 0.0, +3.0)["n_cation"], ion_counts(1000, 0.0, +3.0)["n_anion"]) == (0, 3)
    with pytest.raises(Exception, match="not an integer"):
        ion_counts(1000, 0.0, -41.5)


def test_no_water_inside_the_duplex(water):
    d, info = water
    assert info["solvent"]["checks"]["water_in_duplex"]["n_water_oxygens_near_rings"] == 0


def test_control_a_water_in_the_duplex_is_detected(water):
    d, _ = water
    g = read_gro(d / "conf.gro")
    assert water_in_duplex_check(g, "SOL")["ok"]
    # one water moved onto the centre of base pair 11's rings (between the two bases' rings)
    ring = [i for i, (r, n) in enumerate(zip(g.resid, g.name)) if r in (11, 2 * N_BP + 1 - 11)
            and n in ("N1", "C2", "N3", "C4", "C5", "C6")]
    centre = g.x[ring].mean(axis=0)
    ow = g.name.index("OW")
    g.x[ow:ow + 3] += centre - g.x[ow]
    bad = water_in_duplex_check(g, "SOL")
    assert not bad["ok"] and bad["atoms"] == [ow + 1] and bad["closest_A"] < 2.5


def test_the_dna_topology_is_the_vacuum_builds(water, vacuum):
    (dw, iw), (dv, iv) = water, vacuum

    def body(path):     # pdb2gmx's header comments carry the time of the run
        return [ln for ln in path.read_text().splitlines() if not ln.startswith(";")]
    itps = sorted(dv.glob("*.itp"))
    assert len(itps) == 6
    for itp in itps:
        assert body(dw / itp.name) == body(itp), itp.name
    gw, gv = read_gro(dw / "conf.gro"), read_gro(dv / "conf.gro")
    n = gv.n_atoms
    assert n == iw["n_atoms"] == iv["n_atoms"]
    assert gw.name[:n] == gv.name and gw.resname[:n] == gv.resname and np.all(gw.resid[:n] == gv.resid)
    assert set(gw.resname[n:]) == {"SOL", "NA", "CL"}
    # the DNA where the vacuum build put it (no minimisation in either)
    assert np.abs(gw.x[:n] - gv.x).max() < 2e-3
    # the junction as in vacuum, on the run input
    assert [j["ok"] for j in iw["junction_run_input"]] == [True, True]
    assert all(j["interior_steps_compared"] >= 1 for j in iw["junction_run_input"])
    keys = ("molecule", "junction_bases", "interior_steps_compared", "n_interactions", "n_exclusion_lists", "ok")
    assert [{k: j[k] for k in keys} for j in iw["junction_run_input"]] == \
        [{k: j[k] for k in keys} for j in iv["junction_run_input"]]


def test_controls_a_changed_dna_topology_and_a_charged_system_are_detected(water, gmx, tmp_path):
    d, info = water
    rec = info["solvent"]
    conf, top = read_gro(d / "conf.gro"), d / "topol.top"
    dna = read_gro(d / "conf.gro")
    n = info["n_atoms"]
    dna = type(dna)(dna.title, dna.resid[:n], dna.resname[:n], dna.name[:n], dna.x[:n], None, dna.box)
    args = (["DNA_chain_A", "DNA_chain_B"], rec["dna_itp_sha256"], {"SOL", "NA", "CL"}, {"SOL", "NA", "CL"})
    assert dna_first_check(top, conf, dna, *args)["ok"]
    # an .itp changed by one charge digit
    for f in d.glob("topol_DNA_chain_A.itp"):
        (tmp_path / f.name).write_text(f.read_text().replace("-0.", "-1.", 1))
    (tmp_path / "topol_DNA_chain_B.itp").write_bytes((d / "topol_DNA_chain_B.itp").read_bytes())
    (tmp_path / "topol.top").write_text(top.read_text())
    assert not dna_first_check(tmp_path / "topol.top", conf, dna, *args)["ok"]
    # the molecules in another order
    lines = top.read_text().replace("DNA_chain_A         1\nDNA_chain_B         1\n",
                                    "DNA_chain_B         1\nDNA_chain_A         1\n")
    (tmp_path / "topol.top").write_text(lines)
    assert not dna_first_check(tmp_path / "topol.top", conf, dna, *args)["ok"]
    # a charged system: one sodium fewer in coordinates and topology
    k = conf.resname.index("NA")
    keep = np.arange(conf.n_atoms) != k
    resnames = [r for r, m in zip(conf.resname, keep) if m]
    names = [a for a, m in zip(conf.name, keep) if m]
    write_gro(tmp_path / "conf.gro", type(conf)(conf.title, conf.resid[keep], resnames, names, conf.x[keep], None,
                                                conf.box))
    na = conf.resname.count("NA")
    text = top.read_text().replace(f"\nNA               {na}\n", f"\nNA               {na - 1}\n")
    assert text != top.read_text()
    (tmp_path / "topol.top").write_text(text)
    for f in d.glob("*.itp"):
        (tmp_path / f.name).write_bytes(f.read_bytes())
    # the vacuum mdp: PME would refuse the charged system outright (a grompp warning)
    (tmp_path / "v.mdp").write_text(render_md(MdSettings(nsteps=0)))
    subprocess.run([gmx, "grompp", "-f", "v.mdp", "-c", "conf.gro", "-p", "topol.top", "-o", "q.tpr",
                    "-po", "q_out.mdp"], cwd=tmp_path, check=True, capture_output=True)
    charged = total_charge_check(tmp_path / "q.tpr")
    assert not charged["ok"] and charged["total_charge_e"] == pytest.approx(-1.0, abs=1e-3)
    # and the ion count check sees the missing sodium
    lost = read_gro(tmp_path / "conf.gro")
    assert not ion_count_check(lost, rec, cation="NA", anion="CL", salt_mM=SALT_MM)["ok"]


# --- the mdp and the tension --------------------------------------------------------------

def test_the_mdp_in_water(water):
    d, info = water
    mdp = (d / "md.mdp").read_text()
    assert read_mdp_value(mdp, "coulombtype") == "PME"
    assert read_mdp_value(mdp, "pcoupl") == "C-rescale" and read_mdp_value(mdp, "pcoupltype") == "semiisotropic"
    A = info["box_nm"][0] * info["box_nm"][1]
    p_xy, p_z = (float(x) for x in read_mdp_value(mdp, "ref-p").split())
    assert p_xy == 1.0 and p_z == pytest.approx(1.0 - 10.0 * TENSION_PN / A, abs=1e-5)


def test_a_fixed_box_stays_available():
    mdp = render_md(MdSettings(solvated=True, thermostat=True))
    assert read_mdp_value(mdp, "pcoupl") == "no" and read_mdp_value(mdp, "coulombtype") == "PME"
    assert read_mdp_value(render_md(MdSettings()), "coulombtype") == "Cut-off"     # vacuum as before


def test_reference_pressure_against_hand_values():
    # 30 pN over 25 nm^2: 1.2 pN/nm^2 = 12 bar below the 1 bar across
    assert tension.ref_p_axis_bar(30.0, 25.0) == pytest.approx(-11.0)
    assert tension.ref_p_axis_bar(0.0, 25.0) == pytest.approx(1.0)
    assert tension.ref_p_axis_bar(-5.0, 50.0, p_perp_bar=2.0) == pytest.approx(3.0)
    with pytest.raises(InputError):
        tension.ref_p_axis_bar(30.0, 0.0)


def test_tension_formulas_against_hand_values():
    # water: (P_perp - P_zz) A; P_perp 1 bar, P_zz -11 bar, A 25 nm^2 = 2500 A^2 -> 12 bar x 25 nm^2 = 30 pN
    assert tension.md_tension_pN([-11.0], 2500.0, [1.0])[0] == pytest.approx(30.0)
    # the vacuum formula reads the water's 1 bar as -2.5 pN on that box
    assert tension.md_tension_pN([1.0], 2500.0)[0] == pytest.approx(-2.5)
    assert tension.md_tension_pN([1.0], 2500.0, [1.0])[0] == pytest.approx(0.0)
    # the barostat's target and the reader agree for any tension and area
    for T, A in ((30.0, 25.0), (-7.0, 61.3), (0.0, 10.0)):
        assert tension.md_tension_pN([tension.ref_p_axis_bar(T, A)], A * 100.0, [1.0])[0] == pytest.approx(T)


def test_the_tension_reader_takes_the_formula_of_the_setting(tmp_path, monkeypatch):
    t = np.arange(4.0)
    energies = {"time": t, "Pres-XX": np.full(4, 3.0), "Pres-YY": np.full(4, -1.0), "Pres-ZZ": np.full(4, -11.0),
                "Box-X": np.full(4, 5.0), "Box-Y": np.full(4, 5.0), "Box-Z": np.full(4, 7.0)}
    monkeypatch.setattr(tension, "read_energies", lambda d, gmx, edr="md.edr": dict(energies))
    (tmp_path / "md.edr").write_text("")
    build = {"box": {"axis": 2}, "solvent": None}
    (tmp_path / "build.json").write_text(json.dumps(build))
    assert np.allclose(tension.tension_series(tmp_path, "gmx")["tension_pN"], 11.0 * 25 * 0.1)   # -P_zz A
    build["solvent"] = {"model": "tip3p"}
    (tmp_path / "build.json").write_text(json.dumps(build))
    s = tension.tension_series(tmp_path, "gmx")
    assert np.allclose(s["tension_pN"], (1.0 + 11.0) * 25 * 0.1) and s["formula"].startswith("water")


# --- bad options: refused before any work --------------------------------------------------

@pytest.mark.parametrize("args, message", [
    (["--solvent", "tip4p"], "invalid choice"),
    (["--solvent", "tip3p", "--salt-mM", "-1"], "salt-mM"),
    (["--salt-mM", "150"], "salt needs water"),
    (["--solvent", "tip3p", "--axial-tension-pN", "30"], "needs --thermostat"),
    (["--axial-tension-pN", "30", "--thermostat"], "add --solvent"),
    (["--solvent", "tip3p", "--axial-pressure"], "axial-tension-pN 0"),
])
def test_bad_options_exit_2_before_work(dnarod, tmp_path, args, message):
    scene = Path(__file__).resolve().parents[2] / "workflows" / "scenes" / "dna21.toml"
    t0 = time.time()
    p = subprocess.run([str(dnarod), "build-md", str(scene), "-o", str(tmp_path / "out"), *args],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2, p.stderr
    assert message in p.stderr
    assert not (tmp_path / "out").exists()
    assert time.time() - t0 < 60      # no rod run, no GROMACS


def test_the_api_refuses_the_same(tmp_path):
    with pytest.raises(InputError, match="not a water model"):
        solvent_of("tip4p", 0.0, "charmm27")
    with pytest.raises(InputError, match=">= 0 mM"):
        solvent_of("tip3p", -5.0, "amber99sb-ildn")
    with pytest.raises(InputError, match="needs --thermostat"):
        BuildRequest(scene="x.toml", output=tmp_path, solvent="tip3p", axial_tension_pN=1.0).medium()
    assert solvent_of("vacuum", 0.0, "charmm27") is None
