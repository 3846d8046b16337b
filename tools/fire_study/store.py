"""The results of one study: ``results.jsonl``, one mission per line, appended and flushed.

The first line is a header naming the study and the sha256 of its canonical content
(:meth:`fire_study.spec.Study.digest`); every other line is one finished mission (its key --
scenario, airframe, uavs, tactic, seed -- and its measures). A study reopened on the same
directory resumes: the missions already on file are not run again. A file of another study, or
of this study's file changed since (other seeds, tactics, overrides, ...), is refused: results of
two studies are never mixed. A line cut short by a kill (no newline at the end) is dropped.
When every mission is in, the file is rewritten in the study's own mission order, so a study
resumed after a kill ends with the same file as one run straight through.

One run at a time per directory: :func:`run_lock` holds an exclusive ``flock`` on
``DIR/results.lock`` while missions run, so a second run on the same directory (which would
append the same missions twice, or rewrite the file under the first) stops at once with an error
naming the directory and the holder's process id. The kernel drops the lock when its process
ends, killed or not, so a lock is never left stale.
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

from .errors import StudyError
from .spec import Study

__all__ = ["FORMAT", "KEY_FIELDS", "ResultStore", "mission_key", "read_results", "run_lock"]

FORMAT = "fire_study/1"
KEY_FIELDS = ("scenario", "airframe", "uavs", "tactic", "seed")


def mission_key(row: dict[str, Any]) -> tuple:
    return tuple(row[k] for k in KEY_FIELDS)


def _dumps(obj: Any) -> str:
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), allow_nan=False)


@contextlib.contextmanager
def run_lock(out_dir: Path) -> Iterator[Path]:
    """Hold ``out_dir/results.lock`` (module doc) for the ``with`` block; :class:`StudyError` if
    another process holds it."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "results.lock"
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(fd, 64, 0).decode(errors="replace").strip() or "unknown"
            raise StudyError(
                f"{out_dir}: another study run is writing these results (process {holder}, lock {path}); "
                "wait for it to end, stop it, or use another --out directory"
            ) from None
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
        try:
            yield path
        finally:
            os.ftruncate(fd, 0)
            fcntl.flock(fd, fcntl.LOCK_UN)
    finally:
        os.close(fd)


def read_results(path: Path) -> tuple[dict, list[dict]]:
    """(header, rows) of a results file; complete lines only."""
    header: dict | None = None
    rows: list[dict] = []
    text = path.read_text(encoding="utf-8")
    for i, line in enumerate(text.split("\n")[:-1]):  # the last piece: "" or a line cut short
        if not line.strip():
            continue
        try:
            obj = json.loads(line)
        except json.JSONDecodeError as e:
            raise StudyError(f"{path}: line {i + 1}: not JSON ({e.msg}); the file is damaged") from None
        if header is None:
            if obj.get("format") != FORMAT:
                raise StudyError(f"{path}: line 1: not a study results file (format {obj.get('format')!r})")
            header = obj
        else:
            rows.append(obj)
    if header is None:
        raise StudyError(f"{path}: no header line: not a study results file")
    return header, rows


class ResultStore:
    """``DIR/results.jsonl`` of one study (module doc)."""

    def __init__(self, out_dir: Path, study: Study) -> None:
        self.path = Path(out_dir) / "results.jsonl"
        self.study = study
        self.header: dict[str, Any] = {
            "format": FORMAT,
            "study": study.name,
            "study_sha256": study.digest(),
            "missions": len(study.seeds) * len(study.arms()),
        }
        self.rows: dict[tuple, dict] = {}
        if self.path.exists():
            self._reopen()
        else:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._write_all([])

    def _reopen(self) -> None:
        header, rows = read_results(self.path)
        if header.get("study_sha256") != self.header["study_sha256"]:
            raise StudyError(
                f"{self.study.file}: the results in {self.path} belong to "
                + (
                    f"another study ({header.get('study')!r})"
                    if header.get("study") != self.study.name
                    else "this study as it was before the file changed"
                )
                + f" (sha256 {str(header.get('study_sha256'))[:12]} there, {self.header['study_sha256'][:12]} now);"
                " use another --out directory, or restore the study file"
            )
        text = self.path.read_bytes()
        if text and not text.endswith(b"\n"):  # a line cut short by a kill: drop it
            with self.path.open("r+b") as f:
                f.truncate(text.rfind(b"\n") + 1)
        self.rows = {mission_key(r): r for r in rows}

    def done(self) -> set[tuple]:
        return set(self.rows)

    def append(self, row: dict) -> None:
        """One finished mission, on disk (flushed and fsynced) before this returns."""
        key = mission_key(row)
        if key in self.rows:
            return
        with self.path.open("a", encoding="utf-8") as f:
            f.write(_dumps(row) + "\n")
            f.flush()
            os.fsync(f.fileno())
        self.rows[key] = row

    def _write_all(self, rows: Iterable[dict]) -> None:
        tmp = self.path.with_suffix(".jsonl.tmp")
        with tmp.open("w", encoding="utf-8") as f:
            f.write(_dumps(self.header) + "\n")
            for r in rows:
                f.write(_dumps(r) + "\n")
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, self.path)

    def finalise(self, order: list[tuple]) -> None:
        """Rewrite the file in ``order`` (the study's mission order) once every mission is in."""
        rank = {k: i for i, k in enumerate(order)}
        self._write_all(sorted(self.rows.values(), key=lambda r: rank.get(mission_key(r), len(rank))))
