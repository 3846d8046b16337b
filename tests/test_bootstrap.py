"""The bootstrap stops with a message naming what to install when a toolchain piece is missing."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _fake_path(tmp_path: Path, keep: list[str], fake: dict[str, str] | None = None) -> str:
    """A PATH holding only the named tools (plus bash basics), and optional fake scripts."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    for tool in keep + [
        "bash",
        "env",
        "cat",
        "sha256sum",
        "cut",
        "head",
        "awk",
        "dirname",
        "find",
        "sort",
        "xargs",
        "rm",
        "mkdir",
        "tail",
    ]:
        real = shutil.which(tool)
        if real:
            (bin_dir / tool).symlink_to(real)
    for name, body in (fake or {}).items():
        p = bin_dir / name
        p.write_text("#!/bin/sh\n" + body + "\n")
        p.chmod(0o755)
    return str(bin_dir)


def _run(path: str, **env: str) -> subprocess.CompletedProcess:
    e = {"PATH": path, "HOME": os.environ.get("HOME", "/tmp"), **env}
    return subprocess.run(
        ["bash", str(ROOT / "scripts/bootstrap")], env=e, capture_output=True, text=True, timeout=60
    )


@pytest.mark.parametrize(
    ("missing", "message"),
    [
        ("cmake", "cmake not found.*apt-get install cmake"),
        ("g++", "no C\\+\\+ compiler.*apt-get install g\\+\\+"),
    ],
)
def test_missing_tool_is_named(tmp_path, missing, message):
    tools = ["python3", "cmake", "g++", "c++", "gcc", "cc"]
    keep = [t for t in tools if not (t == missing or (missing == "g++" and t == "c++"))]
    r = _run(_fake_path(tmp_path, keep))
    assert r.returncode != 0
    assert pytest.importorskip("re").search(message, r.stderr), r.stderr


def test_wrong_python_is_named(tmp_path):
    fake = {"python3": 'if [ "$1" = "-c" ]; then echo 3.9; exit 0; fi; exit 1'}
    r = _run(_fake_path(tmp_path, ["cmake", "g++", "c++", "gcc", "cc"], fake))
    assert r.returncode != 0
    assert "Python 3.9" in r.stderr and "3.10, 3.11 and 3.12" in r.stderr, r.stderr


def test_old_cmake_is_named(tmp_path):
    fake = {"cmake": 'echo "cmake version 3.16.3"'}
    r = _run(_fake_path(tmp_path, ["python3", "g++", "c++", "gcc", "cc"], fake))
    assert r.returncode != 0
    assert "cmake 3.16.3 is too old" in r.stderr, r.stderr


CONSOLE_SCRIPTS = {  # tools/pyproject.toml [project.scripts]
    "fire-run-mission": "fire_mission.runner",
    "fire-report": "fire_report.cli",
    "fire-bench": "fire_bench.bench",
}


def _venv_env() -> dict[str, str]:
    """The environment env.sh gives: this checkout's tools first, then the workspace packages."""
    src = ROOT / "ros2_ws/src"
    pkgs = [
        str(src / p) for p in ("fire_uav_common", "fire_world_sim", "fire_uav_recording", "fire_uav_agent")
    ]
    path = os.pathsep.join([str(ROOT / "tools"), *pkgs, os.environ.get("PYTHONPATH", "")])
    return {**os.environ, "PYTHONPATH": path}


def test_console_scripts_are_installed_and_run_this_checkouts_tools():
    venv = ROOT / ".venv"
    if not (venv / "bin/python").exists():
        pytest.skip("no .venv: run scripts/bootstrap")
    for name, module in CONSOLE_SCRIPTS.items():
        exe = venv / "bin" / name
        assert exe.is_file() and os.access(exe, os.X_OK), f"{exe} missing: scripts/bootstrap installs it"
        assert f"from {module} import main" in exe.read_text(), exe.read_text()
    # the venv may be shared with other checkouts: PYTHONPATH (env.sh) decides whose tools run
    r = subprocess.run(
        [str(venv / "bin/python"), "-c", "import fire_mission, fire_report, fire_bench as b; print(b.__file__)"],
        env=_venv_env(), capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert Path(r.stdout.strip()).resolve().is_relative_to((ROOT / "tools").resolve()), r.stdout
    r = subprocess.run(
        [str(venv / "bin/fire-report"), "--help"], env=_venv_env(), capture_output=True, text=True, timeout=60
    )
    assert r.returncode == 0 and "usage" in r.stdout.lower(), r.stdout + r.stderr
