"""Sweeps of ``scripts/bench`` locally and on a Dask cluster (sweeps beyond one machine).

The fast tests check the sweep machinery's contracts: spec errors, the host-wide ROS domain
claim, results in sorted-spec order whatever the completion order, the one-line errors for an
unreachable scheduler and a missing dask. The slow test starts a two-worker
``distributed.LocalCluster`` (separate worker processes) and runs the same small sweep of
harness missions locally and on the cluster: the two ``results.json`` must be identical but
for the fields that describe the run rather than the missions (``machine``, the benchmark's
``wall_s``, ``executor`` and its own ``machine``). The system test runs real-process missions on the cluster, each on
its own claimed ROS domain.
"""

from __future__ import annotations

import json
import socket
import sys
from pathlib import Path

import pytest
from fire_bench import bench
from fire_bench.sweep import (
    DaskExecutor,
    LocalExecutor,
    MissionSpec,
    Sweep,
    SweepError,
    run_sweep,
)
from fire_mission.determinism import VOLATILE_KEYS
from fire_mission.procs import DOMAIN_RANGE

#: fields of a results.json section that describe the run, not the missions (a section's
#: ``machine`` carries the minute it ran: two runs across a minute boundary differ there)
RUN_FIELDS = ("wall_s", "executor", "machine")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


# --- fast ---------------------------------------------------------------------------------------
def test_spec_rejects_bad_fields() -> None:
    with pytest.raises(SweepError, match="mode must be one of harness, processes, call, got 'fleet'"):
        MissionSpec("b", "tiny_test", mode="fleet")
    with pytest.raises(SweepError, match="call='module:function'"):
        MissionSpec("b", "tiny_test", mode="call", call="nomodule")
    with pytest.raises(SweepError, match=r"args \['--kill', '1@30'\] only apply to mode 'processes'"):
        MissionSpec("b", "tiny_test", args=("--kill", "1@30"))
    with pytest.raises(SweepError, match="uavs must be >= 0, got -1"):
        MissionSpec("b", "tiny_test", uavs=-1)


def _echo_sweep(seeds: list[int]) -> Sweep:
    # builtins:dict(**kwargs) as the mission: a result that names its own spec
    specs = [
        MissionSpec("echo", "none", seed=s, mode="call", call="builtins:dict", kwargs=(("seed", s),))
        for s in seeds
    ]
    return Sweep(specs, lambda pairs: {"order": [(s.seed, r["seed"]) for s, r in pairs]})


@pytest.mark.parametrize("jobs", [1, 3])
def test_results_come_in_spec_order(jobs: int) -> None:
    seeds = [5, 1, 9, 3, 7, 2]
    out = run_sweep(_echo_sweep(seeds), LocalExecutor(jobs), progress=None)
    # sorted by spec (JSON of the fields: seeds here), each result its own spec's
    assert out["order"] == [(s, s) for s in sorted(seeds)]


def test_same_mission_twice_is_an_error() -> None:
    with pytest.raises(SweepError, match="same mission twice: echo none seed=1 call"):
        run_sweep(_echo_sweep([1, 2, 1]), LocalExecutor(1), progress=None)


def test_progress_line_per_mission(capsys: pytest.CaptureFixture[str]) -> None:
    from fire_bench.sweep import _log_progress

    run_sweep(_echo_sweep([1, 2, 3]), LocalExecutor(1), progress=_log_progress)
    lines = [x for x in capsys.readouterr().err.splitlines() if x.startswith("[bench] ")]
    assert [x.split()[1] for x in lines] == ["1/3", "2/3", "3/3"]
    assert all(" s wall on " in x and socket.gethostname() in x for x in lines), lines


@pytest.mark.timeout(60)
def test_unreachable_scheduler_is_one_line_naming_it(capsys: pytest.CaptureFixture[str]) -> None:
    addr = f"tcp://127.0.0.1:{_free_port()}"
    with pytest.raises(SweepError, match=f"cannot reach the Dask scheduler at {addr} within 2 s") as e:
        DaskExecutor(addr, connect_timeout_s=2.0)
    assert "\n" not in str(e.value)
    assert bench.main(["--only", "table1", "--scheduler", addr, "--no-page"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith(f"bench: error: cannot reach the Dask scheduler at {addr}"), err


@pytest.mark.parametrize("addr", ["nonsense", "127.0.0.1:8786", "tcp://127.0.0.1", "udp://127.0.0.1:8786"])
def test_scheduler_address_must_be_tcp_host_port(addr: str) -> None:
    with pytest.raises(SweepError, match=f"--scheduler expects tcp://HOST:PORT, got '{addr}'"):
        DaskExecutor(addr)


def test_missing_dask_is_named(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed -> ImportError
    with pytest.raises(
        SweepError, match="needs Dask distributed, which is not installed.*dask==.*distributed=="
    ):
        DaskExecutor("tcp://127.0.0.1:8786")


def test_bench_rejects_jobs_with_scheduler(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        bench.main(["--scheduler", "tcp://127.0.0.1:1", "--jobs", "2"])
    assert "--jobs applies to local runs only" in capsys.readouterr().err


# --- a small sweep, locally and on a two-worker cluster ------------------------------------------
def _summaries(pairs: list[tuple[MissionSpec, dict]]) -> dict:
    """Every mission's whole summary but the machine-dependent fields (wall time, processes)."""
    return {
        "missions": [
            {"spec": s.describe(), **{k: v for k, v in r.items() if k not in VOLATILE_KEYS}} for s, r in pairs
        ]
    }


def _tiny(quick: bool) -> Sweep:
    """ff_two_fires, 2 and 3 UAVs x seeds 1, 2, 20 s of mission time, in the harness."""
    short = (("timing.max_duration_s", 20.0),)
    specs = [
        MissionSpec("tiny", "ff_two_fires", uavs=n, seed=s, overrides=short) for s in (2, 1) for n in (3, 2)
    ]
    return Sweep(specs, _summaries)


def _tiny_processes(quick: bool) -> Sweep:
    """tiny_test, 2 UAVs, seeds 1 and 2, real processes (about 55 s of mission time each)."""
    specs = [MissionSpec("tiny_proc", "tiny_test", uavs=2, seed=s, mode="processes") for s in (1, 2)]
    return Sweep(specs, lambda pairs: {"missions": [r for _, r in pairs]})


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, host="127.0.0.1"
    ) as c:
        yield c


def _bench_json(monkeypatch: pytest.MonkeyPatch, out: Path, name: str, fn, *extra: str) -> dict:
    monkeypatch.setitem(bench.BENCHES, name, (fn, 0.2, 0.2, "test sweep"))
    assert bench.main(["--only", name, "--out", str(out), "--no-page", *extra]) == 0
    return json.loads((out / "results.json").read_text())


@pytest.mark.slow
def test_same_results_locally_and_on_two_workers(
    cluster, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    local = _bench_json(monkeypatch, tmp_path / "local", "tiny", _tiny)
    capsys.readouterr()
    remote = _bench_json(
        monkeypatch, tmp_path / "dask", "tiny", _tiny, "--scheduler", cluster.scheduler_address
    )
    err = capsys.readouterr().err
    assert local["tiny"]["executor"] == "local"
    assert remote["tiny"]["executor"] == f"dask {cluster.scheduler_address}"
    # the recorded command says how the section was run (the scheduler is part of it)
    assert local["tiny"]["command"] == "scripts/bench --only tiny"
    assert remote["tiny"]["command"] == f"scripts/bench --only tiny --scheduler {cluster.scheduler_address}"
    for r in (local, remote):
        r.pop("machine")
        for k in (*RUN_FIELDS, "command"):
            r["tiny"].pop(k)
    assert remote == local
    missions = local["tiny"]["missions"]
    assert [(m["uav_count"], m["seed"]) for m in missions] == [
        (2, 1),
        (2, 2),
        (3, 1),
        (3, 2),
    ]  # sorted by spec
    assert all(m["mission_time_s"] == pytest.approx(20.0) for m in missions)
    assert len({json.dumps(m, sort_keys=True) for m in missions}) == 4  # not one mission four times
    # one progress line per mission, naming the worker that ran it
    done = [x for x in err.splitlines() if x.startswith("[bench] ") and " s wall on tcp://127.0.0.1:" in x]
    assert sorted(x.split()[1] for x in done) == ["1/4", "2/4", "3/4", "4/4"]


@pytest.mark.system
@pytest.mark.slow
def test_process_missions_on_the_cluster_get_their_own_domains(
    cluster, ros_env: dict[str, str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    out = _bench_json(
        monkeypatch, tmp_path / "dask", "tiny_proc", _tiny_processes, "--scheduler", cluster.scheduler_address
    )
    missions = out["tiny_proc"]["missions"]
    assert [m["outcome"] for m in missions] == ["complete", "complete"], missions
    domains = [m["domain_id"] for m in missions]
    assert all(d in DOMAIN_RANGE for d in domains), domains
    assert [m["seed"] for m in missions] == [1, 2]
    assert all(m["drops_total"] >= 2 and m["fires_active_at_end"] == 0 for m in missions), missions


# --- the benchmarks' own sweeps ------------------------------------------------------------------
#: the sub-benchmarks declared to return a Sweep (annotation ``-> Sweep``)
SWEEP_BENCHES = [
    n for n, (fn, *_) in bench.BENCHES.items() if fn.__annotations__.get("return") in ("Sweep", Sweep)
]


@pytest.mark.parametrize("quick", [True, False])
@pytest.mark.parametrize("name", SWEEP_BENCHES)
def test_bench_sweeps_are_well_formed(name: str, quick: bool) -> None:
    """Each sweep's derived scenarios load, it has no mission twice, and its reducer survives
    missions that all failed (a broken runner must not lose the rest of a 3-hour run)."""
    import yaml
    from fire_uav_common.scenario import scenario_from_dict

    sw = bench.BENCHES[name][0](quick)
    assert isinstance(sw, Sweep)
    for s in sw.specs:
        if s.scenario_yaml is not None:
            sc = scenario_from_dict(yaml.safe_load(s.scenario_yaml), file=s.scenario)
            assert sc.name == s.scenario
    failed = Sweep(
        [
            MissionSpec(
                s.bench,
                s.scenario,
                s.uavs,
                s.seed,
                s.overrides,
                "call",
                (),
                s.label,
                s.scenario_yaml,
                "builtins:dict",
                (("outcome", "runner_failed"),),
            )
            for s in sw.specs
        ],
        sw.reduce,
    )
    out = run_sweep(failed, LocalExecutor(1), progress=None)
    rows = out.get("rows", [])
    assert rows, out
    assert all(
        r.get("completed") in (0, "0/1", "0/3") or r.get("outcome") == "runner_failed" for r in rows
    ), rows
