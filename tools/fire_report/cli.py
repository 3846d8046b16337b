"""Command line of the report: one-line errors, exit 0 on success, 2 on a bad bag, 3 on a bug."""

from __future__ import annotations

import argparse
import os
import sys
import traceback
from pathlib import Path
from typing import NoReturn

from fire_report.errors import ReportError


class _OneLineParser(argparse.ArgumentParser):
    """Usage errors in one line (argparse prints its usage block first), exit status 2."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def main(argv: list[str] | None = None) -> int:
    parser = _OneLineParser(
        prog="report",
        description="Metrics, figures and index.html for a recorded mission bag (no ROS needed).",
    )
    parser.add_argument("bag", help="rosbag2 directory (or .mcap file) written by the recorder")
    parser.add_argument("--baseline", help="bag of the same scenario and seed with no fleet (--uavs 0)")
    parser.add_argument("-o", "--out", help="output directory (default: <bag>_report next to the bag)")
    parser.add_argument(
        "--strict",
        action="store_true",
        help="fail on a bag the recorder did not close, instead of reading its complete chunks",
    )
    args = parser.parse_args(argv)
    bag = Path(args.bag)
    out = Path(args.out) if args.out else bag.parent / f"{bag.name.removesuffix('.mcap')}_report"
    try:
        from fire_report.report import write_report

        metrics = write_report(bag, out, salvage=not args.strict, baseline=args.baseline)
    except ReportError as err:
        sys.stderr.write(f"report: error: {err}\n")
        return 2
    except KeyboardInterrupt:
        sys.stderr.write("report: interrupted\n")
        return 130
    except Exception as err:
        if os.environ.get("FIRE_REPORT_DEBUG"):
            traceback.print_exc()
        sys.stderr.write(
            f"report: internal error: {type(err).__name__}: {' '.join(str(err).split())} "
            "(set FIRE_REPORT_DEBUG=1 for the traceback)\n"
        )
        return 3
    for w in metrics.get("warnings", []):
        sys.stderr.write(f"report: warning: {w}\n")
    sys.stdout.write(
        f"report: {out / 'index.html'}  outcome={metrics['outcome']} drops={metrics['drop_count']} "
        f"duration={metrics['mission_duration_s']:.1f}s figures={len(metrics['figures'])}\n"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
