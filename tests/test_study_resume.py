"""A study's results survive a kill: resumed, it reruns nothing that finished and ends with the
same results file as a study run straight through -- locally, and on a two-worker Dask cluster.

Tiny study: tiny_test (an analytic fire, 2 UAVs), head and flank, seeds 1 and 2, 6 s missions,
with a fire variation so that the seeds differ.
"""

from __future__ import annotations

import io
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml
from fire_bench.sweep import Finished, LocalExecutor
from fire_study.run import run_study
from fire_study.spec import load_study
from fire_study.store import read_results

TINY = {
    "name": "tiny",
    "scenarios": ["tiny_test"],
    "tactics": ["head", "flank"],
    "uavs": [2],
    "seeds": [1, 2],
    "time_limit_s": 6,
    "fire_variation": {"ignition_sd_m": 10},
}


def _study(tmp_path: Path, doc: dict = TINY):
    p = tmp_path / "tiny.yaml"
    p.write_text(yaml.safe_dump(doc))
    return load_study(p)


def _straight(tmp_path: Path, study) -> bytes:
    rep = run_study(study, tmp_path / "straight", LocalExecutor(1), stream=io.StringIO())
    assert (rep.ran, rep.already, rep.total) == (4, 0, 4)
    return (tmp_path / "straight" / "results.jsonl").read_bytes()


class ArithmeticExecutor:
    """Stands in for the missions (fast tier): a result computed from the spec, reported in an
    order other than the specs' (the last first), as parallel workers do."""

    name = "arithmetic"

    def __init__(self) -> None:
        self.ran: list[str] = []

    def run(self, specs, progress=None):
        out = []
        for k, spec in enumerate(reversed(specs), 1):
            kw = dict(spec.kwargs)
            res = {"outcome": "time_limit", "burned_area_m2": 100.0 * kw["seed"] + kw["uavs"], "contained": False,
                   "contained_at_s": None, "time_limit_s": 6.0, "wall_s": 0.1}  # fmt: skip
            f = Finished(res, 0.1, "here")
            self.ran.append(spec.label)
            if progress:
                progress(k, len(specs), spec, f)
            out.append(f)
        return out[::-1]

    def close(self) -> None:
        pass


def test_resume_skips_finished_missions_drops_a_cut_line_and_ends_with_the_same_file(tmp_path: Path) -> None:
    study = _study(tmp_path, dict(TINY, seeds=[1, 2, 3]))
    ex = ArithmeticExecutor()
    assert run_study(study, tmp_path / "straight", ex, stream=io.StringIO()).ran == 6
    whole = (tmp_path / "straight" / "results.jsonl").read_bytes()
    out = tmp_path / "cut"
    first = ArithmeticExecutor()
    assert run_study(study, out, first, stream=io.StringIO(), limit=4).ran == 4
    with (out / "results.jsonl").open("a") as f:
        f.write('{"scenario":"tiny_test","airfr')  # a line cut short by SIGKILL mid-write
    second = ArithmeticExecutor()
    rep = run_study(study, out, second, stream=io.StringIO())
    assert (rep.ran, rep.already, rep.total) == (2, 4, 6)
    assert set(first.ran) | set(second.ran) == set(ex.ran) and not set(first.ran) & set(second.ran)
    assert (out / "results.jsonl").read_bytes() == whole
    assert (
        run_study(study, out, ArithmeticExecutor(), stream=io.StringIO()).ran == 0
    )  # all done: nothing runs


@pytest.mark.slow
def test_a_study_cut_short_and_resumed_ends_with_the_same_file(tmp_path: Path) -> None:
    study = _study(tmp_path)
    whole = _straight(tmp_path, study)
    out = tmp_path / "cut"
    first = run_study(study, out, LocalExecutor(1), stream=io.StringIO(), limit=2)
    assert (first.ran, first.already) == (2, 0)
    header, rows = read_results(out / "results.jsonl")
    assert len(rows) == 2 and header["missions"] == 4
    with (out / "results.jsonl").open("a") as f:
        f.write('{"scenario":"tiny_test","airfr')  # a line cut short by SIGKILL mid-write
    log = io.StringIO()
    second = run_study(study, out, LocalExecutor(1), stream=log)
    assert (second.ran, second.already, second.total) == (2, 2, 4)  # nothing finished runs again
    assert "[study] [" in log.getvalue() and "ETA" in log.getvalue()
    assert (out / "results.jsonl").read_bytes() == whole
    _, rows = read_results(out / "results.jsonl")
    assert [(r["tactic"], r["seed"]) for r in rows] == [("head", 1), ("flank", 1), ("head", 2), ("flank", 2)]
    assert "wall_s" not in rows[0]  # nothing machine-dependent in the results


def _cli(tmp_path: Path, *args: str) -> subprocess.Popen:
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    return subprocess.Popen(
        [sys.executable, "-m", "fire_study", str(tmp_path / "tiny.yaml"), *args],
        env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
    )  # fmt: skip


@pytest.mark.slow
def test_a_study_killed_with_sigkill_resumes_to_the_same_file(tmp_path: Path) -> None:
    study = _study(tmp_path, dict(TINY, seeds=[1, 2, 3]))
    whole = run_study(study, tmp_path / "straight", LocalExecutor(1), stream=io.StringIO())
    assert whole.ran == 6
    out = tmp_path / "killed"
    p = _cli(tmp_path, "--out", str(out), "--no-report")
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline:
            f = out / "results.jsonl"
            if f.exists() and len(f.read_text().splitlines()) >= 3:  # header + 2 missions
                break
            time.sleep(0.1)
        os.kill(p.pid, signal.SIGKILL)
    finally:
        p.wait(timeout=30)
    done = len(read_results(out / "results.jsonl")[1])
    assert 2 <= done < 6
    q = _cli(tmp_path, "--out", str(out), "--no-report")
    _, err = q.communicate(timeout=300)
    assert q.returncode == 0, err
    assert f"{6 - done} missions run now, {done} already on file, 6 in the study" in err
    assert (out / "results.jsonl").read_bytes() == (tmp_path / "straight" / "results.jsonl").read_bytes()


@pytest.mark.slow
def test_the_same_study_on_a_two_worker_dask_cluster_gives_identical_results(tmp_path: Path) -> None:
    distributed = pytest.importorskip("distributed")
    from fire_bench.sweep import DaskExecutor

    study = _study(tmp_path)
    whole = _straight(tmp_path, study)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, host="127.0.0.1"
    ) as cluster:
        ex = DaskExecutor(cluster.scheduler_address)
        try:
            log = io.StringIO()
            rep = run_study(study, tmp_path / "dask", ex, stream=log)
            workers = set(ex.workers())
        finally:
            ex.close()
    assert rep.ran == 4 and len(workers) == 2
    assert (tmp_path / "dask" / "results.jsonl").read_bytes() == whole
    ran_on = (tmp_path / "dask" / "missions.log").read_text()
    assert ran_on.count("tcp://127.0.0.1:") == 4
