"""``scripts/study STUDY.yaml``: run a study's missions (resumable), then its statistics and report.

    scripts/study STUDY.yaml [--out DIR] [--jobs N | --scheduler tcp://HOST:PORT] [--report-only]

Results go to ``DIR/results.jsonl`` (default ``runs/study/NAME``; one mission per line, resumable),
the report to ``DIR/report/index.html`` with ``results.csv`` and ``results.parquet`` beside it.
Bad input (the study file, a refused results directory) is one line on stderr and exit status 2;
an interrupted study exits 130 and resumes when the same command runs again.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .errors import StudyError

__all__ = ["main"]


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="study", description=__doc__.split("\n\n")[0])
    p.add_argument("study", type=Path, help="study YAML file")
    p.add_argument("--out", type=Path, help="results directory (default runs/study/NAME)")
    p.add_argument("--jobs", type=int, default=1, help="local worker processes (default 1)")
    p.add_argument("--scheduler", help="run the missions on this Dask scheduler (tcp://HOST:PORT)")
    p.add_argument("--report-only", action="store_true", help="no missions: the report of what is on file")
    p.add_argument("--limit", type=int, help="run at most this many of the missions left (then stop)")
    p.add_argument("--no-report", action="store_true", help="run the missions, write no report")
    return p


def main(argv: list[str] | None = None) -> int:
    a = _parser().parse_args(argv)
    try:
        from .spec import load_study

        study = load_study(a.study)
        out = a.out if a.out is not None else Path("runs/study") / study.name
        if a.jobs < 1:
            raise StudyError(f"--jobs must be >= 1, got {a.jobs}")
        if a.limit is not None and a.limit < 0:
            raise StudyError(f"--limit must be >= 0, got {a.limit}")
        from .store import ResultStore

        if not a.report_only:
            from fire_bench.sweep import SweepError, make_executor

            from .run import run_study

            try:
                executor = make_executor(a.scheduler, a.jobs)
            except SweepError as e:
                raise StudyError(str(e)) from None
            try:
                rep = run_study(study, out, executor, limit=a.limit)
            finally:
                executor.close()
            print(
                f"[study] {study.name}: {rep.ran} missions run now, {rep.already} already on file, "
                f"{rep.total} in the study ({rep.wall_s:.0f} s wall, {executor.name})",
                file=sys.stderr,
            )
        if a.report_only and not (out / "results.jsonl").exists():
            raise StudyError(f"{out / 'results.jsonl'}: no such results file: nothing to report")
        store = ResultStore(out, study)
        if not store.rows:
            raise StudyError(f"{out / 'results.jsonl'}: no missions on file yet: nothing to report")
        from .report import summary_table, write_report

        if not a.no_report:
            res = write_report(study, list(store.rows.values()), out / "report")
            print(f"[study] report: {res['index']}", file=sys.stderr)
        print(summary_table(study, list(store.rows.values())))
    except StudyError as e:
        print(f"study: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("\n[study] interrupted: the missions that finished are on file; run the same command to resume",
              file=sys.stderr)  # fmt: skip
        return 130
    return 0


if __name__ == "__main__":
    sys.exit(main())
