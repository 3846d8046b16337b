"""Run a study's missions that are not on file yet, on local workers or a Dask cluster.

The missions go through ``fire_bench.sweep``'s executors (``LocalExecutor``: this process or a
local process pool; ``DaskExecutor``: a ``distributed`` scheduler); each finished mission is
written to the study's :class:`~fire_study.store.ResultStore` as it arrives, so a study killed
at any point keeps every mission that finished. The order of submission is seed-major (every arm
of the first seed, then the next seed): a study cut short holds whole paired seeds first.
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TextIO

from fire_bench.sweep import Executor, Finished, MissionSpec

from .spec import Arm, Study, mission_overrides, scenario_path_of
from .store import KEY_FIELDS, ResultStore, run_lock

__all__ = ["StudyMission", "RunReport", "missions", "run_study"]


@dataclass(frozen=True)
class StudyMission:
    arm: Arm
    seed: int

    def key(self) -> tuple:
        return (self.arm.scenario, self.arm.airframe, self.arm.uavs, self.arm.tactic, self.seed)

    def describe(self) -> str:
        return f"{self.arm.label()} seed {self.seed}"


@dataclass
class RunReport:
    total: int
    already: int
    ran: int
    wall_s: float


def missions(study: Study) -> list[StudyMission]:
    """Every mission of the study, seed-major (module doc)."""
    return [StudyMission(a, s) for s in study.seeds for a in study.arms()]


def _spec(study: Study, m: StudyMission) -> MissionSpec:
    ov = mission_overrides(study, m.arm.scenario, m.arm.airframe, m.arm.uavs, m.arm.tactic, m.seed)
    path = scenario_path_of(study, m.arm.scenario)
    is_file = Path(m.arm.scenario).suffix in (".yaml", ".yml")
    kwargs: dict[str, Any] = {
        "scenario": path.name if is_file else m.arm.scenario,
        "uavs": m.arm.uavs,
        "seed": m.seed,
        "overrides": tuple(sorted(ov.items())),
        "scenario_yaml": path.read_text(encoding="utf-8") if is_file else None,
        "scenario_dir": str(path.resolve().parent) if is_file else None,
    }
    return MissionSpec(
        bench="study",
        scenario=m.arm.scenario,
        uavs=m.arm.uavs,
        seed=m.seed,
        mode="call",
        call="fire_study.mission:run_mission",
        kwargs=tuple(sorted(kwargs.items())),
        label=m.describe(),
    )


def _clock(s: float) -> str:
    s = max(0, int(round(s)))
    return f"{s // 3600}:{s % 3600 // 60:02d}:{s % 60:02d}"


class StudyProgress:
    """A progress bar with an ETA on ``stream`` (a line per mission when it is not a terminal)."""

    def __init__(self, total: int, already: int, stream: TextIO, width: int = 30) -> None:
        self.total, self.already, self.stream, self.width = total, already, stream, width
        self.t0 = time.monotonic()
        self.tty = hasattr(stream, "isatty") and stream.isatty()

    def update(self, done_now: int, last: str) -> None:
        done = self.already + done_now
        elapsed = time.monotonic() - self.t0
        left = self.total - done
        eta = elapsed / done_now * left if done_now else float("nan")
        fill = int(self.width * done / max(self.total, 1))
        bar = "#" * fill + "." * (self.width - fill)
        eta_s = _clock(eta) if eta == eta else "?"
        line = f"[study] [{bar}] {done}/{self.total} elapsed {_clock(elapsed)} ETA {eta_s} | {last}"
        if self.tty:
            self.stream.write("\r\x1b[2K" + line + ("\n" if left == 0 else ""))
        else:
            self.stream.write(line + "\n")
        self.stream.flush()


def run_study(
    study: Study,
    out_dir: Path,
    executor: Executor,
    stream: TextIO = sys.stderr,
    limit: int | None = None,
) -> RunReport:
    """Run the missions of ``study`` not yet in ``out_dir/results.jsonl`` (at most ``limit`` of them);
    rewrites the file in mission order once every mission is in."""
    with run_lock(Path(out_dir)):
        return _run_locked(study, out_dir, executor, stream, limit)


def _run_locked(
    study: Study, out_dir: Path, executor: Executor, stream: TextIO, limit: int | None
) -> RunReport:
    store = ResultStore(out_dir, study)
    order = missions(study)
    done = store.done()
    todo = [m for m in order if m.key() not in done]
    if limit is not None:
        todo = todo[:limit]
    by_label = {m.describe(): m for m in todo}
    already = sum(1 for m in order if m.key() in done)
    bar = StudyProgress(len(order), already, stream)
    walls = (Path(out_dir) / "missions.log").open("a", encoding="utf-8")
    t0 = time.monotonic()

    def finished(k: int, n: int, spec: MissionSpec, f: Finished) -> None:
        m = by_label[spec.label]
        result = dict(f.result)
        wall = result.pop("wall_s", f.wall_s)
        row = dict(zip(KEY_FIELDS, m.key(), strict=True))
        row.update(result)
        store.append(row)
        walls.write(f"{m.describe()}: {result.get('outcome')}, {wall:.1f} s wall on {f.worker}\n")
        walls.flush()
        bar.update(k, f"{m.describe()}: {result.get('outcome')} ({wall:.0f} s)")

    try:
        if todo:
            executor.run([_spec(study, m) for m in todo], finished)
    finally:
        walls.close()
    if len(store.done() & {m.key() for m in order}) == len(order):
        store.finalise([m.key() for m in order])
    return RunReport(len(order), already, len(todo), time.monotonic() - t0)
