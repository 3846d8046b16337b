"""Driver behind scripts/mutation: runs mutmut on one pure module at a time.

mutmut derives a mutant's module name from its path under ``src/``, while our packages live in
``ros2_ws/src/<pkg>/<pkg>`` and ``tools/<pkg>``. So each module gets a stage directory
(``ros2_ws/build/mutation/<module>``) holding ``src/<pkg>`` (a copy of its package) and a
pyproject that tells mutmut to mutate that one file and run only the module's fast tests (from
config/mutation.toml) in place, with the other packages importable unmutated via PYTHONPATH.
"""

from __future__ import annotations

import argparse
import fcntl
import os
import re
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import tomllib

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "config" / "mutation.toml"
DOC = ROOT / "docs" / "testing.md"
STAGE = ROOT / "ros2_ws" / "build" / "mutation"
PACKAGE_ROOTS = sorted(p for p in (ROOT / "ros2_ws" / "src").iterdir() if p.is_dir()) + [ROOT / "tools"]
TABLE_START = "<!-- mutation-table:start -->"
TABLE_END = "<!-- mutation-table:end -->"
HEADER = (
    "| module | mutants | killed | survived | equivalent | no tests | timeout | score |\n"
    "|---|---:|---:|---:|---:|---:|---:|---:|"
)
KILLED = {"killed", "timeout", "caught by type check"}


@dataclass
class Result:
    module: str
    statuses: dict[str, str]
    equivalent: set[str]

    def count(self, *names: str) -> int:
        return sum(1 for k, s in self.statuses.items() if s in names and k not in self.equivalent)

    @property
    def score(self) -> float:
        judged = len(self.statuses) - len(self.equivalent & self.statuses.keys())
        return 100.0 * self.count(*KILLED) / judged if judged else float("nan")

    def row(self) -> str:
        unchecked = sum(1 for s in self.statuses.values() if s == "not checked")
        if unchecked:  # a run that was stopped: no score
            done = len(self.statuses) - unchecked
            return (
                f"| `{self.module}` | {len(self.statuses)} | {self.count(*KILLED)} | {self.count('survived')} "
                f"| | {self.count('no tests')} | | incomplete: {done} of {len(self.statuses)} checked |"
            )
        return (
            f"| `{self.module}` | {len(self.statuses)} | {self.count(*KILLED) - self.count('timeout')} "
            f"| {self.count('survived')} | {len(self.equivalent & self.statuses.keys())} "
            f"| {self.count('no tests')} | {self.count('timeout')} | {self.score:.0f} % |"
        )


def package_dir(module: str) -> Path:
    top = module.split(".")[0]
    for root in PACKAGE_ROOTS:
        if (root / top / "__init__.py").is_file():
            return root / top
    raise SystemExit(f"mutation: no package '{top}' under ros2_ws/src/* or tools/ (module {module})")


def module_file(module: str) -> tuple[Path, Path]:
    """(package dir, module path relative to it)."""
    pkg = package_dir(module)
    rel = Path(*module.split(".")[1:]).with_suffix(".py")
    if not (pkg / rel).is_file() and (pkg / rel.with_suffix("") / "__init__.py").is_file():
        rel = rel.with_suffix("") / "__init__.py"  # a subpackage: its __init__ (mutmut names it so)
    if not (pkg / rel).is_file():
        raise SystemExit(f"mutation: module {module}: no file {pkg / rel}")
    return pkg, rel


def stage(module: str, tests: list[str], again: bool = False) -> Path:
    """Stage ``module`` afresh; with ``again`` keep the last run (its mutants and results) and only
    rewrite the test selection, after checking the module's source is the one that was mutated."""
    pkg, rel = module_file(module)
    missing = [t for t in tests if not (ROOT / t).is_file()]
    if missing:
        raise SystemExit(f"mutation: module {module}: test file(s) not found: {', '.join(missing)}")
    d = STAGE / module
    if again:
        staged = d / "src" / pkg.name / rel
        if not (d / "mutants").is_dir() or not staged.is_file():
            raise SystemExit(
                f"mutation: module {module}: no earlier run in {d} to re-check (run it without --again)"
            )
        if staged.read_bytes() != (pkg / rel).read_bytes():
            raise SystemExit(
                f"mutation: module {module}: source changed since the last run; run it without --again"
            )
    else:
        shutil.rmtree(d, ignore_errors=True)  # never reuse an old run's results
        shutil.copytree(pkg, d / "src" / pkg.name, ignore=shutil.ignore_patterns("__pycache__"))
    # a module that finds the repository's data from its own file (fire_uav_common.scenario.ground:
    # parents[5] / "data", e.g. the shipped landscapes) looks in STAGE/data when run from the stage
    if not (STAGE / "data").is_symlink():
        STAGE.mkdir(parents=True, exist_ok=True)
        (STAGE / "data").symlink_to(ROOT / "data", target_is_directory=True)
    # mutmut runs each mutant's tests from <stage>/mutants by their node ids, which are relative to
    # the repository root (--rootdir): without these links pytest finds no such file, the worker
    # fails, and mutmut counts that failure as a KILL (every mutant with a test was "killed").
    (d / "mutants").mkdir(parents=True, exist_ok=True)
    for top in sorted({Path(t).parts[0] for t in tests}):
        link = d / "mutants" / top
        if not link.is_symlink():
            link.symlink_to(ROOT / top, target_is_directory=True)
    (d / "pytest.ini").write_text(
        "[pytest]\naddopts = --import-mode=importlib -p no:cacheprovider -m 'not slow'\n"
        "markers =\n    system: real ROS processes\n    slow: over ~20 s\n"
    )
    toml_list = lambda xs: "[" + ", ".join(f'"{x}"' for x in xs) + "]"  # noqa: E731
    (d / "pyproject.toml").write_text(
        "[tool.mutmut]\n"
        'source_paths = ["src"]\n'
        f'only_mutate = ["src/{pkg.name}/{rel.as_posix()}"]\n'
        f"pytest_add_cli_args = {toml_list(['-c', str(d / 'pytest.ini'), '--rootdir', str(ROOT), '-q'])}\n"
        f"pytest_add_cli_args_test_selection = {toml_list(str(ROOT / t) for t in tests)}\n"
        "use_git_change_detection = false\n"
    )
    return d


def built_message_paths() -> list[Path]:
    """The generated Python of the workspace's message-only packages (no Python sources in src,
    e.g. fire_uav_msgs), from ``ros2_ws/install`` when the workspace is built; empty otherwise.

    Tests that compare a module with rclpy's (de)serialisation of these types (the byte codecs)
    then run in the stage instead of skipping. Only message packages: an algorithm package's
    installed copy would shadow the mutated one. Their C type support (``install/<pkg>/lib``) is
    put on the tests' library path. A checkout without its own build (a second git worktree of the
    same repository) takes them from the install prefixes of the workspace its shell has sourced
    (``AMENT_PREFIX_PATH``): message packages only, so its sources are still the ones mutated.
    """
    out = []
    for src in PACKAGE_ROOTS:
        if (src / src.name).is_dir() or not (src / "msg").is_dir():
            continue
        found = sorted((ROOT / "ros2_ws" / "install" / src.name / "lib").glob("python3*/site-packages"))
        for prefix in filter(None, os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep)):
            if found or Path(prefix).name != src.name:
                continue
            found = sorted((Path(prefix) / "lib").glob("python3*/site-packages"))
        out += found
    return out


def statuses_of(d: Path, module: str, env: dict[str, str]) -> dict[str, str]:
    out = subprocess.run(
        [sys.executable, "-m", "mutmut", "results", "--all", "true"],
        cwd=d,
        env=env,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    statuses = {}
    for line in out.splitlines():
        m = re.match(r"\s*(\S+__mutmut_\d+): (.+)$", line)
        if m:
            statuses[m.group(1)] = m.group(2).strip()
    if not statuses:
        raise SystemExit(f"mutation: module {module}: mutmut reported no mutants:\n{out}")
    return statuses


def run(
    module: str,
    tests: list[str],
    equivalent: set[str],
    show: bool,
    report_only: bool = False,
    again: bool = False,
) -> Result:
    """Mutate ``module`` and test it; ``again``: re-check only the last run's survivors and
    "no tests" mutants (for tests added since; the killed ones stand, the source is unchanged),
    and check the ones a stopped run left unchecked."""
    d = STAGE / module if report_only else stage(module, tests, again)
    if report_only and not (d / "mutants").is_dir():
        raise SystemExit(f"mutation: module {module}: no earlier run in {d} (run without --report-only)")
    pkg_root = package_dir(module).parent
    env = dict(os.environ)
    paths = [str(p) for p in PACKAGE_ROOTS if p != pkg_root] + [str(ROOT / "tests" / "system")]
    built = built_message_paths()  # the .msg packages' generated Python, if built
    paths += [str(p) for p in built]
    libs = [str(p.parents[2]) for p in built]  # their install/<pkg>/lib: the C type support
    env["LD_LIBRARY_PATH"] = os.pathsep.join([*libs, *filter(None, [env.get("LD_LIBRARY_PATH")])])
    env["PYTHONPATH"] = os.pathsep.join(paths)
    env.setdefault("PYTHONHASHSEED", "0")
    mutmut = [sys.executable, "-m", "mutmut"]
    if not report_only:
        names: list[str] = []
        if again:
            names = [
                k
                for k, s in statuses_of(d, module, env).items()
                if s in ("survived", "no tests", "not checked", "segfault")  # a crash decides nothing
            ]
            names = [k for k in names if k not in equivalent]
            if not names:
                print(f"[mutation] {module}: nothing left to re-check", file=sys.stderr, flush=True)
        what = f"re-checking {len(names)} mutant(s)" if again else "mutmut run"
        print(f"[mutation] {module}: {what} against {len(tests)} test file(s)", file=sys.stderr, flush=True)
        t0 = time.monotonic()
        if again:
            # mutmut collects the stats of tests added since by their id relative to the stage dir,
            # which fails for our tests (outside it): drop the stats, so that it collects them all
            # again from the absolute selection (the results themselves are kept)
            (d / "mutants" / "mutmut-stats.json").unlink(missing_ok=True)
        if names or not again:
            with open(d / "mutmut-run.log", "w") as log:  # mutmut's progress spinner, kept out of the table
                rc = subprocess.run(
                    [*mutmut, "run", "--max-children", "1", *names], cwd=d, env=env, stdout=log, stderr=log
                )
            if rc.returncode != 0:
                raise SystemExit(
                    f"mutation: module {module}: mutmut run failed (exit {rc.returncode}); see {d}/mutmut-run.log"
                )
        print(f"[mutation] {module}: {time.monotonic() - t0:.0f} s wall", file=sys.stderr, flush=True)
    statuses = statuses_of(d, module, env)
    listed = equivalent & statuses.keys()
    # mutmut numbers a function's mutants in order, so editing a module re-points the keys of
    # config/mutation.toml at other mutants: a listed "equivalent" that the tests kill is such a
    # stale key (or was never equivalent); it counts as killed, and the key must be fixed
    for k in sorted(k for k in listed if statuses[k] in KILLED):
        print(
            f"  WARNING: {k} is listed as equivalent in config/mutation.toml but the tests kill it: "
            "a stale key (the module changed, mutmut renumbered its mutants) or not equivalent",
            flush=True,
        )
    result = Result(module, statuses, {k for k in listed if statuses[k] not in KILLED})
    survivors = [
        k for k, s in statuses.items() if s not in KILLED and s != "not checked" and k not in equivalent
    ]
    for k in survivors:
        print(f"  {statuses[k]}: {k}")
        if show:
            diff = subprocess.run([*mutmut, "show", k], cwd=d, env=env, capture_output=True, text=True).stdout
            print("    " + "\n    ".join(diff.strip().splitlines()[2:]))
    return result


def update_doc(results: list[Result]) -> None:
    """Rewrite the rows of ``results`` in the table of docs/testing.md. Two runs finishing at once
    (two modules in two shells) take turns on a lock, so neither writes back a table read before
    the other's row went in."""
    STAGE.mkdir(parents=True, exist_ok=True)
    with open(STAGE / "doc.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        _update_doc(results)


def _update_doc(results: list[Result]) -> None:
    text = DOC.read_text() if DOC.exists() else f"# Testing\n\n{TABLE_START}\n{TABLE_END}\n"
    if TABLE_START not in text:
        raise SystemExit(f"mutation: {DOC} has no '{TABLE_START}' marker")
    head, rest = text.split(TABLE_START, 1)
    table, tail = rest.split(TABLE_END, 1)
    rows = {}
    for line in table.splitlines():
        m = re.match(r"\| `([\w.]+)` \|", line)
        if m:
            rows[m.group(1)] = line
    for r in results:
        rows[r.module] = r.row()
    order = list(tomllib.loads(CONFIG.read_text())["modules"])
    lines = [rows.get(m, f"| `{m}` | not run yet | | | | | | |") for m in order]
    DOC.write_text(f"{head}{TABLE_START}\n{HEADER}\n" + "\n".join(lines) + f"\n{TABLE_END}{tail}")


def main() -> int:
    ap = argparse.ArgumentParser(prog="scripts/mutation", description=__doc__.splitlines()[0])
    ap.add_argument("modules", nargs="*", help="dotted module names (default: all in config/mutation.toml)")
    ap.add_argument("--list", action="store_true", help="list the modules and their tests")
    ap.add_argument("--show", action="store_true", help="print the diff of every surviving mutant")
    ap.add_argument("--report-only", action="store_true", help="re-read the last run's results, run nothing")
    ap.add_argument("--no-doc", action="store_true", help=f"do not update {DOC.relative_to(ROOT)}")
    ap.add_argument(
        "--again",
        action="store_true",
        help="re-check only the last run's survivors and 'no tests' mutants (after adding tests); resumes a stopped run",
    )
    a = ap.parse_args()
    cfg = tomllib.loads(CONFIG.read_text())
    modules = cfg["modules"]
    if a.list:
        for m, v in modules.items():
            print(f"{m}: {' '.join(v['tests'])}")
        return 0
    unknown = [m for m in a.modules if m not in modules]
    if unknown:
        raise SystemExit(f"mutation: unknown module(s) {', '.join(unknown)}; see scripts/mutation --list")
    equivalent = set(cfg.get("equivalent", {}))
    results = []
    for m in a.modules or list(modules):
        results.append(run(m, modules[m]["tests"], equivalent, a.show, a.report_only, a.again))
        print(results[-1].row(), flush=True)
        if not a.no_doc:
            update_doc(results[-1:])  # after each module: a long run that stops keeps what it measured
    print(HEADER)
    for r in results:
        print(r.row())
    return 0


if __name__ == "__main__":
    sys.exit(main())
