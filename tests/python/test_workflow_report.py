"""The report step on synthetic inputs of known speed: a rod output file in the
docs/contracts.md HDF5 layout (read through the same path as a rodsim file) and an MD-like
wrapped trajectory. results.json must carry the speeds put in, and the HTML must be
self-contained (figures as base64 PNG)."""
import base64
import json

import numpy as np
import pytest

from dna_models.units import Units
from mdbridge.analysis import WaveAnalysis
from mdbridge.analysis.synthetic import helix_trajectory
from dnarod.report import report
from dnarod.steps import analyse as steps

N_BP, TURNS, RISE = 42, 4, 3.38
L = N_BP * RISE
K = 2 * np.pi / L


def write_rod_h5(path, traj):
    """A rodsim-like file (solver units) holding the synthetic base-pair trajectory."""
    import h5py
    u = Units.paper()
    T, n = traj.origins.shape[:2]
    ds = u.length_to_rod(L) / n
    # body-frame Gamma whose lab image integrates to the period: T Gamma ds = P / n
    Gamma = np.einsum("tixk,tx->tik", traj.R, u.length_to_rod(traj.period) / n) / ds
    with h5py.File(path, "w") as f:
        f["time"] = u.time_to_rod(traj.times_ps)
        f["s"] = np.arange(n) * ds
        f["centerline"] = u.length_to_rod(traj.origins)
        f["directors"] = traj.R
        f["fields/Gamma"] = Gamma


def test_report_from_synthetic_runs(tmp_path):
    c_rod, c_md = 0.35, 2.2
    times = np.arange(0.0, 200.0, 1.0)
    rod_traj, _ = helix_trajectory(times, lambda x, t: 4 * np.cos(K * x - c_rod * K * t), n=N_BP,
                                   turns=TURNS)
    scene = tmp_path / "scene.toml"
    scene.write_text(f'[initial]\nkind = "dna_planar"\nbp = {N_BP}\nturns = {TURNS}\nA_v_A_per_ps = 1.0\n')
    d = tmp_path / "rod" / "Av1"
    d.mkdir(parents=True)
    write_rod_h5(d / "rod.h5", rod_traj)
    s = steps.analyse_rod(scene, d / "rod.h5", d / "analysis", n_boot=20)
    assert s["wave_speed_A_per_ps"] == pytest.approx(c_rod, rel=0.01)

    md_traj, _ = helix_trajectory(times, lambda x, t: 4 * np.cos(K * x - c_md * K * t), n=N_BP,
                                  turns=TURNS, offset_A=1.0, noise_A=0.3, box_A=70.0)
    a = WaveAnalysis(md_traj, n_boot=20).run()
    m = a.summary()
    m.update(kind="md", A_v_A_per_ps=1.0, seed=1, bp_intact_fraction_final=0.9)
    md = tmp_path / "md" / "Av1_seed1"
    md.mkdir(parents=True)
    steps._write(md / "analysis", a, m, {"intact_times_ps": times, "intact_fraction": np.full(len(times), 0.9)})

    cfg = {"A_v_A_per_ps": [1], "seeds": [1], "headline_A_v_A_per_ps": 1,
           "rod": {"run_ps": 199}, "md": {"run_ps": 199}, "sweep": {"A_v_A_per_ps": []}}
    (tmp_path / "cfg.yaml").write_text(json.dumps(cfg))  # JSON is YAML
    assert report.main([str(tmp_path / "cfg.yaml"), str(tmp_path)]) == 0
    res = json.loads((tmp_path / "results.json").read_text())
    for key in ("rod_wave_speed_A_per_ps", "md_wave_speed_A_per_ps", "rod_wave_speed_err_A_per_ps",
                "md_wave_speed_err_A_per_ps", "rod_planarity", "md_planarity", "md_bp_intact_fraction",
                "rod_run_ps", "md_run_ps", "seeds"):
        assert key in res, key
    assert res["rod_wave_speed_A_per_ps"] == pytest.approx(c_rod, rel=0.01)
    assert res["md_wave_speed_A_per_ps"] == pytest.approx(c_md, rel=0.01)
    assert res["md_bp_intact_fraction"] == pytest.approx(0.9)
    assert res["rod_planarity"] < 1e-6
    # both axes are the same 4 A wave shape moving at different speeds: RMSD grows from ~0
    rmsd = res["rod_md_rmsd"][0]["rmsd_A"]
    assert rmsd[0] < 0.3 and max(rmsd) > 1.0  # 0.3 A noise on the MD-like origins
    page = (tmp_path / "report" / "index.html").read_text()
    assert "src=\"http" not in page and page.count("data:image/png;base64,") >= 4
    png = page.split("data:image/png;base64,")[1].split('"')[0]
    assert base64.b64decode(png)[:8] == b"\x89PNG\r\n\x1a\n"
    assert "1.4" in page and "2.2" in page  # the table vs the paper
    # the page leads with what was found: the verdict, then a figure, then the tables;
    # rows without a number sit below, each with its reason
    v, img, table, below = (page.index('id="verdict"'), page.index("<img"), page.index("<table"),
                            page.index('id="not-measured"'))
    assert v < img < table < below
    verdict = page[v:page.index("</section>", v)]
    assert f"{res['md_wave_speed_A_per_ps']:.3g}" in verdict and f"{res['rod_wave_speed_A_per_ps']:.3g}" in verdict
    assert "differ by" in verdict          # 2.2 against 0.35 A/ps, errors of about 1 %
    headline = page[page.index('id="headline"'):page.index("</table>", page.index('id="headline"'))]
    assert "n/a" not in headline
    listed = page[below:page.index("</ul>", below)]
    import html
    assert "predicted (CG rod)" in listed and html.escape(res["cg_rod_reason"]) in listed
    # another setting than the main job's: one record's error, and the opening says so
    assert res["md_wave_speed_err_A_per_ps"] == res["md_wave_speed_err_one_record_A_per_ps"]
    assert "one record's error" in verdict
    # the main job's setting (workflows/report/realisations.py) with one seed: the floor between its
    # realisations joins the record's error, in the summary, the matched comparison and the opening
    from dnarod.report import realisations, verdict as opening
    rec = json.loads(realisations.RECORD.read_text())
    main = dict(cfg, scene=rec["setting"]["scene"], md={"run_ps": rec["setting"]["md_run_ps"],
                                                         "build_args": rec["setting"]["build_args"],
                                                         "run_args": rec["setting"]["run_args"]})
    assert realisations.setting(main) == rec["setting"]
    r2 = report.results_json(main, report.collect(main, tmp_path))
    floor = rec["summary"]["floor_A_per_ps"]
    assert r2["md_wave_speed_err_one_record_A_per_ps"] == pytest.approx(res["md_wave_speed_err_A_per_ps"])
    assert r2["md_wave_speed_err_A_per_ps"] == pytest.approx(np.hypot(res["md_wave_speed_err_A_per_ps"], floor))
    head = next(r for r in r2["comparison"]["rows"] if r["A_v_A_per_ps"] == 1)
    assert head["md"]["speed_err_A_per_ps"] == r2["md_wave_speed_err_A_per_ps"]
    assert f"scatter between {rec['summary']['k']} runs of this setting" in opening.opening(r2)[0]
