"""MD inputs of a periodic, ligated duplex built for real with GROMACS, and a short run.

Rod initial conditions here are the paper's Table 1 written out by hand (a
straight twisted rod along lab Y, d1 = Z and d2 = X at s = 0, shear-only
displacement A cos(2 pi s / L) along Z, lab velocity (0, 0, A_v sin(2 pi s/L)))
plus a twist rate omega = (0, w sin(2 pi s / L), 0) about the axis, so every
expected number comes from these formulas, not from the code under test.
"""
import json
import subprocess
from pathlib import Path

import MDAnalysis as mda
import numpy as np
import pytest

from dna_models.errors import ExternalToolError
from mdbridge.md.builder import build_duplex
from mdbridge.md.gromacs.box import plan_box
from mdbridge.md.gromacs.gro import read_gro
from mdbridge.md.gromacs.inputs import RodInitial, build_inputs
from mdbridge.md.gromacs.mdp import MdSettings
from mdbridge.md.gromacs.run import run_md

RISE = 3.38
KB = 8.314462618e-3     # kJ/(mol K)
A_V = 1.0               # A/ps
W = 0.05                # rad/ps
A_DISP = 3.0            # A


def table1_rod(n_bp, turns, A=A_DISP, Av=A_V, w=W):
    L = n_bp * RISE
    s = np.arange(n_bp) * RISE
    k, tw = 2 * np.pi / L, 2 * np.pi * turns / L
    origins = np.stack([0 * s, s, A * np.cos(k * s)], 1)
    d1 = np.stack([np.sin(tw * s), 0 * s, np.cos(tw * s)], 1)    # Eq 47, rows of T^-1
    d2 = np.stack([np.cos(tw * s), 0 * s, -np.sin(tw * s)], 1)
    d3 = np.tile([0.0, 1.0, 0.0], (n_bp, 1))
    gamma = np.stack([0 * s, 0 * s, Av * np.sin(k * s)], 1)
    omega = np.stack([0 * s, w * np.sin(k * s), 0 * s], 1)
    return RodInitial(origins, np.stack([d1, d2, d3], axis=2), gamma, omega, L)


def make(tmp, n_bp=21, turns=2, T=0.0, seed=7, settings=None, **kw):
    rod = table1_rod(n_bp, turns)
    seq = ("ACGTTGCAGGCATCGATCCGA" * 10)[:n_bp]
    st = build_duplex(seq, rod.origins_A, rod.R, periodic_box=(0, rod.closure_length_A, 0))
    # the rod "predicts" the centerline swinging +-8 A along Z during the run
    swing = rod.origins_A[None] + np.array([[[0, 0, 8.0]], [[0, 0, -8.0]]])
    box = plan_box(np.concatenate([rod.origins_A[None], swing]), rod.origins_A,
                   rod.closure_length_A, rod_run_ps=1.0)
    info = build_inputs(tmp, st, rod, box, sequence=seq, temperature_K=T, seed=seed,
                        settings=settings or MdSettings(nsteps=200), **kw)
    return rod, info


@pytest.fixture(scope="module")
def cold(gmx, tmp_path_factory):
    d = tmp_path_factory.mktemp("cold")
    rod, info = make(d, T=0.0, gmx=gmx)
    return d, rod, info


@pytest.fixture(scope="module")
def warm(gmx, tmp_path_factory):
    d = tmp_path_factory.mktemp("warm")
    # rigid templates + pdb2gmx hydrogens put H within ~1 A of the next nucleotide at
    # sheared steps: without the restrained minimisation this MD explodes at step 0
    rod, info = make(d, T=300.0, seed=11, gmx=gmx, minimize=True)
    return d, rod, info


def _tpr(d, gmx):
    subprocess.run([gmx, "grompp", "-f", "md.mdp", "-c", "conf.gro", "-p", "topol.top",
                    "-o", "test.tpr", "-po", "test_out.mdp"], cwd=d, check=True,
                   capture_output=True)
    return mda.Universe(str(d / "test.tpr"), str(d / "conf.gro"))


def _pair_of_each_atom(u, n_bp):
    """Base pair (0-based, = index along strand I) of every atom, found from geometry:
    each strand II nucleotide pairs with the strand I one whose N1/N3 is nearest."""
    res = list(u.residues)
    I, II = res[:n_bp], res[n_bp:]

    def n13(r):
        return r.atoms.select_atoms("name N1" if r.resname in ("DA", "DG") else "name N3").positions[0]
    XI = np.array([n13(r) for r in I])
    pair = {r.ix: i for i, r in enumerate(I)}
    for r in II:
        pair[r.ix] = int(np.argmin(np.linalg.norm(XI - n13(r), axis=1)))
    return np.array([pair[a.residue.ix] for a in u.atoms])


def _expected_rod_velocity(x_A, pair, rod, shift):
    r = rod.origins_A[pair] + shift
    v = rod.gamma_lab_A_ps[pair] + np.cross(rod.omega_lab_rad_ps[pair], x_A - r)
    return v / 10.0   # nm/ps


def test_files_and_build_record(cold):
    d, rod, info = cold
    for f in ("conf.gro", "topol.top", "topol_DNA_chain_A.itp", "topol_DNA_chain_B.itp",
              "md.mdp", "em.mdp", "build.json"):
        assert (d / f).is_file(), f
    b = json.loads((d / "build.json").read_text())
    assert b["sequence"] == "ACGTTGCAGGCATCGATCCGA" and b["seed"] == 7
    assert b["units"]["tau_ps"] == pytest.approx(0.9416, abs=1e-3)
    assert b["total_charge_e"] == -42          # cyclic strands: -1 e per nucleotide
    assert b["nucleotide_charge_range_e"] == [-1.0, -1.0]
    mdp = (d / "md.mdp").read_text()
    for line in ("periodic-molecules      = yes", "pbc                     = xyz",
                 "integrator              = md", "tcoupl                  = no",
                 "rcoulomb                = 1.0", "rvdw                    = 1.0",
                 "coulombtype             = Cut-off", "gen-vel                 = no"):
        assert line in mdp


def test_junction_terms_exact_and_bonded_in_the_tpr(cold, gmx):
    d, rod, info = cold
    for rep in info["junctions"]:
        assert rep["ok"]
        c = rep["junction_counts"]
        assert (c["bonds"], c["angles"], c["proper_dihedrals"], c["pairs"]) == (1, 4, 7, 7)
    # independent reader: MDAnalysis's TPR parser sees the two ring-closing O3'-P bonds
    u = _tpr(d, gmx)
    n = 21
    for first, last in ((1, n), (n + 1, 2 * n)):
        o3 = u.select_atoms(f"resid {last} and name O3'")[0]
        p = u.select_atoms(f"resid {first} and name P")[0]
        assert p in o3.bonded_atoms
    # and the minimum-image junction links at t = 0 are ordinary O3'-P bonds
    for s, v in info["junction_O3P_t0_A"].items():
        assert 1.5 < v["junction"] < 1.7


def test_box_closes_the_helix_and_holds_the_predicted_swing(cold):
    d, rod, info = cold
    g = read_gro(d / "conf.gro")
    assert g.box[1] == pytest.approx(21 * RISE / 10, abs=1e-5)        # exact closure along Y
    # across: the swing's range along Z (A cos at the 21 base pairs, +-8 A)
    # + diameter 20 + 2 x cut-off 10 + margin 10
    c = A_DISP * np.cos(2 * np.pi * np.arange(21) / 21)
    z_range = (c.max() + 8.0) - (c.min() - 8.0)
    assert g.box[2] == pytest.approx((z_range + 20 + 20 + 10) / 10, abs=1e-4)
    assert g.box[0] == pytest.approx((20 + 20 + 10) / 10, abs=1e-4)


def test_zero_kelvin_velocities_are_exactly_the_rod_rigid_body_field(cold, gmx):
    d, rod, info = cold
    u = _tpr(d, gmx)
    g = read_gro(d / "conf.gro")
    pair = _pair_of_each_atom(u, 21)
    shift = np.array(info["box"]["shift_A"])
    v_expect = _expected_rod_velocity(g.x * 10.0, pair, rod, shift)
    assert np.abs(g.v - v_expect).max() < 6e-5          # .gro keeps 4 decimals of nm/ps
    assert np.abs(v_expect).max() > 0.05                # the field is not trivially zero
    # base pairs built where the rod puts them (re-analysed with 3DNA's definitions)
    fr = info["frames_t0_vs_rod"]
    assert fr["max_origin_A"] < 0.01 and fr["max_angle_deg"] < 0.2


def test_warm_velocities_are_rod_plus_thermal_at_300K_with_zero_momentum(warm, gmx):
    d, rod, info = warm
    u = _tpr(d, gmx)
    g = read_gro(d / "conf.gro")
    m = u.atoms.masses
    pair = _pair_of_each_atom(u, 21)
    v_th = g.v - _expected_rod_velocity(g.x * 10.0, pair, rod, np.array(info["box"]["shift_A"]))
    n = len(m)
    T = np.sum(m[:, None] * v_th ** 2) / ((3 * n - 3) * KB)
    assert T == pytest.approx(300.0, abs=0.5)
    assert np.abs((m[:, None] * v_th).sum(axis=0)).max() < 0.05   # amu nm/ps; rounding only


def test_short_md_runs_and_checks_hold(warm, gmx):
    d, rod, info = warm
    assert info["closest_nonbonded_contact"]["min_distance_A"] > 1.5
    rec = run_md(d, steps=200, gmx=gmx, threads=2, output_ps=0.05, stream=None)
    for f in ("md.tpr", "md.xtc", "md.edr", "md.log", "confout.gro", "md.done", "checks.json"):
        assert (d / f).is_file(), f
    assert not list(d.glob("*.part.*"))
    assert rec["steps"] == 200 and json.loads((d / "md.done").read_text())["steps"] == 200
    c = json.loads((d / "checks.json").read_text())
    assert c["n_frames"] == 5 and c["times_ps"] == [0.0, pytest.approx(0.2)]
    assert c["junction_ok"]
    for s in ("I", "II"):
        assert 1.4 < c["junction_O3P"][s]["junction_min_A"] < c["junction_O3P"][s]["junction_max_A"] < 1.8
    assert c["watson_crick"]["fraction_intact"][0] == 1.0
    assert c["side_image"]["ok"] and c["side_image"]["min_distance_A"] > 20.0
    e = c["energy"]
    # 0.2 ps of NVE: total energy within a few % of the kinetic energy
    assert e["max_abs_deviation_over_kinetic_start"] < 0.05


def test_one_thread_under_an_openmp_request_of_two(warm, gmx, tmp_path, monkeypatch):
    """Snakemake sets OMP_NUM_THREADS to a rule's threads; run-md --threads 1 under 2 must
    still run (mdrun refuses -nt 1 with an OpenMP request of 2 unless told -ntomp)."""
    import shutil
    d = tmp_path / "md"
    shutil.copytree(warm[0], d)
    for f in ("md.done", "checks.json", "md.xtc", "md.tpr"):
        (d / f).unlink(missing_ok=True)
    monkeypatch.setenv("OMP_NUM_THREADS", "2")
    rec = run_md(d, steps=20, gmx=gmx, threads=1, output_ps=0.02, checks=False, stream=None)
    assert rec["steps"] == 20 and (d / "md.xtc").is_file()


def test_gromacs_failure_surfaces_and_never_looks_finished(warm, gmx, tmp_path):
    d, rod, info = warm
    broken = tmp_path / "broken"
    broken.mkdir()
    for f in ("conf.gro", "topol.top", "topol_DNA_chain_A.itp", "topol_DNA_chain_B.itp",
              "posre_bases_DNA_chain_A.itp", "posre_bases_DNA_chain_B.itp", "build.json",
              "posre_DNA_chain_A.itp", "posre_DNA_chain_B.itp"):
        (broken / f).write_bytes((d / f).read_bytes())
    mdp = (d / "md.mdp").read_text().replace("integrator              = md",
                                             "integrator              = bogus")
    (broken / "md.mdp").write_text(mdp)
    (broken / "md.done").write_text("{}")               # a stale marker from an earlier run
    with pytest.raises(ExternalToolError) as e:
        run_md(broken, steps=10, gmx=gmx, stream=None)
    assert "grompp" in str(e.value) and "bogus" in str(e.value)
    assert not (broken / "md.done").exists()


def test_neutral_phosphates_make_every_nucleotide_neutral(gmx, tmp_path):
    # also the other offered settings: thermostat, 2 fs with h-bond constraints (grompp
    # accepts them: build_inputs runs grompp on md.mdp)
    st = MdSettings(nsteps=200, thermostat=True, temperature_K=300.0, dt_ps=0.002,
                    constraints="h-bonds")
    rod, info = make(tmp_path, electrostatics="neutral-phosphates", gmx=gmx, settings=st)
    mdp = (tmp_path / "md.mdp").read_text()
    assert "tcoupl                  = V-rescale" in mdp and "ref-t                   = 300.0" in mdp
    assert "constraints             = h-bonds" in mdp and "dt                      = 0.002" in mdp
    assert info["total_charge_e"] == pytest.approx(0.0, abs=1e-6)
    assert info["nucleotide_charge_range_e"] == [0.0, 0.0]
    u = _tpr(tmp_path, gmx)
    q = np.array([r.atoms.charges.sum() for r in u.residues])
    assert np.abs(q).max() < 1e-4


def test_amber_and_restrained_minimisation(gmx, tmp_path):
    rod, info = make(tmp_path, forcefield="amber99sb-ildn", minimize=True, gmx=gmx)
    assert all(r["ok"] for r in info["junctions"])
    em = info["minimization"]
    assert em["converged"]
    # base heavy atoms held: the base-pair frames barely move, the rest relaxes
    assert em["frames_moved"]["max_origin_A"] < 0.1 and em["frames_moved"]["max_angle_deg"] < 2.0


def test_158bp_paper_system_passes_grompp(gmx, tmp_path):
    rod, info = make(tmp_path, n_bp=158, turns=15, T=300.0, gmx=gmx)
    assert info["total_charge_e"] == -316
    assert 9900 < info["n_atoms"] < 10200
    assert all(r["ok"] for r in info["junctions"])
    assert info["box_nm"][1] == pytest.approx(53.404, abs=1e-6)


def test_cli_build_md_from_the_dna21_scene_then_run_md(gmx, tmp_path, capsys):
    """The real chain: scene -> rodcore -> builder -> GROMACS. The scene is the paper's
    Table 1 with A = 0 and A_v = 1 A/ps, so at 0 K every atom of base pair i must move
    with (0, 0, sin(2 pi i / 21)) A/ps in the lab: a formula, not the rod's output."""
    from dnarod.cli import main
    scene = Path(__file__).resolve().parents[2] / "workflows" / "scenes" / "dna21.toml"
    out = tmp_path / "md21"
    assert main(["build-md", str(scene), "-o", str(out), "--ps", "0.2", "--temperature", "0",
                 "--seed", "3"]) == 0
    b = json.loads((out / "build.json").read_text())
    assert b["n_bp"] == 21 and b["turns"] == 2 and b["twist_deg"] == pytest.approx(720 / 21)
    assert b["sequence_source"] == "random, seed 3" and len(b["sequence"]) == 21
    assert b["box"]["rod_run_ps"] == 0.2 and b["box"]["axis"] == 1
    assert b["box_nm"][1] == pytest.approx(21 * RISE / 10, abs=1e-9)
    u = _tpr(out, gmx)
    g = read_gro(out / "conf.gro")
    pair = _pair_of_each_atom(u, 21)
    v_expect = np.zeros_like(g.v)
    v_expect[:, 2] = np.sin(2 * np.pi * pair / 21) * 0.1      # nm/ps
    assert np.abs(g.v - v_expect).max() < 6e-5
    assert main(["run-md", str(out), "--steps", "100", "--threads", "2", "--output-ps", "0.05"]) == 0
    assert (out / "md.done").is_file()
    c = json.loads((out / "checks.json").read_text())
    assert c["junction_ok"] and c["side_image"]["ok"]
    # bad input is a clear error, exit 2
    assert main(["build-md", str(tmp_path / "missing.toml"), "-o", str(tmp_path / "x")]) == 2
    assert "missing.toml: scene file not found" in capsys.readouterr().err


def test_build_md_without_ps_runs_as_long_as_the_rod_run_it_is_given(gmx, rodsim, tmp_path, capsys):
    """A scene's t_end is in rod time (dna21.toml: 21.24 tau = 19.9996 ps), so a fixed
    default MD length (20 ps, 600 ps) can overrun the rod run that sizes the box. Without
    --ps the MD is the whole rod run in whole MD steps: floor(19.9996 ps / 1 fs) = 19.999 ps.
    The control: asking for the round number is refused, naming both lengths."""
    from dnarod.cli import main
    from dna_models.units import Units
    from mdbridge.md.gromacs.mdp import read_mdp_value
    from mdbridge.md.gromacs.rod import DEFAULT_MD_PS, md_length_ps
    scene = Path(__file__).resolve().parents[2] / "workflows" / "scenes" / "dna21.toml"
    rod = tmp_path / "rod21.h5"
    subprocess.run([str(rodsim), "run", str(scene), "-o", str(rod)], check=True, capture_output=True)
    covered_ps = Units.paper().time_to_ps(21.24)
    assert 19.999 < covered_ps < 20.0
    assert md_length_ps(None, dt_ps=0.002) == DEFAULT_MD_PS == 600.0
    out = tmp_path / "md21"
    assert main(["build-md", str(scene), "--rod", str(rod), "-o", str(out), "--temperature", "0",
                 "--seed", "3"]) == 0
    b = json.loads((out / "build.json").read_text())
    assert b["md_length_ps"] == pytest.approx(19.999, abs=1e-9)
    assert b["box"]["rod_run_ps"] == pytest.approx(19.999, abs=1e-9)
    assert read_mdp_value((out / "md.mdp").read_text(), "nsteps") == "19999"
    capsys.readouterr()
    assert main(["build-md", str(scene), "--rod", str(rod), "-o", str(tmp_path / "x"),
                 "--temperature", "0", "--ps", "20"]) == 2
    assert f"covers {covered_ps:g} ps, the MD 20 ps" in capsys.readouterr().err


def test_a_segment_kept_as_steps_is_the_trajectory_s_ensemble(warm, gmx, tmp_path):
    """A long run's segment kept as steps.npz (float16, its trajectory gone) gives the
    coarse-graining the same ensemble as the trajectory: the step parameters to float16's
    resolution (< 0.05 deg, < 0.005 A), the same open pairs, and the same masses and inertia."""
    import shutil
    from dnarod.steps.segments import reduce_steps
    from mdbridge.coarsegrain.reader import read_ensemble, read_steps_ensemble
    from mdbridge.md.integrity import PairIntegrity
    from mdbridge.md.builder.duplex import base_pairs
    d0, _, _ = warm
    d = tmp_path / "md"
    shutil.copytree(d0, d, ignore=shutil.ignore_patterns("md.tpr", "md.xtc", "md.edr", "md.log", "md.done", "md.part.*",
                                                       "*.cpt", "confout.gro", "checks.json"))
    run_md(d, steps=400, gmx=gmx, threads=1, output_ps=0.05, stream=None)
    seg = tmp_path / "seg01"
    reduce_steps(d, seg, stride=1)
    u = mda.Universe(str(d / "md.tpr"), str(d / "md.xtc"))
    res = {int(r.resid): r for r in u.residues}
    a = PairIntegrity(u, [(res[i], res[j]) for i, j in base_pairs(21)]).run()
    np.savez_compressed(seg / "integrity.npz", times_ps=np.asarray(a.times_ps, float),
                        n1_n3_A=a.results.distance_A.astype(np.float16))
    ens_t, ext_t = read_ensemble(mda.Universe(str(d / "md.tpr"), str(d / "md.xtc")), closed=True)
    ens_s, ext_s = read_steps_ensemble(d, [seg / "steps.npz"])
    assert ens_s.q.shape == ens_t.q.shape == (9, 21, 6)
    np.testing.assert_allclose(ens_s.times_ps, ens_t.times_ps, atol=1e-6)
    np.testing.assert_allclose(ens_s.q[..., :3], ens_t.q[..., :3], atol=0.005)
    np.testing.assert_allclose(ens_s.q[..., 3:], ens_t.q[..., 3:], atol=0.05)
    assert np.array_equal(ens_s.opened, ens_t.opened)
    np.testing.assert_array_equal(ext_s["mass_inertia"]["mass"], ext_t["mass_inertia"]["mass"])
    for k in ("inertia", "slice_inertia"):
        np.testing.assert_allclose(ext_s["mass_inertia"][k], ext_t["mass_inertia"][k], rtol=1e-9)
    assert ext_s["pairs"] == ext_t["pairs"]
    assert ext_s["temperature_K"] == 300.0
