"""Run a mission through the real runner (scripts/run_mission's Python entry) in a test."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def run_mission(out: Path, env: dict[str, str], *args: str, timeout_s: float = 400.0) -> tuple[dict, str]:
    """Run ``run_mission`` with ``args`` into ``out``; return (summary.json, runner stderr)."""
    e = dict(env)
    e["PYTHONPATH"] = str(ROOT / "tools") + os.pathsep + e.get("PYTHONPATH", "")
    e.pop("ROS_DOMAIN_ID", None)  # the runner picks its own private domain
    proc = subprocess.run(
        [sys.executable, "-m", "fire_mission.runner", *args, "--out", str(out), "--quiet", "--no-report"],
        env=e,
        capture_output=True,
        text=True,
        timeout=timeout_s,
        check=False,
    )
    summary_path = out / "summary.json"
    assert summary_path.is_file(), f"runner wrote no summary (exit {proc.returncode}):\n{proc.stderr[-4000:]}"
    return json.loads(summary_path.read_text()), proc.stderr


def assert_no_survivors(summary: dict) -> None:
    """No process the runner started outlives it."""
    alive = []
    for name, pid in summary["pids"].items():
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            continue
        try:
            state = Path(f"/proc/{pid}/stat").read_text().split()[2]
        except OSError:
            continue
        if state != "Z":
            alive.append(f"{name} (pid {pid})")
    assert not alive, f"processes outlived the mission: {alive}"
