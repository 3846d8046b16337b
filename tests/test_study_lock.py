"""One study run per results directory: a second run on a directory another process is writing
stops at once (exit 2, the directory and the holder named) and writes nothing; once the holder is
gone, killed or not, the next run proceeds (no stale lock)."""

from __future__ import annotations

import io
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from fire_bench.sweep import Finished
from fire_study.cli import main
from fire_study.errors import StudyError
from fire_study.run import run_study
from fire_study.spec import load_study
from fire_study.store import run_lock

TINY = {"name": "tiny", "scenarios": ["tiny_test"], "tactics": ["head", "flank"], "uavs": [2], "seeds": [1, 2],
        "time_limit_s": 6}  # fmt: skip


class ArithmeticExecutor:
    """Stands in for the missions: a result made from the spec (the lock, not the missions, is tested)."""

    name = "arithmetic"

    def __init__(self) -> None:
        self.ran: list[str] = []

    def run(self, specs, progress=None):
        out = []
        for k, spec in enumerate(specs, 1):
            res = {"outcome": "time_limit", "burned_area_m2": 100.0 * dict(spec.kwargs)["seed"], "contained": False,
                   "contained_at_s": None, "time_limit_s": 6.0, "wall_s": 0.1}  # fmt: skip
            f = Finished(res, 0.1, "here")
            self.ran.append(spec.label)
            if progress:
                progress(k, len(specs), spec, f)
            out.append(f)
        return out

    def close(self) -> None:
        pass


HOLD = """
import sys, time
from pathlib import Path
from fire_study.store import run_lock
with run_lock(Path(sys.argv[1])):
    print("held", flush=True)
    time.sleep(120)
"""


def _holder(out: Path) -> subprocess.Popen:
    p = subprocess.Popen([sys.executable, "-c", HOLD, str(out)], stdout=subprocess.PIPE, text=True,
                         start_new_session=True)  # fmt: skip
    assert p.stdout is not None and p.stdout.readline().strip() == "held"
    return p


def _study(tmp_path: Path):
    f = tmp_path / "tiny.yaml"
    f.write_text(yaml.safe_dump(TINY))
    return load_study(f)


def test_a_second_run_on_a_directory_being_written_stops_and_writes_nothing(tmp_path: Path, capsys) -> None:
    study = _study(tmp_path)
    out = tmp_path / "results"
    holder = _holder(out)
    try:
        ex = ArithmeticExecutor()
        with pytest.raises(StudyError, match=rf"{out}: another study run .*process {holder.pid}"):
            run_study(study, out, ex, stream=io.StringIO())
        assert ex.ran == []
        assert not (out / "results.jsonl").exists()
        # the command line: one line, exit status 2
        assert main([str(tmp_path / "tiny.yaml"), "--out", str(out), "--no-report"]) == 2
        err = capsys.readouterr().err
        assert err.startswith("study: error: ") and f"process {holder.pid}" in err and err.count("\n") == 1
    finally:
        os.kill(holder.pid, signal.SIGKILL)
        holder.wait(timeout=30)
    # the holder was killed, not stopped: the kernel released its lock
    ex = ArithmeticExecutor()
    rep = run_study(study, out, ex, stream=io.StringIO())
    assert (rep.ran, rep.total) == (4, 4) and len(ex.ran) == 4


def test_the_lock_is_released_after_a_run_and_after_an_error_inside_it(tmp_path: Path) -> None:
    with run_lock(tmp_path):
        pass
    with pytest.raises(RuntimeError), run_lock(tmp_path):
        raise RuntimeError("a mission failed")
    with run_lock(tmp_path):  # taken again in the same process: nothing left held
        with pytest.raises(StudyError, match="another study run"), run_lock(tmp_path):
            pass
