"""The comparison report (report/index.html of the tiny run) opened in a real browser:
Debian's headless Chromium driven through chromedriver (Selenium), with every network
route closed (an unreachable proxy, every host name unresolvable), so a page that
needed the network would show failed requests and console errors.

Checks: the page loads with no console errors; no request leaves file:/data: URLs;
every figure is decoded and not blank (pixel statistics read back in the page); the
headline table is there; every figure has a caption; a screenshot is taken; the page
leads with what was found (the verdict, then a figure, then the tables, and the rows
without a number below them, each with its reason). Also: every axis of every report
figure has labels with units.
"""
import base64
import io
import json

import numpy as np
import pytest

CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"

# Per image: decoded size and statistics of its pixels, read back through a canvas.
PIXEL_STATS_JS = """
return Array.from(document.images).map(img => {
  const c = document.createElement('canvas');
  c.width = img.naturalWidth; c.height = img.naturalHeight;
  const g = c.getContext('2d');
  if (!img.complete || img.naturalWidth === 0) return {alt: img.alt, w: 0, h: 0};
  g.drawImage(img, 0, 0);
  const d = g.getImageData(0, 0, c.width, c.height).data;
  let n = 0, nonWhite = 0, sum = 0, sum2 = 0;
  for (let i = 0; i < d.length; i += 4) {
    const y = 0.299 * d[i] + 0.587 * d[i + 1] + 0.114 * d[i + 2];
    n++; sum += y; sum2 += y * y; if (y < 240) nonWhite++;
  }
  const mean = sum / n;
  return {alt: img.alt, w: c.width, h: c.height, std: Math.sqrt(sum2 / n - mean * mean),
          nonWhite: nonWhite / n,
          caption: (img.closest('figure') && img.closest('figure').querySelector('figcaption'))
                   ? img.closest('figure').querySelector('figcaption').textContent : ''};
});
"""


@pytest.fixture(scope="module")
def browser():
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    for exe in (CHROMIUM, CHROMEDRIVER):
        import os
        if not os.access(exe, os.X_OK):
            pytest.fail(f"{exe} not found: scripts/setup.sh installs chromium and chromium-driver")
    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
              "--window-size=1200,900", "--proxy-server=127.0.0.1:9",
              "--host-resolver-rules=MAP * ~NOTFOUND", "--allow-file-access-from-files"):
        opts.add_argument(a)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL", "performance": "ALL"})
    drv = webdriver.Chrome(service=Service(CHROMEDRIVER), options=opts)
    try:
        yield drv
    finally:
        drv.quit()


def _open(browser, page):
    browser.get(page.as_uri())
    browser.execute_script("return document.readyState")  # blocks until load
    return browser


def test_page_needs_nothing_but_itself(browser, tiny_run, tmp_path):
    page = tiny_run[0] / "report" / "index.html"
    drv = _open(browser, page)
    console = drv.get_log("browser")
    errors = [e for e in console if e["level"] in ("SEVERE", "ERROR")]
    assert not errors, errors
    urls = []
    for entry in drv.get_log("performance"):
        msg = json.loads(entry["message"])["message"]
        if msg["method"] == "Network.requestWillBeSent":
            urls.append(msg["params"]["request"]["url"])
    assert urls, "the performance log saw no request at all (the check itself is broken)"
    remote = [u for u in urls if not u.startswith(("file:", "data:"))]
    assert not remote, f"the report asks the network for {remote}"
    png = drv.get_screenshot_as_png()
    (tmp_path / "report.png").write_bytes(png)
    import matplotlib.image as mpimg
    shot = mpimg.imread(io.BytesIO(png))
    assert shot.shape[0] > 100 and np.std(shot[..., :3]) > 0.02, "the screenshot is blank"


def test_headline_table_and_figures(browser, tiny_run):
    page = tiny_run[0] / "report" / "index.html"
    drv = _open(browser, page)
    rows = drv.execute_script(
        "const t = document.getElementById('headline'); return t ? Array.from(t.rows).map(r => r.innerText) : null;")
    assert rows is not None, "no headline table (id=headline)"
    assert any("wave speed" in r or "frequency" in r for r in rows) and len(rows) >= 4
    stats = drv.execute_script(PIXEL_STATS_JS)
    assert len(stats) >= 4, stats
    for s in stats:
        assert s["w"] > 50 and s["h"] > 50, f"figure {s['alt']} did not decode"
        # matplotlib figures: a white background with lines, text and maps on it
        assert s["std"] > 5 and s["nonWhite"] > 0.005, f"figure {s['alt']} is blank: {s}"
        assert len(s["caption"]) > 40, f"figure {s['alt']} has no caption saying what to look for"


ORDER_JS = """
const v = document.getElementById('verdict'), img = document.images[0];
const table = document.querySelector('table'), below = document.getElementById('not-measured');
const after = (a, b) => !!(a && b && (a.compareDocumentPosition(b) & Node.DOCUMENT_POSITION_FOLLOWING));
return {verdict: v ? v.innerText : null,
        verdict_then_figure: after(v, img), figure_then_table: after(img, table),
        table_then_missing: after(table, below),
        figure_top: img ? img.getBoundingClientRect().top : null,
        table_top: table ? table.getBoundingClientRect().top : null,
        headline: document.getElementById('headline').innerText,
        missing: Array.from(document.querySelectorAll('#not-measured-list li')).map(li => li.innerText)};
"""


def test_page_leads_with_what_was_found(browser, tiny_run):
    """A newcomer sees the verdict in words and a figure before any table; the summary holds
    numbers only, and what has none (tiny.yaml's 4-ps MD is refused) is listed below with
    its one-line reason."""
    page = tiny_run[0] / "report" / "index.html"
    o = _open(browser, page).execute_script(ORDER_JS)
    assert o["verdict"] and len(o["verdict"]) > 80, o["verdict"]
    assert "A/ps" in o["verdict"] and ("MD" in o["verdict"])
    assert o["verdict_then_figure"] and o["figure_then_table"] and o["table_then_missing"], o
    assert o["figure_top"] < o["table_top"]
    assert "n/a" not in o["headline"]
    res = json.loads((tiny_run[0] / "results.json").read_text())
    assert o["missing"], "tiny.yaml's MD record is too short for a speed: it must be listed with its reason"
    for item in o["missing"]:
        label, _, why = item.partition(": ")
        assert label and len(why) > 10, item
    md = res["md_wave_speed_A_per_ps"]
    md_refused = md is None or not np.isfinite(md)
    assert md_refused == any(item.startswith("MD") and ("speed" in item or "frequency" in item)
                             for item in o["missing"])


def test_control_blank_figure_is_caught(browser, tmp_path):
    """The blank-figure check must be able to fail: a white PNG is flagged."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig = plt.figure(figsize=(3, 2))
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    plt.close(fig)
    b64 = base64.b64encode(buf.getvalue()).decode()
    page = tmp_path / "blank.html"
    page.write_text(f'<html><body><figure><img alt="blank" src="data:image/png;base64,{b64}">'
                    f'<figcaption>x</figcaption></figure></body></html>')
    stats = _open(browser, page).execute_script(PIXEL_STATS_JS)
    assert stats[0]["w"] > 50 and not (stats[0]["std"] > 5 and stats[0]["nonWhite"] > 0.005)


def test_every_axis_is_labelled_with_units(tiny_run):
    """Each axis of each report figure has a label with its unit in brackets."""
    import yaml
    from dnarod.report.report import CAPTIONS, collect, figures, results_json
    out = tiny_run[0]
    cfg = yaml.safe_load((out / "config.effective.yaml").read_text())
    data = collect(cfg, out)
    figs = figures(cfg, data, results_json(cfg, data))
    assert set(figs) <= set(CAPTIONS) and len(figs) >= 4
    for name, fig in figs.items():
        for ax in fig.axes:
            if ax.get_label() == "<colorbar>":
                label = ax.get_ylabel() or ax.get_xlabel()
                assert "[" in label, (name, "colorbar", label)
                continue
            for label in (ax.get_xlabel(), ax.get_ylabel()):
                assert label and "[" in label and "]" in label, (name, ax.get_title(), label)


DISPERSION_JS = """
const f = document.getElementById('fig-dispersion'), t = document.getElementById('dispersion-table');
return {figure: !!f, caption: f ? f.querySelector('figcaption').innerText : '',
        rows: t ? Array.from(t.rows).map(r => Array.from(r.cells).map(c => c.innerText)) : null,
        fit: (document.getElementById('dispersion-fit') || {}).innerText || '',
        verdict: document.getElementById('verdict').innerText};
"""


def test_dispersion_figure_and_table(browser, tiny_run):
    """The dispersion section: its figure decoded and not blank, with a caption, and the z table
    with one row per mode of results.json["dispersion"] (MD, the rods, z; a refused MD mode
    says why)."""
    page = tiny_run[0] / "report" / "index.html"
    drv = _open(browser, page)
    o = drv.execute_script(DISPERSION_JS)
    assert o["figure"] and "wavenumber" in o["caption"], o["caption"]
    stats = {s["alt"]: s for s in drv.execute_script(PIXEL_STATS_JS)}
    s = stats["dispersion"]
    assert s["w"] > 50 and s["std"] > 5 and s["nonWhite"] > 0.005, s
    res = json.loads((tiny_run[0] / "results.json").read_text())["dispersion"]
    assert o["rows"] is not None and len(o["rows"]) == 1 + len(res["rows"]), o["rows"]
    assert o["rows"][0][:4] == ["kind", "n", "k [1/A]", "MD omega0 [rad/ps]"]
    for cells, r in zip(o["rows"][1:], res["rows"]):
        assert cells[0] == r["kind"] and int(cells[1]) == r["n"]
        assert cells[3].startswith("refused: ") == (r["md_omega0_per_ps"] is None)
    assert "from the frequencies" in o["fit"] and "tension" in o["verdict"]
