"""An agent without a search role does not load scipy or scikit-learn (agent memory).

The agent node, its core and the search adapter import the heavy libraries only in the
functions that use them, so a suppression-only agent stays small; a search run still loads
them when it first needs them.
"""

from __future__ import annotations

import subprocess
import sys

PROBE = """
import sys
import fire_uav_agent.agent_node, fire_uav_agent.search_io, fire_uav_agent.search
print(sorted(m for m in ("scipy", "sklearn") if m in sys.modules))
"""


def test_agent_modules_do_not_import_scipy_or_sklearn():
    out = subprocess.run(
        [sys.executable, "-c", PROBE], capture_output=True, text=True, timeout=120, check=False
    )
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.strip() == "[]", out.stdout


def test_search_loads_them_when_it_runs():
    probe = PROBE.replace(
        "print(",
        "from fire_uav_agent.search.mst import mission_radius_m\n"
        'import numpy as np\nmission_radius_m(np.zeros((2, 3, 2)), backend="centralised")\nprint(',
    )
    out = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, timeout=120, check=False
    )
    assert out.returncode == 0, out.stderr[-2000:]
    assert "scipy" in out.stdout, out.stdout
