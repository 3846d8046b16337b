"""One error family per package: each package has an ``errors.py`` whose classes derive from one
base, and its modules raise those, not bare builtins (``raise ValueError(...)``), so a caller can
catch the package's errors as one and each error says by its type where it comes from.

Allowed besides the family: ``SystemExit`` and argparse's ``ArgumentTypeError`` in command-line
code, re-raising (``raise``), and raising an error class that was passed in as an argument.
"""

from __future__ import annotations

import ast
import builtins
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: package directory -> the base class of its family (defined in the package's errors.py)
FAMILIES = {
    "ros2_ws/src/fire_world_sim/fire_world_sim": "WorldError",
    "ros2_ws/src/fire_uav_common/fire_uav_common": "CommonError",
    "ros2_ws/src/fire_uav_recording/fire_uav_recording": "RecordingError",
    "tools/fire_mission": "MissionError",
    "tools/fire_bench": "BenchError",
    "ros2_ws/src/fire_perimeter_monitor/fire_perimeter_monitor": "MonitorError",
    "tools/fire_report": "ReportError",
}
# AttributeError: a module-level __getattr__ must raise it (PEP 562)
ALLOWED = {"SystemExit", "KeyboardInterrupt", "NotImplementedError", "StopIteration", "AttributeError"}
#: Modules that still raise a builtin; each entry must still do so (test_known_builtin_raises), so
#: an entry is deleted when its module joins its package's family.
KNOWN_BUILTIN_RAISES = {
    "ros2_ws/src/fire_world_sim/fire_world_sim/fires/rothermel.py",
    "ros2_ws/src/fire_world_sim/fire_world_sim/fires/fuel_models.py",
}
BUILTIN_ERRORS = {
    n for n, v in vars(builtins).items() if isinstance(v, type) and issubclass(v, BaseException)
}


def _builtin_raises(path: Path) -> list[str]:
    out = []
    label = path.relative_to(ROOT) if path.is_relative_to(ROOT) else path
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Raise) and node.exc is not None:
            exc = node.exc.func if isinstance(node.exc, ast.Call) else node.exc
            name = exc.id if isinstance(exc, ast.Name) else None
            if name in BUILTIN_ERRORS and name not in ALLOWED:
                out.append(f"{label}:{node.lineno} raises {name}")
    return out


def _modules(pkg: str) -> list[Path]:
    return sorted(p for p in (ROOT / pkg).rglob("*.py") if not {"test", "tests"} & set(p.parts))


@pytest.mark.parametrize("pkg", sorted(FAMILIES))
def test_the_package_has_one_family_in_errors_py(pkg: str) -> None:
    tree = ast.parse((ROOT / pkg / "errors.py").read_text())
    classes = {c.name: [ast.unparse(b) for b in c.bases] for c in tree.body if isinstance(c, ast.ClassDef)}
    base = FAMILIES[pkg]
    assert base in classes, f"{pkg}/errors.py has no {base}"

    def in_family(name: str) -> bool:
        return name == base or any(in_family(b) for b in classes.get(name, []) if b in classes)

    assert [n for n in classes if not in_family(n)] == [], f"{pkg}/errors.py: classes outside {base}"


@pytest.mark.parametrize("pkg", sorted(FAMILIES))
def test_the_package_raises_its_own_errors(pkg: str) -> None:
    found = [
        r
        for p in _modules(pkg)
        if str(p.relative_to(ROOT)) not in KNOWN_BUILTIN_RAISES
        for r in _builtin_raises(p)
    ]
    assert found == []


def test_known_builtin_raises_are_still_there() -> None:
    gone = sorted(p for p in KNOWN_BUILTIN_RAISES if not (ROOT / p).exists() or not _builtin_raises(ROOT / p))
    assert gone == [], f"no builtin raised any more, delete from KNOWN_BUILTIN_RAISES: {gone}"


def test_the_scan_finds_a_builtin_raise(tmp_path: Path) -> None:
    bad = tmp_path / "m.py"
    bad.write_text(
        "def f(x, error):\n    if x:\n        raise ValueError('no')\n    if error:\n        raise error('x')\n"
        "    raise SystemExit(2)\n"
    )
    assert _builtin_raises(bad) == [f"{bad}:3 raises ValueError"]
