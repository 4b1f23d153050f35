"""rodcore as an installed C++ package: `cmake --install`
into a temporary prefix, then an outside project (tests/cpp/find_package/)
does find_package(rodcore) + target_link_libraries(app PRIVATE rodcore::rodcore),
builds against the public headers only and runs the exact twisted-rod wave
(paper Eq 24). The app checks Gamma1 against A cos(w t - k s) with w from Eq 26
(written out in the app, not taken from rodcore), energy conservation, and
that its observer saw every frame. Control: the same app on the same scene
with loose tolerances must report the error it sees (the check can fail)."""
import re
import subprocess
from pathlib import Path

import h5py
import pytest

ROOT = Path(__file__).resolve().parents[2]
APP_SRC = ROOT / "tests" / "cpp" / "find_package"
SCENE = ROOT / "workflows" / "scenes" / "twisted_wave.toml"


@pytest.fixture(scope="module")
def app(bin_dir, tmp_path_factory):
    build = bin_dir.parent
    if not (build / "CMakeCache.txt").is_file():
        pytest.fail(f"{build} is not a CMake build: run scripts/build.sh (with the same DNAROD_BUILD)")
    tmp = tmp_path_factory.mktemp("install")
    prefix = tmp / "prefix"
    subprocess.run(["cmake", "--install", str(build), "--prefix", str(prefix)], check=True,
                   capture_output=True, text=True)
    headers = {p.name for p in (prefix / "include" / "rodcore").iterdir()}
    assert {"simulation.hpp", "scene_io.hpp", "observer.hpp", "h5_writer.hpp", "version.hpp",
            "dna_units.hpp"} <= headers
    for h in (prefix / "include" / "rodcore").iterdir():  # nothing of toml++ or HDF5 leaks
        text = h.read_text()
        assert "toml++" not in text and "<hdf5.h>" not in text, h.name
    appdir = tmp / "app"
    cfg = subprocess.run(["cmake", "-S", str(APP_SRC), "-B", str(appdir), f"-DCMAKE_PREFIX_PATH={prefix}",
                          "-DCMAKE_BUILD_TYPE=Release"], capture_output=True, text=True)
    assert cfg.returncode == 0, cfg.stdout + cfg.stderr
    bld = subprocess.run(["nice", "-n", "10", "cmake", "--build", str(appdir)], capture_output=True, text=True)
    assert bld.returncode == 0, bld.stdout + bld.stderr
    return appdir / "app"


def test_outside_project_runs_the_exact_wave(app, tmp_path):
    out = tmp_path / "wave.h5"
    p = subprocess.run([str(app), str(SCENE), str(out)], capture_output=True, text=True)
    assert p.returncode == 0, p.stdout + p.stderr
    assert p.stdout.strip().endswith("ok")
    errs = [float(x) for x in re.findall(r"max \|Gamma1 - exact\| = (\S+),", p.stdout)]
    assert len(errs) == 2 and max(errs) < 1e-7
    # The H5Writer observer wrote the file rodsim writes, version and scales included.
    with h5py.File(out, "r") as f:
        assert f.attrs["complete"] == 1
        assert f["time"].shape == (11,)
        assert f.attrs["rodcore_version"] == re.search(r"rodcore (\S+):", p.stdout).group(1)
        assert f.attrs["ell_A"] > 0 and f.attrs["tau_ps"] > 0


def test_control_loose_tolerances_fail_the_check(app, tmp_path):
    loose = tmp_path / "loose.toml"
    text = SCENE.read_text().replace("rtol = 1e-11", "rtol = 1e-4").replace("atol = 1e-11", "atol = 1e-4")
    text = text.replace("max_energy_drift = 1e-8", "max_energy_drift = 1.0")
    assert text != SCENE.read_text()
    loose.write_text(text)
    p = subprocess.run([str(app), str(loose), str(tmp_path / "loose.h5")], capture_output=True, text=True)
    assert p.returncode == 1 and p.stdout.strip().endswith("FAILED"), p.stdout + p.stderr
