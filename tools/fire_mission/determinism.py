"""Does a lockstep mission repeat exactly? Run it twice and compare what the two runs recorded.

``scripts/run_mission SCENARIO --check-determinism`` (or the test helper :func:`compare_runs`):
the same scenario, seed and fault schedule run twice; the two ``summary.json`` files are compared
field for field (fields that measure the machine, not the mission, left out: wall time, CPU,
memory, PIDs, the ROS domain, paths), and the ``/world/truth`` messages of the two bags byte for
byte (raw CDR: every vehicle's true state, every fire, every step). The first step at which the
runs part is reported. Realtime mode is not deterministic by design and is refused.
"""

from __future__ import annotations

import argparse
import copy
import json
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

__all__ = ["VOLATILE_KEYS", "RunDiff", "check_twice", "compare_runs", "compare_summaries", "compare_truth"]

#: summary.json fields that measure the machine or the run's place, not the mission
VOLATILE_KEYS = frozenset(
    {
        "wall_time_s",
        "steps_per_wall_s",
        "steps_per_wall_s_note",
        "processes",
        "pids",
        "domain_id",
        "bag",
        "exit_codes",
        "scenario_file",
    }
)
TRUTH_TOPIC = "/world/truth"


@dataclass
class RunDiff:
    """What differs between two runs (empty lists and ``first_step is None``: identical)."""

    summary: list[str] = field(default_factory=list)
    truth_messages: tuple[int, int] = (0, 0)
    first_step: int | None = None
    truth: list[str] = field(default_factory=list)

    @property
    def identical(self) -> bool:
        return not self.summary and not self.truth and self.first_step is None

    def text(self) -> str:
        if self.identical:
            return f"identical: summaries equal, {self.truth_messages[0]} /world/truth messages equal byte for byte"
        lines = []
        if self.first_step is not None:
            lines.append(f"the runs part at step {self.first_step}")
        lines += [f"truth: {t}" for t in self.truth]
        lines += [f"summary: {d}" for d in self.summary[:20]]
        if len(self.summary) > 20:
            lines.append(f"summary: ... {len(self.summary) - 20} more differences")
        return "\n".join(lines)


def _diff(a: object, b: object, path: str, out: list[str], skip: frozenset[str] = VOLATILE_KEYS) -> None:
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b), key=str):
            if path == "" and k in skip:
                continue
            if k not in a or k not in b:
                out.append(f"{path}{k}: only in run {'1' if k in a else '2'}")
            else:
                _diff(a[k], b[k], f"{path}{k}.", out, skip)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{path[:-1]}: {len(a)} vs {len(b)} entries")
        for i, (x, y) in enumerate(zip(a, b, strict=False)):
            _diff(x, y, f"{path}{i}.", out, skip)
    elif a != b:
        out.append(f"{path[:-1]}: {a!r} vs {b!r}")


def compare_summaries(a: dict, b: dict, ignore: tuple[str, ...] = ()) -> list[str]:
    """Differences between two summary.json dicts, volatile fields (and ``ignore``) left out."""
    out: list[str] = []
    _diff(a, b, "", out, VOLATILE_KEYS | frozenset(ignore))
    return out


def compare_truth(bag_a: Path, bag_b: Path) -> tuple[tuple[int, int], int | None, list[str]]:
    """((messages in a, in b), first step whose truth differs or None, details) of two bags."""
    from fire_uav_recording import open_bag

    with open_bag(bag_a) as a, open_bag(bag_b) as b:
        ra = [(conn.msgtype, raw) for conn, _, raw in a.raw_messages([TRUTH_TOPIC])]
        rb = [(conn.msgtype, raw) for conn, _, raw in b.raw_messages([TRUTH_TOPIC])]
        counts = (len(ra), len(rb))
        for i, ((ta, xa), (_, xb)) in enumerate(zip(ra, rb, strict=False)):
            if bytes(xa) != bytes(xb):
                ma, mb = a.reader.deserialize(xa, ta), b.reader.deserialize(xb, ta)
                detail = [f"message {i}: step {ma.step} vs {mb.step}"]
                for va, vb in zip(ma.vehicles, mb.vehicles, strict=False):
                    if (va.x_m, va.y_m, va.z_m, va.status) != (vb.x_m, vb.y_m, vb.z_m, vb.status):
                        detail.append(
                            f"uav {va.uav_id}: ({va.x_m:.3f}, {va.y_m:.3f}, {va.z_m:.3f}) status {va.status} vs "
                            f"({vb.x_m:.3f}, {vb.y_m:.3f}, {vb.z_m:.3f}) status {vb.status}"
                        )
                        break
                return counts, int(min(ma.step, mb.step)), detail
        if counts[0] != counts[1]:
            shorter = min(counts)
            step = None
            if shorter:
                last = (ra if counts[0] < counts[1] else rb)[shorter - 1]
                step = int(a.reader.deserialize(last[1], last[0]).step) + 1
            return counts, step, [f"{counts[0]} vs {counts[1]} truth messages (one run is longer)"]
    return counts, None, []


def compare_runs(run_a: Path, run_b: Path, ignore: tuple[str, ...] = ()) -> RunDiff:
    """Compare two run directories (each with ``summary.json`` and ``bag/``); ``ignore``: more
    top-level summary fields to leave out (e.g. ``faults_injected`` when one run had a stall)."""
    d = RunDiff()
    sa = json.loads((run_a / "summary.json").read_text())
    sb = json.loads((run_b / "summary.json").read_text())
    d.summary = compare_summaries(sa, sb, ignore)
    if (run_a / "bag").exists() and (run_b / "bag").exists():
        d.truth_messages, d.first_step, d.truth = compare_truth(run_a / "bag", run_b / "bag")
    else:
        d.truth = ["a bag is missing (--no-record?): truth not compared"]
    return d


def check_twice(args: argparse.Namespace, run: Callable[[argparse.Namespace], int]) -> int:
    """``--check-determinism``: run ``args`` twice into OUT/run1 and OUT/run2 and compare."""
    from fire_mission.errors import MissionError

    if args.mode != "lockstep":
        raise MissionError(
            "--check-determinism needs --mode lockstep (realtime is not deterministic by design)"
        )
    if args.no_record:
        raise MissionError("--check-determinism compares the bags: drop --no-record")
    root = Path(__file__).resolve().parents[2]
    base = args.out or root / "runs" / f"determinism-{time.strftime('%Y%m%d-%H%M%S')}"
    codes = []
    for name in ("run1", "run2"):
        a = copy.copy(args)
        a.out, a.no_report = base / name, True
        print(f"[run_mission] determinism check: {name} -> {a.out}", file=sys.stderr)
        codes.append(run(a))
    d = compare_runs(base / "run1", base / "run2")
    (base / "determinism.txt").write_text(d.text() + "\n")
    print(f"\n[run_mission] determinism check ({base}):\n{d.text()}", file=sys.stderr)
    return 0 if d.identical else 3
