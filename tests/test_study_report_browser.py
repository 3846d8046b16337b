"""The study report in a real browser: headless Chromium opens ``index.html`` of a study (results
made up from arithmetic, 3 tactics x 2 fleet sizes x 5 seeds), every figure loads, the verdicts
and tables are on the page, and a screenshot of it is not blank."""

from __future__ import annotations

import json
import re
import shutil
import subprocess

import numpy as np
import pytest
import yaml
from fire_study.report import write_report
from fire_study.spec import load_study

PROBE = """<pre id="probe-out">pending</pre><script>
window.addEventListener('load', function () {
  var imgs = Array.from(document.images);
  document.getElementById('probe-out').textContent = 'RESULT ' + JSON.stringify({
    imgs: imgs.map(function (i) { return {src: i.getAttribute('src'), ok: i.complete && i.naturalWidth > 0}; }),
    tables: document.querySelectorAll('table').length,
    verdicts: Array.from(document.querySelectorAll('li')).map(function (l) { return l.textContent; })});
});
</script>"""


def _chromium() -> str:
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if exe is None:
        pytest.fail(
            "chromium not installed: scripts/bootstrap installs it (apt-get install chromium)", pytrace=False
        )
    return exe


def _study_and_rows(tmp_path):
    doc = {"name": "browser", "scenarios": ["grass_running"], "tactics": ["head", "flank", "auto"],
           "uavs": [3, 6], "seeds": {"first": 1, "count": 5}}  # fmt: skip
    (tmp_path / "s.yaml").write_text(yaml.safe_dump(doc))
    study = load_study(tmp_path / "s.yaml")
    rng = np.random.default_rng(0)
    rows = []
    for seed in study.seeds:
        fire = rng.uniform(30e4, 50e4)
        for arm in study.arms():
            k = {"head": 1.0, "flank": 0.6, "auto": 0.62}[arm.tactic] * (1.2 if arm.uavs == 3 else 1.0)
            contained = arm.tactic != "head" and arm.uavs == 6
            rows.append({"scenario": arm.scenario, "airframe": arm.airframe, "uavs": arm.uavs, "tactic": arm.tactic,
                         "seed": seed, "burned_area_m2": fire * k * rng.uniform(0.97, 1.03), "time_limit_s": 900.0,
                         "contained": contained, "contained_at_s": 700.0 + 10 * seed if contained else None,
                         "water_on_burning_kg": 2e5 * k, "crashes": 0, "min_separation_m": 5.0 + seed})  # fmt: skip
    return study, rows


@pytest.mark.slow  # two Chromium runs: 30-60 s on a loaded machine
def test_the_study_report_loads_in_chromium_with_every_figure(tmp_path) -> None:
    study, rows = _study_and_rows(tmp_path)
    out = tmp_path / "report"
    res = write_report(study, rows, out)
    assert sorted(res["tables"]) == ["results.csv", "results.parquet"]
    import pandas as pd

    assert len(pd.read_parquet(out / "results.parquet")) == 30 == len(pd.read_csv(out / "results.csv"))
    page = (out / "index.html").read_text()
    (out / "probe.html").write_text(page.replace("</body>", PROBE + "</body>"))
    cmd = [_chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--virtual-time-budget=15000",
           "--dump-dom", (out / "probe.html").as_uri()]  # fmt: skip
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120, check=False)
    m = re.search(r"RESULT (\{.*?\})</pre>", r.stdout, re.S)
    assert m, f"the probe page did not report (exit {r.returncode}):\n{r.stdout[-1500:]}\n{r.stderr[-1500:]}"
    got = json.loads(m.group(1).replace("&quot;", '"').replace("&amp;", "&"))
    assert sorted(i["src"] for i in got["imgs"]) == sorted(res["figures"]) and len(got["imgs"]) == 4
    assert all(i["ok"] for i in got["imgs"]), got["imgs"]
    assert got["tables"] >= 8
    v = " | ".join(got["verdicts"])
    assert re.search(
        r"on grass_running with 6 UAVs, flank burns (3[6-9]|4[0-4]) % less than head \(95 % CI -", v
    ), v
    assert "no detectable difference in burned area between auto and flank" in v
    shot = tmp_path / "shot.png"
    cmd = [_chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
           "--window-size=1200,1600", f"--screenshot={shot}", (out / "index.html").as_uri()]  # fmt: skip
    subprocess.run(cmd, capture_output=True, timeout=120, check=False)
    import matplotlib.image as mpimg

    img = mpimg.imread(shot)
    assert img.shape[:2] == (1600, 1200)
    assert img[..., :3].std() > 0.05  # text and figures, not a blank page
