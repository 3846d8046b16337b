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
