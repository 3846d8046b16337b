"""The report in a real browser: headless Chromium (Debian's ``chromium``, installed by
scripts/bootstrap) opens ``report/index.html`` of a synthetic mission and every figure loads.

A probe copy of the page (``index.html`` plus a script) writes, on the load event, each image's
``complete``/``naturalWidth`` into the DOM, which ``--dump-dom`` prints; a figure that the
browser cannot find or decode has naturalWidth 0.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess

import pytest
from fire_report.report import write_report
from fire_report.synthetic import write_synthetic_mission

PROBE_SCRIPT = """<pre id="probe-out">pending</pre><script>
window.addEventListener('load', function () {
  var imgs = Array.from(document.images);
  document.getElementById('probe-out').textContent = 'RESULT ' + JSON.stringify(imgs.map(function (i) {
    return {src: i.getAttribute('src'), ok: i.complete && i.naturalWidth > 0, w: i.naturalWidth};
  }));
});
</script>"""


def _chromium() -> str:
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if exe is None:
        pytest.fail(
            "chromium not installed: scripts/bootstrap installs it (apt-get install chromium)", pytrace=False
        )
    return exe


def _render(report_dir) -> list[dict]:
    page = (report_dir / "index.html").read_text(encoding="utf8")
    assert "</body>" in page
    (report_dir / "probe.html").write_text(page.replace("</body>", PROBE_SCRIPT + "</body>"), encoding="utf8")
    cmd = [_chromium(), "--headless", "--no-sandbox", "--disable-gpu",
           "--virtual-time-budget=15000", "--dump-dom", (report_dir / "probe.html").as_uri()]  # fmt: skip
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=120, check=False)
    m = re.search(r"RESULT (\[.*?\])</pre>", res.stdout, re.S)
    assert m, (
        f"the probe page did not report (exit {res.returncode}):\n{res.stdout[-1500:]}\n{res.stderr[-1500:]}"
    )
    return json.loads(m.group(1).replace("&quot;", '"'))


def test_every_figure_of_the_report_loads_in_chromium(tmp_path):
    write_synthetic_mission(tmp_path / "bag")
    metrics = write_report(tmp_path / "bag", tmp_path / "report")
    imgs = _render(tmp_path / "report")
    assert sorted(i["src"] for i in imgs) == sorted(metrics["figures"]) and imgs
    bad = [i for i in imgs if not i["ok"]]
    assert not bad, f"figures that did not load: {bad}"


def test_the_probe_sees_a_missing_figure(tmp_path):
    write_synthetic_mission(tmp_path / "bag")
    metrics = write_report(tmp_path / "bag", tmp_path / "report")
    (tmp_path / "report" / metrics["figures"][0]).unlink()
    bad = [i["src"] for i in _render(tmp_path / "report") if not i["ok"]]
    assert bad == [metrics["figures"][0]]
