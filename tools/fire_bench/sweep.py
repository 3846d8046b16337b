"""Sweeps of independent missions, run locally or fanned out over a Dask distributed cluster.

A sweep-shaped sub-benchmark of ``scripts/bench`` returns a :class:`Sweep`: a list of
independent :class:`MissionSpec` (scenario, fleet size, seed, overrides, mode) and a reducer
that turns the finished missions into the benchmark's JSON figures. An :class:`Executor` runs
the specs: :class:`LocalExecutor` in this process (sequential, today's behaviour) or on a local
process pool, :class:`DaskExecutor` on the workers of a ``distributed`` scheduler
(``scripts/bench --scheduler tcp://HOST:PORT``). Results are always handed to the reducer in
the order of the sorted specs, never in completion order, so ``results.json`` is the same
whichever executor ran the missions (lockstep missions are deterministic per seed).

Modes:

* ``harness``: :func:`fire_mission.inprocess.run_inprocess` (the real World and Agents, no
  DDS) -- needs no ROS domain;
* ``processes``: ``python -m fire_mission.runner`` (the real process fleet, no recording) on a
  ROS domain claimed for this mission alone on its host (``fire_mission.procs.claim_domain``: an exclusive
  lock file per domain id, so two missions on one worker, or on two workers of one host, never
  share a domain);
* ``call``: any importable ``module:function(**kwargs)`` returning a JSON-able dict (for
  sub-benchmarks whose mission is not a plain summary, e.g. the suppression cases).

A derived scenario travels with its spec as YAML text (``scenario_yaml``): a worker on
another machine has no access to the client's temporary files. Dask is imported only when a
scheduler is given.
"""

from __future__ import annotations

import contextlib
import importlib
import json
import os
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

from fire_bench.errors import SweepError

__all__ = [
    "DaskExecutor",
    "Executor",
    "LocalExecutor",
    "MissionSpec",
    "Sweep",
    "SweepError",
    "make_executor",
    "run_spec",
    "run_sweep",
]

MODES = ("harness", "processes", "call")
#: the Dask pins of requirements/py.txt (named in the "not installed" error)
DASK_PINS = "dask==2026.8.0 distributed==2026.8.0"


@dataclass(frozen=True)
class MissionSpec:
    """One independent mission of a sweep. Plain data: it is pickled to the worker.

    ``overrides`` are dotted scenario fields (``(("timing.max_duration_s", 20.0),)``, the
    runner's ``--set``); ``uavs`` None flies the scenario's fleet and 0 none (the fire alone, as
    in every runner); ``args`` are extra ``fire_mission.runner`` arguments (processes mode
    only, e.g. ``("--kill", "1@30")``); ``label`` is the reducer's name for the case.
    """

    bench: str
    scenario: str
    uavs: int | None = None
    seed: int | None = None
    overrides: tuple[tuple[str, Any], ...] = ()
    mode: str = "harness"
    args: tuple[str, ...] = ()
    label: str = ""
    scenario_yaml: str | None = None
    call: str = ""
    kwargs: tuple[tuple[str, Any], ...] = ()
    timeout_s: float = 1800.0

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise SweepError(f"mission spec mode must be one of {', '.join(MODES)}, got '{self.mode}'")
        if self.mode == "call" and ":" not in self.call:
            raise SweepError(f"mission spec mode 'call' needs call='module:function', got '{self.call}'")
        if self.args and self.mode != "processes":
            raise SweepError(f"mission spec args {list(self.args)} only apply to mode 'processes'")
        if self.uavs is not None and self.uavs < 0:
            raise SweepError(f"mission spec uavs must be >= 0, got {self.uavs}")

    def sort_key(self) -> str:
        """A total order over specs of any field types (JSON of the fields, keys sorted)."""
        return json.dumps(
            [
                self.bench,
                self.label,
                self.scenario,
                self.mode,
                self.uavs,
                self.seed,
                self.overrides,
                self.args,
                self.call,
                self.kwargs,
                self.scenario_yaml or "",
            ],
            sort_keys=True,
            default=str,
        )

    def describe(self) -> str:
        fleet = "" if self.uavs is None else f"uavs={self.uavs}"  # None: the scenario's
        parts = [self.bench, self.label or self.scenario, fleet, f"seed={self.seed}", self.mode]
        return " ".join(p for p in parts if p)


@dataclass
class Sweep:
    """What a sweep-shaped sub-benchmark returns: its missions and how to reduce them.

    ``reduce`` gets ``[(spec, result), ...]`` in sorted-spec order and returns the
    benchmark's JSON-able figures; it runs on the client, never on a worker.
    """

    specs: list[MissionSpec]
    reduce: Callable[[list[tuple[MissionSpec, dict]]], dict]


@dataclass(frozen=True)
class Finished:
    """One finished mission as the executor reports it (``result`` is the mission's dict)."""

    result: dict
    wall_s: float
    worker: str


# --- on the worker ----------------------------------------------------------------------------
def _scenario_arg(spec: MissionSpec, tmp: Path) -> str:
    if spec.scenario_yaml is None:
        return spec.scenario
    path = tmp / f"{Path(spec.scenario).stem}.yaml"
    path.write_text(spec.scenario_yaml)
    return str(path)


def _run_processes(spec: MissionSpec, scenario: str, tmp: Path) -> dict:
    import zlib

    from fire_mission.procs import MissionError, claim_domain

    hint = zlib.crc32(spec.sort_key().encode())
    with claim_domain(hint) as domain:
        env = dict(os.environ, FIRE_UAV_DOMAIN_ID=str(domain), ROS_DOMAIN_ID=str(domain))
        argv = [sys.executable, "-m", "fire_mission.runner", scenario]
        if spec.uavs is not None:
            argv += ["--uavs", str(spec.uavs)]
        if spec.seed is not None:
            argv += ["--seed", str(spec.seed)]
        for k, v in spec.overrides:
            argv += ["--set", f"{k}={json.dumps(v) if not isinstance(v, str) else v}"]
        argv += [*spec.args, "--out", str(tmp / "run"), "--quiet", "--no-record", "--no-report"]
        try:
            p = subprocess.run(
                argv, env=env, capture_output=True, text=True, timeout=spec.timeout_s, check=False
            )
        except subprocess.TimeoutExpired:
            return {"outcome": "runner_failed", "error": f"runner exceeded {spec.timeout_s:g} s wall"}
        summary = tmp / "run/summary.json"
        if not summary.is_file():
            tail = (p.stderr or "").strip().splitlines()[-3:]
            return {"outcome": "runner_failed", "exit_code": p.returncode, "error": " | ".join(tail)}
        out = json.loads(summary.read_text())
        if out.get("domain_id") not in (None, domain):
            raise MissionError(f"runner used ROS domain {out.get('domain_id')}, not the claimed {domain}")
        return out


def run_spec(spec: MissionSpec) -> tuple[dict, float, str]:
    """Run one mission here (on a worker, or in the client); returns (result, wall [s], worker)."""
    t0 = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="sweep-") as d:
        tmp = Path(d)
        if spec.mode == "harness":
            from fire_mission.inprocess import run_inprocess

            result = run_inprocess(
                _scenario_arg(spec, tmp), uavs=spec.uavs, seed=spec.seed, overrides=dict(spec.overrides)
            )
        elif spec.mode == "processes":
            result = _run_processes(spec, _scenario_arg(spec, tmp), tmp)
        else:
            mod, fn = spec.call.split(":", 1)
            result = getattr(importlib.import_module(mod), fn)(**dict(spec.kwargs))
    return result, time.monotonic() - t0, _worker_name()


def _worker_name() -> str:
    try:
        from distributed import get_worker

        return str(get_worker().address)
    except (ImportError, ValueError):
        return f"{socket.gethostname()}:{os.getpid()}"


# --- executors --------------------------------------------------------------------------------
Progress = Callable[[int, int, MissionSpec, Finished], None]


def _collect(
    specs: Sequence[MissionSpec],
    completed: Iterable[tuple[int, tuple[dict, float, str]]],
    progress: Progress | None,
) -> list[Finished]:
    """The missions in the specs' order, from ``(spec index, run_spec's result)`` pairs in the
    order they finish (reporting each to ``progress`` as it comes)."""
    out: list[Finished | None] = [None] * len(specs)
    for done, (i, raw) in enumerate(completed, 1):
        out[i] = f = Finished(*raw)
        if progress:
            progress(done, len(specs), specs[i], f)
    return [f for f in out if f is not None]


class Executor(Protocol):
    """Runs mission specs; ``run`` returns one :class:`Finished` per spec, in the specs' order."""

    name: str

    def run(self, specs: Sequence[MissionSpec], progress: Progress | None = None) -> list[Finished]: ...

    def close(self) -> None: ...


class LocalExecutor:
    """This machine: sequentially in this process (``jobs`` 1) or on a process pool."""

    def __init__(self, jobs: int = 1) -> None:
        if jobs < 1:
            raise SweepError(f"local jobs must be >= 1, got {jobs}")
        self.jobs = jobs
        self.name = "local" if jobs == 1 else f"local x{jobs}"

    def run(self, specs: Sequence[MissionSpec], progress: Progress | None = None) -> list[Finished]:
        if self.jobs == 1:
            return _collect(specs, ((i, run_spec(s)) for i, s in enumerate(specs)), progress)
        with ProcessPoolExecutor(max_workers=self.jobs) as ex:
            futs = {ex.submit(run_spec, s): i for i, s in enumerate(specs)}
            return _collect(specs, ((futs[f], f.result()) for f in as_completed(futs)), progress)

    def close(self) -> None:
        pass


class DaskExecutor:
    """The workers of a Dask ``distributed`` scheduler; one task per mission.

    Every worker must run from a bootstrapped checkout with ``scripts/env.sh`` sourced (it
    imports ``fire_bench.sweep`` and the project's packages). Tasks are submitted ``pure=False``
    (a mission is never served from another's cache) with no retries: a mission that raises
    fails the sweep with the worker's error.
    """

    def __init__(self, address: str, connect_timeout_s: float = 5.0) -> None:
        try:
            from distributed import Client
        except ImportError as e:
            raise SweepError(
                f"--scheduler {address} needs Dask distributed, which is not installed ({e}); "
                f"install the pins of requirements/py.txt: pip install {DASK_PINS}"
            ) from None
        _probe(address, connect_timeout_s)
        # built in two steps so that a failed connection can be closed here, quietly, instead of
        # by Client.__del__ at exit (a 10 s wait and a traceback)
        client = Client.__new__(Client)
        try:
            client.__init__(address, timeout=f"{connect_timeout_s}s", set_as_default=False)  # type: ignore[misc]
        except Exception as e:  # OSError, TimeoutError, a non-Dask listener's garbage (MemoryError)
            with contextlib.suppress(Exception):
                client.close(timeout=1)
            msg = str(e).strip().splitlines()[0] if str(e).strip() else ""
            raise SweepError(
                f"cannot reach the Dask scheduler at {address} within {connect_timeout_s:g} s: "
                f"{type(e).__name__}{': ' + msg if msg else ''} (is a Dask scheduler listening there?)"
            ) from None
        self.client = client
        self.address = address
        self.name = f"dask {address}"

    def workers(self) -> list[str]:
        """The addresses of the workers connected now."""
        return sorted(self.client.scheduler_info().get("workers", {}))

    def run(self, specs: Sequence[MissionSpec], progress: Progress | None = None) -> list[Finished]:
        from distributed import as_completed as dask_completed

        futs = [
            self.client.submit(run_spec, s, pure=False, key=f"mission-{i}-{os.getpid()}-{time.time_ns()}")
            for i, s in enumerate(specs)
        ]
        index = {f.key: i for i, f in enumerate(futs)}
        completed = ((index[f.key], f.result()) for f in dask_completed(futs, loop=self.client.loop))
        return _collect(specs, completed, progress)

    def close(self) -> None:
        self.client.close()


def _probe(address: str, timeout_s: float) -> None:
    """Fail fast with one line when ``address`` is not ``tcp://HOST:PORT`` or nothing listens there
    (a refused or unresolvable address fails at once, a silent one after ``timeout_s``)."""
    scheme, sep, rest = address.partition("://")
    host, colon, port = rest.rpartition(":")
    if not sep or scheme != "tcp" or not colon or not host or not port.isdigit():
        raise SweepError(f"--scheduler expects tcp://HOST:PORT, got '{address}'")
    try:
        with socket.create_connection((host.strip("[]"), int(port)), timeout=timeout_s):
            pass
    except OSError as e:
        why = "timed out" if isinstance(e, TimeoutError) else (e.strerror or str(e))
        raise SweepError(
            f"cannot reach the Dask scheduler at {address} within {timeout_s:g} s: {why}"
        ) from None


def make_executor(scheduler: str | None, jobs: int = 1) -> Executor:
    """``DaskExecutor(scheduler)`` when an address is given, else ``LocalExecutor(jobs)``."""
    if scheduler:
        return DaskExecutor(scheduler)
    return LocalExecutor(jobs)


def _log_progress(k: int, n: int, spec: MissionSpec, f: Finished) -> None:
    outcome = f.result.get("outcome", "done") if isinstance(f.result, Mapping) else "done"
    print(
        f"[bench] {k}/{n} {spec.describe()}: {outcome}, {f.wall_s:.1f} s wall on {f.worker}",
        file=sys.stderr,
        flush=True,
    )


def run_sweep(sweep: Sweep, executor: Executor, progress: Progress | None = _log_progress) -> dict:
    """Run the sweep's specs (sorted by :meth:`MissionSpec.sort_key`) and reduce them."""
    specs = sorted(sweep.specs, key=MissionSpec.sort_key)
    keys = [s.sort_key() for s in specs]
    if len(set(keys)) != len(keys):
        dup = next(s for i, s in enumerate(specs) if keys.count(keys[i]) > 1)
        raise SweepError(f"sweep has the same mission twice: {dup.describe()}")
    finished = executor.run(specs, progress)
    return sweep.reduce([(s, f.result) for s, f in zip(specs, finished, strict=True)])


@dataclass
class SweepResults:
    """Helper for reducers: the results of one sweep, looked up by spec fields."""

    pairs: list[tuple[MissionSpec, dict]] = field(default_factory=list)

    def where(self, **match: Any) -> list[dict]:
        return [r for s, r in self.pairs if all(getattr(s, k) == v for k, v in match.items())]
