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
