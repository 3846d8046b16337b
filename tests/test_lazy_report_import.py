"""The runner's end-of-mission summary does not load matplotlib.

``LiveSummary.suppression`` takes its figures from ``fire_report.metrics``; matplotlib came in
through the package's ``write_report`` and cost every mission ~0.3 s (1.4 s CPU on a loaded
machine) after its last step. The report still gets it when it draws.
"""

from __future__ import annotations

import subprocess
import sys

PROBE = """
import sys
from fire_mission.summary import LiveSummary
s = LiveSummary(uav_count=1)
s.add_truth(0.0, [(10.0, True)])
s.add_truth(1.0, [(12.0, False)])
d = s.suppression()
assert d["burned_area_m2"] == 12.0, d
print("matplotlib" in sys.modules)
{extra}
"""


def _run(extra: str = "") -> str:
    out = subprocess.run(
        [sys.executable, "-c", PROBE.format(extra=extra)],
        capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout.split()


def test_the_summary_does_not_import_matplotlib():
    assert _run() == ["False"]


def test_write_report_still_comes_from_the_package_and_brings_it():
    got = _run(
        "from fire_report import write_report\nprint(callable(write_report), 'matplotlib' in sys.modules)"
    )
    assert got == ["False", "True", "True"]


def test_an_unknown_name_is_still_an_attribute_error():
    got = _run(
        "import fire_report\ntry:\n    fire_report.no_such_thing\nexcept AttributeError as e:\n    print('no_such_thing' in str(e))"
    )
    assert got == ["False", "True"]
