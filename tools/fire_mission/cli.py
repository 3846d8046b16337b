"""Command-line pieces shared by the runners and the benchmarks: one-line usage errors."""

from __future__ import annotations

import argparse
from collections.abc import Iterable
from typing import Any, NoReturn


class OneLineParser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose usage errors are one line: what is wrong and where to look
    (``--help``), exit status 2. argparse's own prints the whole usage block first, and the line
    that matters comes last."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def set_overrides(p: argparse.ArgumentParser, pairs: Iterable[str]) -> dict[str, Any]:
    """The scenario overrides of repeated ``--set FIELD=VALUE`` options, each value read as YAML
    (``3``, ``true``, ``[1, 2]``); a pair without ``=`` is a usage error naming it."""
    import yaml

    overrides: dict[str, Any] = {}
    for kv in pairs:
        if "=" not in kv:
            p.error(f"--set {kv!r}: expected FIELD=VALUE")
        k, v = kv.split("=", 1)
        overrides[k] = yaml.safe_load(v)
    return overrides


def mission_exit_status(outcome: str, uav_count: int, user_max_duration_s: float | None) -> int:
    """0 when the mission ended as asked, 1 when the fleet ran out of the scenario's own time.

    A mission the user cut short with ``--max-duration`` ended where it was asked to (a quick
    look, an example, a smoke test); a fleet that did not finish within the scenario's own time
    limit failed. With no fleet the fire burns until the limit: that is the run's purpose.
    """
    if outcome == "complete":
        return 0
    if outcome == "time_limit" and (uav_count == 0 or user_max_duration_s is not None):
        return 0
    return 1
