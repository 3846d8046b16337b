"""Command-line pieces shared by the runners and the benchmarks: one-line usage errors."""

from __future__ import annotations

import argparse
from typing import NoReturn


class OneLineParser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose usage errors are one line: what is wrong and where to look
    (``--help``), exit status 2. argparse's own prints the whole usage block first, and the line
    that matters comes last."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


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
