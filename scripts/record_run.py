#!/usr/bin/python3
"""Write the measured figures of a whole run, with date and machine, under out/records/;
copy them into the committed results/ only when asked (`commit`), so that running the
README's two commands leaves every tracked file as it was.

The README and docs quote the files in results/ (tests/python/test_docs_numbers.py holds them to it):

    record_run.py test-times --step pytest=617 --step "sanitizers + fuzz"=392 --total-s 1026
        -> out/records/test_times.json (scripts/test.sh calls it after a complete run)
    record_run.py main-job --wall-s 1644 --out out/compare
        -> out/records/main_job.json (scripts/run.sh calls it after a complete default run):
           the MD's ns/day from md/*/md.done, the headline MD's drift and phase speed from
           results.json.
    record_run.py commit main_job test_times
        -> results/main_job.json, results/test_times.json: the records the docs quote, replaced
           by this machine's newest (then update the docs' figures: test_docs_numbers.py); the
           main job's kicked MD speed is also appended to results/main_job_realisations.json, the
           realisations of its setting whose scatter the report adds to a single run's error
"""
import argparse
import datetime
import json
import os
import platform
import sys
from pathlib import Path

from mdbridge.jsonio import write_json  # the one strict-JSON writer

ROOT = Path(__file__).resolve().parents[1]


def machine() -> str:
    """CPU model, cores and OS: what the timings depend on (no host name)."""
    cpu = "CPU model unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    osname = platform.platform()
    try:
        for line in Path("/etc/os-release").read_text().splitlines():
            if line.startswith("PRETTY_NAME="):
                osname = line.split("=", 1)[1].strip('"')
    except OSError:
        pass
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    return f"{os.cpu_count()} cores, {cpu}, {osname}; load average {load:.1f} at the end"


def _stamp(what: str, command: str) -> dict:
    return {"what": what, "date": datetime.date.today().isoformat(), "machine": machine(),
            "recorded_by": "scripts/record_run.py", "command": command}


def test_times(args) -> dict:
    steps = {}
    for s in args.step:
        name, _, sec = s.rpartition("=")
        steps[name] = int(round(float(sec)))
    rec = _stamp("bash scripts/test.sh: wall time of each step", "bash scripts/test.sh")
    rec.update(total_s=int(round(args.total_s)), steps_s=steps)
    return rec


def main_job(args) -> dict:
    out = Path(args.out)
    res = json.loads((out / "results.json").read_text())
    rates = []
    for done in sorted(out.glob("md/*/md.done")):
        r = json.loads(done.read_text()).get("ns_per_day")
        if r:
            rates.append(float(r))
    rec = _stamp("The main job (README Quickstart, first command): bash scripts/run.sh",
                 "bash scripts/run.sh")
    rec.update(
        wall_min=round(args.wall_s / 60.0, 1),
        md_ns_per_day=[round(min(rates)), round(max(rates))] if rates else None,
        md_energy_drift_kJ_mol_per_ns_per_atom=round(res["md_energy_drift_kJ_mol_per_ns_per_atom"], 2),
        md_energy_drift_target_kJ_mol_per_ns_per_atom=res["md_energy_drift_target_kJ_mol_per_ns_per_atom"],
        md_phase_speed_A_per_ps=round(res["md_wave_speed_A_per_ps"], 2),
        # the record's own error: the report's adds the floor between realisations, which the
        # realisations record is made from (workflows/report/realisations.py)
        md_phase_speed_err_A_per_ps=round(res.get("md_wave_speed_err_one_record_A_per_ps",
                                                  res["md_wave_speed_err_A_per_ps"]), 2))
    return rec


RECORDS = ROOT / "out" / "records"


def commit(names) -> int:
    import shutil
    for name in names:
        src = RECORDS / f"{name}.json"
        if not src.is_file():
            print(f"record_run: {src}: no such record (run the command that writes it first)", file=sys.stderr)
            return 2
        shutil.copyfile(src, ROOT / "results" / f"{name}.json")
        print(f"record_run: {src} -> results/{name}.json")
        if name == "main_job":      # a rerun of the main job is one more realisation of its setting
            from dnarod.report.realisations import record
            path = ROOT / "results" / "main_job_realisations.json"
            if not path.is_file():
                print(f"record_run: no results/{path.name}: the kicked MD's speed is not added to the "
                      "realisations of the main job's setting", file=sys.stderr)
            elif record(path, json.loads(src.read_text())):
                print(f"record_run: its kicked MD's speed appended to results/{path.name}")
    return 0


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="what", required=True)
    t = sub.add_parser("test-times")
    t.add_argument("--step", action="append", default=[], metavar="NAME=SECONDS")
    t.add_argument("--total-s", type=float, required=True)
    m = sub.add_parser("main-job")
    m.add_argument("--wall-s", type=float, required=True)
    m.add_argument("--out", required=True, help="the main job's output folder (results.json, md/)")
    c = sub.add_parser("commit", help="copy records from out/records/ into the committed results/")
    c.add_argument("names", nargs="+", choices=("main_job", "test_times"))
    args = p.parse_args(argv)
    if args.what == "commit":
        return commit(args.names)
    if args.what == "test-times":
        path, rec = RECORDS / "test_times.json", test_times(args)
    else:
        path, rec = RECORDS / "main_job.json", main_job(args)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_json(path, rec)
    print(f"record_run: wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
