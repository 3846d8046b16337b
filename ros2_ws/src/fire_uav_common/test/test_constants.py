"""The IntEnums of fire_uav_common.constants against the .msg files, name for name and value for value."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from fire_uav_common.constants import MSG_CONSTANTS

MSG_DIR = Path(__file__).resolve().parents[2] / "fire_uav_msgs" / "msg"
CONST = re.compile(r"^\s*u?int\d+\s+([A-Z][A-Z0-9_]*)\s*=\s*(-?\d+)")


def msg_constants(msg: str) -> dict[str, int]:
    out = {}
    for line in (MSG_DIR / f"{msg}.msg").read_text().splitlines():
        m = CONST.match(line)
        if m:
            out[m.group(1)] = int(m.group(2))
    return out


@pytest.mark.parametrize(("msg", "prefix"), sorted(MSG_CONSTANTS))
def test_enum_matches_msg(msg: str, prefix: str) -> None:
    enum = MSG_CONSTANTS[(msg, prefix)]
    in_msg = {k[len(prefix) :]: v for k, v in msg_constants(msg).items() if k.startswith(prefix)}
    in_enum = {e.name: int(e.value) for e in enum}
    assert in_msg, f"{msg}.msg has no {prefix}* constants"
    assert in_enum == in_msg


def test_every_msg_constant_has_an_enum() -> None:
    covered = {(m, p) for m, p in MSG_CONSTANTS}
    for path in sorted(MSG_DIR.glob("*.msg")):
        for name in msg_constants(path.stem):
            assert any(m == path.stem and name.startswith(p) for m, p in covered), (
                f"{path.stem}.{name} has no IntEnum in fire_uav_common.constants"
            )


def _project_sources(root: Path) -> list[Path]:
    """The project's Python files that must use the enums: packages and scripts, no tests, no build."""
    paths = list((root / "ros2_ws" / "src").rglob("*.py")) + list((root / "scripts").rglob("*.py"))
    skip = ("/test/", "/build/", "/install/")
    return [p for p in paths if p.name != "constants.py" and not any(s in str(p) for s in skip)]


def test_no_constant_defined_outside_its_module() -> None:
    """No module of the project assigns a message constant name to a literal (use the enums)."""
    root = Path(__file__).resolve().parents[4]
    names = {f"{p}{e.name}" for (_, p), enum in MSG_CONSTANTS.items() for e in enum}
    assign = re.compile(
        r"^\s*([A-Z][A-Z0-9_]*(?:\s*,\s*[A-Z][A-Z0-9_]*)*)\s*=\s*-?\d+(?:\s*,\s*-?\d+)*\s*(#.*)?$"
    )
    offenders = []
    for path in _project_sources(root):
        for n, line in enumerate(path.read_text().splitlines(), 1):
            m = assign.match(line)
            if m and {x.strip() for x in m.group(1).split(",")} & names:
                offenders.append(f"{path.relative_to(root)}:{n}: {line.strip()}")
    assert not offenders, "message constants redefined:\n" + "\n".join(offenders)


def test_no_enum_copies_outside_its_module() -> None:
    """No IntEnum elsewhere repeats one of the message enums (import it from fire_uav_common.constants)."""
    import ast

    root = Path(__file__).resolve().parents[4]
    ours = [{e.name: int(e.value) for e in enum} for enum in MSG_CONSTANTS.values()]
    offenders = []
    for path in _project_sources(root):
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.ClassDef):
                continue
            members = {}
            for stmt in node.body:
                if (
                    isinstance(stmt, ast.Assign)
                    and len(stmt.targets) == 1
                    and isinstance(stmt.targets[0], ast.Name)
                    and isinstance(stmt.value, ast.Constant)
                    and isinstance(stmt.value.value, int)
                ):
                    members[stmt.targets[0].id] = stmt.value.value
            if members and any(members.items() <= enum.items() and len(members) >= 2 for enum in ours):
                offenders.append(f"{path.relative_to(root)}:{node.lineno}: class {node.name}")
    assert not offenders, "message enums copied:\n" + "\n".join(offenders)
