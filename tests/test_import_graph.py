"""No import cycle among the project's modules or its packages, counting imports inside
functions too.

A lazy import (``def f(): from .x import y``) hides a cycle from Python but not from a reader:
this test builds the graph of every project module's imports, top level or not, and fails on
any strongly connected component with more than one module, naming the modules. A module that
imports a name from its own package (``from fire_report.sections import Section`` inside
``fire_report.sections.cp``) depends on the package's ``__init__``, so that edge counts too; an
import of a submodule does not count as one of its package (else every package that re-exports
its submodules would be a cycle). The same graph folded onto the top-level packages
(fire_uav_common, fire_world_sim, ..., fire_report) must be acyclic as well.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SKIP_PARTS = {"test", "tests", "build", "install", "log", ".venv", "__pycache__"}


def _package_roots() -> list[Path]:
    """Directories that hold top-level packages (each ros2_ws package, the tools)."""
    roots = [p for p in (ROOT / "ros2_ws" / "src").iterdir() if p.is_dir()]
    for extra in (ROOT / "tools", ROOT / "scripts" / "lib"):
        if extra.is_dir():
            roots.append(extra)
    return roots


def _modules() -> dict[str, Path]:
    mods: dict[str, Path] = {}
    for root in _package_roots():
        for path in root.rglob("*.py"):
            rel = path.relative_to(root)
            if SKIP_PARTS & set(rel.parts) or path.name == "setup.py" or len(rel.parts) < 2:
                continue
            parts = list(rel.with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            mods[".".join(parts)] = path
    return mods


def _imports(name: str, path: Path, mods: dict[str, Path]) -> set[str]:
    is_pkg = path.name == "__init__.py"
    package = name if is_pkg else name.rpartition(".")[0]
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        targets: list[tuple[str, bool]] = []  # (dotted name, a name taken from a package's __init__)
        if isinstance(node, ast.Import):
            targets = [(a.name, False) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)] if node.level > 1 else base
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            targets = [(mod, False)] + [
                (f"{mod}.{a.name}", f"{mod}.{a.name}" not in mods) for a in node.names
            ]
        for t, from_init in targets:
            # the longest project module that the target names
            while t and t not in mods:
                t = t.rpartition(".")[0]
            # a module's own packages are imported before it, which is no dependency; a name it takes
            # from one of them (``from pkg import Thing`` inside ``pkg.sub``) is
            if t and t != name and (from_init or not name.startswith(t + ".")):
                out.add(t)
    return out


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of size > 1 (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    counter = [0]

    def visit(v: str) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_cycle_finder_finds_a_cycle() -> None:
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


#: Cycles being removed on another branch. Each must still be a cycle here
#: (test_known_cycles_are_still_cycles), so the entry is deleted when its fix lands.
KNOWN_CYCLES: list[list[str]] = []


def _graph() -> dict[str, set[str]]:
    mods = _modules()
    assert len(mods) > 40, sorted(mods)
    return {name: _imports(name, path, mods) for name, path in mods.items()}


def _packages(graph: dict[str, set[str]]) -> dict[str, set[str]]:
    """The module graph folded onto top-level packages (no self-edges)."""
    out: dict[str, set[str]] = {}
    for name, deps in graph.items():
        top = name.split(".")[0]
        out.setdefault(top, set()).update(d.split(".")[0] for d in deps if d.split(".")[0] != top)
    return out


def test_an_import_of_the_own_package_is_an_edge() -> None:
    mods = _modules()
    cp = "fire_report.sections.cp"
    assert "fire_report.sections" in _imports(cp, mods[cp], mods)


def test_no_import_cycles() -> None:
    cycles = [c for c in _cycles(_graph()) if c not in KNOWN_CYCLES]
    assert not cycles, "import cycles:\n" + "\n".join(" <-> ".join(c) for c in cycles)


def test_known_cycles_are_still_cycles() -> None:
    fixed = [c for c in KNOWN_CYCLES if c not in _cycles(_graph())]
    assert not fixed, f"no longer a cycle, delete from KNOWN_CYCLES: {fixed}"


def test_no_cycle_among_packages() -> None:
    packages = _packages(_graph())
    assert {"fire_uav_common", "fire_world_sim", "fire_uav_agent", "fire_mission"} <= set(packages)
    assert packages["fire_uav_common"] == set()  # the bottom layer imports no other project package
    cycles = _cycles(packages)
    assert not cycles, "package import cycles:\n" + "\n".join(" <-> ".join(c) for c in cycles)


def test_a_name_taken_from_the_own_package_is_an_edge(tmp_path) -> None:
    """``pkg/__init__.py`` importing ``pkg.sub`` (even lazily) while ``pkg.sub`` takes a class
    from ``pkg`` is a cycle; ``pkg.sub`` importing its sibling ``pkg.other`` through ``pkg`` is not."""
    (tmp_path / "pkg").mkdir()
    init = tmp_path / "pkg" / "__init__.py"
    init.write_text("def f():\n    from pkg import sub\n\nclass Thing: ...\n")
    sub = tmp_path / "pkg" / "sub.py"
    sub.write_text("from pkg import Thing, other\n")
    other = tmp_path / "pkg" / "other.py"
    other.write_text("")
    mods = {"pkg": init, "pkg.sub": sub, "pkg.other": other}
    graph = {n: _imports(n, p, mods) for n, p in mods.items()}
    assert graph == {"pkg": {"pkg.sub"}, "pkg.sub": {"pkg", "pkg.other"}, "pkg.other": set()}
    assert _cycles(graph) == [["pkg", "pkg.sub"]]
