"""The report in a real browser: headless Chromium (Debian's ``chromium``, installed by
scripts/bootstrap) opens ``report/index.html`` of a synthetic mission and every figure loads;
at a laptop's width and at a narrow window's, no text lies over a figure and nothing is wider
than the window, and a screenshot is taken at each.

A probe copy of the page (``index.html`` plus a script) writes, on the load event, what it
measured into the DOM, which ``--dump-dom`` prints: each image's ``complete``/``naturalWidth``
(a figure that the browser cannot find or decode has naturalWidth 0), and the bounding boxes of
every text run (``Range.getClientRects``) and every image, from which the overlaps are found.
"""

from __future__ import annotations

import html
import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest
from fire_report.report import write_report
from fire_report.synthetic import SyntheticMission, write_synthetic_mission

ROOT = Path(__file__).resolve().parents[1]

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


LAYOUT_SCRIPT = """<pre id="probe-out">pending</pre><script>
window.addEventListener('load', function () {
  function box(r) { return {l: r.left, t: r.top + window.scrollY, r: r.right, b: r.bottom + window.scrollY}; }
  var imgs = Array.from(document.images).map(function (i) {
    return {src: i.getAttribute('src'), box: box(i.getBoundingClientRect())};
  });
  var texts = [];
  var walk = document.createTreeWalker(document.querySelector('main') || document.body, NodeFilter.SHOW_TEXT);
  while (walk.nextNode()) {
    var n = walk.currentNode;
    if (!n.textContent.trim() || n.parentElement.closest('script,style,#probe-out')) continue;
    var range = document.createRange();
    range.selectNodeContents(n);
    Array.from(range.getClientRects()).forEach(function (r) {
      if (r.width > 0 && r.height > 0) texts.push({text: n.textContent.trim().slice(0, 40), box: box(r)});
    });
  }
  document.getElementById('probe-out').textContent = 'RESULT ' + JSON.stringify({
    width: window.innerWidth, scrollWidth: document.documentElement.scrollWidth, imgs: imgs, texts: texts});
});
</script>"""


def _probe(report_dir, script: str, width: int | None = None) -> object:
    page = (report_dir / "index.html").read_text(encoding="utf8")
    assert "</body>" in page
    (report_dir / "probe.html").write_text(page.replace("</body>", script + "</body>"), encoding="utf8")
    size = [f"--window-size={width},900"] if width else []
    cmd = [_chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", *size,
           "--virtual-time-budget=15000", "--dump-dom", (report_dir / "probe.html").as_uri()]  # fmt: skip
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=120, check=False)
    m = re.search(r"RESULT (.*?)</pre>", res.stdout, re.S)
    assert m, (
        f"the probe page did not report (exit {res.returncode}):\n{res.stdout[-1500:]}\n{res.stderr[-1500:]}"
    )
    return json.loads(html.unescape(m.group(1)))


def _render(report_dir) -> list[dict]:
    out = _probe(report_dir, PROBE_SCRIPT)
    assert isinstance(out, list)
    return out


def overlaps(layout: dict, slack_px: float = 1.0) -> list[tuple[str, str]]:
    """(text, image) pairs whose boxes intersect by more than ``slack_px`` on both axes."""
    found = []
    for t in layout["texts"]:
        a = t["box"]
        for i in layout["imgs"]:
            b = i["box"]
            if (
                min(a["r"], b["r"]) - max(a["l"], b["l"]) > slack_px
                and min(a["b"], b["b"]) - max(a["t"], b["t"]) > slack_px
            ):
                found.append((t["text"], i["src"]))
    return found


def test_the_overlap_finder_finds_an_overlap():
    box = {"l": 0, "t": 0, "r": 100, "b": 100}
    layout = {"imgs": [{"src": "a.png", "box": box}],
              "texts": [{"text": "over", "box": {"l": 50, "t": 90, "r": 150, "b": 110}},
                        {"text": "beside", "box": {"l": 100, "t": 0, "r": 200, "b": 20}}]}  # fmt: skip
    assert overlaps(layout) == [("over", "a.png")]


@pytest.fixture(scope="module")
def kill_report(tmp_path_factory):
    """A synthetic mission with a crash, a crash declaration and a scheduled link outage."""
    root = tmp_path_factory.mktemp("browser")
    write_synthetic_mission(root / "bag")
    write_report(root / "bag", root / "report")
    return root / "report"


@pytest.fixture(scope="module")
def landscape_report(tmp_path_factory):
    """The same synthetic mission flown on the worcester_vt landscape: the ground under the maps,
    the landscape map and the table of places in latitude and longitude."""
    root = tmp_path_factory.mktemp("browser_landscape")
    scenario = ROOT / "ros2_ws" / "src" / "fire_world_sim" / "scenarios" / "worcester_vt.yaml"
    write_synthetic_mission(root / "bag", SyntheticMission(scenario_yaml=scenario.read_text()))
    metrics = write_report(root / "bag", root / "report")
    assert metrics["figures"][0] == "landscape.png" and metrics["geo"]["places"]
    return root / "report"


@pytest.mark.slow
@pytest.mark.parametrize("width", [1366, 760])
@pytest.mark.parametrize("report", ["kill_report", "landscape_report"])
def test_no_text_lies_over_a_figure_at_a_laptop_and_a_narrow_width(report, width, tmp_path, request):
    kill_report = request.getfixturevalue(report)
    layout = _probe(kill_report, LAYOUT_SCRIPT, width)
    assert isinstance(layout, dict) and layout["width"] == width
    assert len(layout["imgs"]) >= 5 and len(layout["texts"]) > 50, layout["width"]
    assert not overlaps(layout), f"text over a figure at {width} px: {overlaps(layout)[:5]}"
    assert layout["scrollWidth"] <= width, (
        f"the page is {layout['scrollWidth']} px wide in a {width} px window"
    )
    for img in layout["imgs"]:
        assert img["box"]["r"] <= width and img["box"]["r"] - img["box"]["l"] > 100, img
    shot = tmp_path / f"{report}_{width}.png"
    cmd = [_chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
           f"--window-size={width},1400", "--virtual-time-budget=15000", f"--screenshot={shot}",
           (kill_report / "index.html").as_uri()]  # fmt: skip
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=120, check=False)
    assert shot.is_file(), res.stderr[-1500:]
    head = shot.read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n" and int.from_bytes(head[16:20], "big") == width


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
