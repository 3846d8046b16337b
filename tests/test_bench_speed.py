"""The speed benchmark's in-process row: start-up CPU and x real time after start-up, with a fake runner."""

import json
from pathlib import Path

import pytest
from fire_bench import speed
from fire_bench.markdown import write_markdown

# fake CPU model: start-up [s] per root, then CPU per second of mission
_STARTUP = {"base": 3.0, "head": 2.0}
_PER_S = {"base": 0.1, "head": 0.05}


def _fake_run(root: Path, argv: list[str], timeout_s: float) -> tuple[float, str]:
    """Writes the summary the mission would, and returns start-up + CPU per mission second."""
    tag = root.name
    js = Path(argv[argv.index("--json") + 1])
    mission = 90.0
    for i, a in enumerate(argv):
        if a == "--set" and argv[i + 1].startswith("timing.max_duration_s="):
            mission = min(mission, float(argv[i + 1].split("=")[1]))
    js.write_text(json.dumps({"uav_count": 5, "mission_time_s": mission, "outcome": "ok"}))
    return _STARTUP[tag] + _PER_S[tag] * mission, ""


def _write_summary(
    out: Path, t: float, wall: float, world_ms: float, agent_ms: float, series: list | None = None
) -> None:
    """A lockstep run's summary.json as the runner writes it: ``t`` s of mission at 10 steps/s of
    mission time in ``wall`` s, the world's and one agent's CPU ms per step, the agent's RSS; with
    ``series``, the runner's ``stepping_series`` (a failed run writes none)."""
    procs = {"world": {"cpu_ms_per_step": world_ms}, "agent_0": {"cpu_ms_per_step": agent_ms, "rss_mb": 80.0}}
    summary = {
        "mission_time_s": t,
        "control_period_s": 0.1,
        "steps_per_wall_s": t * 10 / wall,
        "processes": procs,
    }
    if series is not None:
        summary["stepping_series"] = series
    (out / "summary.json").write_text(json.dumps(summary))


def _series(t: float, rate_of, world_ms: float, agent_ms: float, t0_wall: float = 1000.0) -> list:
    """A runner's stepping_series of a fleet stepping at ``rate_of(step)`` steps per wall second up
    to ``t`` s of mission, sampled every wall second, CPU ``world_ms`` / ``agent_ms`` per step."""
    out, wall, steps, n = [], t0_wall, 0.0, round(t * 10)
    while steps < n:
        out.append([round(wall, 3), int(steps), world_ms * steps / 1000, agent_ms * steps / 1000])
        rate = rate_of(steps)
        wall += min(1.0, (n - steps) / rate)  # the last step comes before the next sample
        steps = min(float(n), steps + rate)
    out.append([round(wall, 3), n, world_ms * n / 1000, agent_ms * n / 1000])
    return out


def _page(tmp_path: Path, inprocess=(), world=(), dds=()) -> str:
    """The benchmark page's text rendered from a speed section holding these rows."""
    results = {
        "speed": {
            "command": "c",
            "inprocess": list(inprocess),
            "world": list(world),
            "dds": list(dds),
            "head_commit": "h",
            "base_commit": "b",
        }
    }
    md = tmp_path / "benchmarks.md"
    write_markdown(results, tmp_path, md)
    return md.read_text()


class _QueuedProbe:
    """``speed.CpuProbe`` without a child process: each probe opened takes the next of ``queue``
    as its samples (none once the queue is empty)."""

    queue: list[list[float]] = []

    def __init__(self) -> None:
        self.samples_ms: list[float] = []
        self.stamped: list[tuple[float, float]] = []

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.samples_ms = self.queue.pop(0) if self.queue else []
        self.stamped = [(float(i), ms) for i, ms in enumerate(self.samples_ms)]


@pytest.fixture
def fake(monkeypatch):
    calls = []

    def run(root, argv, timeout_s):
        calls.append((root.name, argv))
        return _fake_run(root, argv, timeout_s)

    monkeypatch.setattr(speed, "_run", run)
    _QueuedProbe.queue = []
    monkeypatch.setattr(speed, "CpuProbe", _QueuedProbe)
    return calls


@pytest.mark.parametrize("head_ms", [[38.0, 36.0, 37.0], [58.0, 61.0, 60.0]])
def test_an_inprocess_row_names_the_hosts_speed_of_its_least_cpu_run_and_flags_unlike_hosts(
    fake, tmp_path, capsys, head_ms
):
    """Session 27: the in-process rows had no probe, and their base/head pairs moved with the
    host's one-core speed (up to 1.7x within a minute). Each side's least-CPU run carries the
    probe's median during it; the start-up runs' probes are not the row's."""
    # run order per repeat: base mission, base start-up, head mission, head start-up (2 repeats);
    # the fake's CPU is the same every repeat, so the least is the first run (min keeps the first)
    _QueuedProbe.queue = [[37.0, 37.5], [99.0], head_ms, [99.0], [20.0], [99.0], [20.0], [99.0]]
    roots = {"base": Path("/x/base"), "head": Path("/x/head")}
    row = speed.inprocess_row(roots, "ff_two_fires", 5, None, repeats=2)
    flagged = head_ms[0] > 50.0
    assert row["base_probe_ms"] == 37.2  # the median of 37.0 and 37.5, rounded
    assert row["head_probe_ms"] == (37.0 if not flagged else 60.0)
    assert bool(row.get("not_comparable")) is flagged
    assert ("ff_two_fires: the host's one-core speed differed" in capsys.readouterr().err) is flagged
    text = _page(tmp_path, inprocess=[row])
    assert "probe ms b" in text and "probe ms h" in text
    assert ("Not comparable side by side:\n\n- ff_two_fires: the host's" in text) is flagged


def test_the_world_row_names_the_hosts_speed_and_flags_unlike_hosts(monkeypatch, tmp_path):
    def run(root, argv, timeout_s):
        ms = {"b": 1.25, "h": 1.30}[Path(root).name]
        return 1.0, "noise\n" + json.dumps({"world_ms_per_step": ms, "truth_digest": "d"}) + "\n"

    monkeypatch.setattr(speed, "_run", run)
    monkeypatch.setattr(speed, "CpuProbe", _QueuedProbe)
    _QueuedProbe.queue = [[36.0], [52.0]]
    row = speed.world_row({"base": tmp_path / "b", "head": tmp_path / "h"}, 20, 100)
    assert (row["base_world_ms_per_step"], row["head_world_ms_per_step"], row["truth_same"]) == (
        1.25,
        1.3,
        True,
    )
    assert (row["base_probe_ms"], row["head_probe_ms"]) == (36.0, 52.0)
    (note,) = row["not_comparable"]
    assert "36 / 52 ms" in note and "44 %" in note
    text = _page(tmp_path, world=[row])
    assert "Not comparable side by side:\n\n- 20 UAVs: the host's one-core speed differed" in text


def test_after_startup_arithmetic():
    assert speed.after_startup(91.0, 11.0, 1.0, 2.0) == 10.0  # 90 s flown after start-up in 9 s
    assert speed.after_startup(1.0, 3.0, 1.0, 2.0) is None  # nothing flown after the start-up run
    assert speed.after_startup(90.0, 2.0, 1.0, 2.0) is None  # no CPU left: refuse, do not divide
    assert speed.after_startup(None, 2.0, 1.0, 2.0) is None


def test_the_row_keeps_its_columns_and_adds_the_startup_ones(fake):
    roots = {"base": Path("/x/base"), "head": Path("/x/head")}
    row = speed.inprocess_row(roots, "ff_two_fires", 5, None, repeats=2)
    # the existing columns, as before: whole CPU over the whole mission
    assert row["base_cpu_s"] == 12.0 and row["head_cpu_s"] == 6.5
    assert row["base_x_real_time"] == round(90 / 12.0, 1) and row["head_x_real_time"] == round(90 / 6.5, 1)
    assert row["summary_same"] is True
    # the start-up run: the same command at 1 s of mission
    assert row["base_startup_cpu_s"] == 3.1 and row["head_startup_cpu_s"] == 2.05
    # after start-up: 89 s of mission for 8.9 s (base) and 4.45 s (head) of CPU: the fake's 1 / per-s
    assert row["base_x_real_time_after_startup"] == 10.0
    assert row["head_x_real_time_after_startup"] == 20.0
    # each repeat runs base then head, each the mission then its start-up run
    assert [c[0] for c in fake] == ["base", "base", "head", "head"] * 2
    startup = [c[1] for c in fake if "timing.max_duration_s=1" in c[1]]
    assert len(startup) == 4 and all("ff_two_fires" in a and "5" in a for a in startup)


def test_the_page_shows_the_startup_columns(fake, tmp_path):
    roots = {"base": Path("/x/base"), "head": Path("/x/head")}
    row = speed.inprocess_row(roots, "ff_two_fires", 5, None, repeats=1)
    text = _page(tmp_path, inprocess=[row])
    head = next(x for x in text.splitlines() if x.startswith("| scenario"))
    cols = [c.strip() for c in head.strip("|").split("|")]
    assert "x real time b" in cols and "start-up CPU s h" in cols and "x real time after start-up h" in cols
    line = next(x for x in text.splitlines() if x.startswith("| ff_two_fires"))
    cells = dict(zip(cols, (c.strip() for c in line.strip("|").split("|")), strict=True))
    assert float(cells["x real time after start-up h"]) == 20.0


def test_the_dds_row_flies_the_vehicle_model_it_names_over_an_airborne_window(monkeypatch, tmp_path):
    """issue [airframe]'s figure (20 UAVs on JSBSim over DDS): the jsbsim row must really set the
    world's backend and the ff_paper rows must not; the rate is the one between the end of the
    takeoff column and the end of the window, within one run, not an average with the fleet on
    the ground; the run is flown by this checkout's runner (harness) over the side's workspace."""
    seen = []

    def run(root, argv, timeout_s, harness=None):
        seen.append((argv, harness))
        out = Path(argv[argv.index("--out") + 1])
        model = next((a.split("=")[1] for a in argv if a.startswith("uavs.vehicle_model=")), "ff_paper")
        t = float(argv[argv.index("--max-duration") + 1])
        # fake fleet: 20 steps/s while the column takes off (t < 43 s), then 8 (ff_paper) or 5 (jsbsim)
        airborne_rate = 5.0 if model == "jsbsim" else 8.0
        wall = min(t, 43.0) * 10 / 20.0 + max(t - 43.0, 0.0) * 10 / airborne_rate
        series = _series(t, lambda n: 20.0 if n < 430 else airborne_rate, 2.0, 4.0)
        _write_summary(out, t, wall, 2.0, 4.0, series)
        return 1.0, ""

    monkeypatch.setattr(speed, "_run", run)
    roots = {"head": tmp_path}
    assert (
        speed.airborne_after_s(20) == 19 * 2.0 + speed.AIRBORNE_MARGIN_S
    )  # ff_two_fires: one takeoff per 2 s
    plain = speed.dds_row(roots, 20, 15.0)
    jsb = speed.dds_row(roots, 20, 15.0, "jsbsim")
    assert len(seen) == 2  # one run each
    assert "--set" not in seen[0][0]
    assert seen[1][0][seen[1][0].index("--set") + 1] == "uavs.vehicle_model=jsbsim"
    assert [float(a[a.index("--max-duration") + 1]) for a, _ in seen] == [58.0, 58.0]
    assert all(h == speed.ROOT for _, h in seen)
    assert (plain["vehicle_model"], plain["head_steps_per_s"]) == ("ff_paper", 8.0)
    assert (jsb["vehicle_model"], jsb["head_steps_per_s"], jsb["head_agent_rss_mb"]) == ("jsbsim", 5.0, 80.0)
    assert (jsb["head_world_cpu_ms_per_step"], jsb["head_agent_cpu_ms_per_step"]) == (2.0, 4.0)
    assert "two_runs" not in plain


def test_the_window_is_measured_within_one_run_not_as_two_runs_difference(monkeypatch, tmp_path):
    """Session 27: at 30 UAVs the same commits gave 3.8 to 16.9 steps/s over one 15 s window, the
    difference of two runs (to 63 s and to 78 s), while within each run the rate stayed at 10-17.
    Two runs of one fleet, one at 14 steps/s overall and the other at 11 (within 8 steps/s of
    each other through the window), differ by 630 / 14 - 780 / 11 s: the window would read 5.8
    steps/s. Within one run it reads what the run flew in it."""

    def run(root, argv, timeout_s, harness=None):
        out = Path(argv[argv.index("--out") + 1])
        t = float(argv[argv.index("--max-duration") + 1])
        rate = 14.0 if t < 70 else 11.0  # the two-run way would see two different runs
        _write_summary(out, t, t * 10 / rate, 5.0, 4.0, _series(t, lambda n: rate, 5.0, 4.0))
        return 1.0, ""

    monkeypatch.setattr(speed, "_run", run)
    row = speed.dds_row({"head": tmp_path}, 30, 15.0)
    assert row["head_steps_per_s"] == 11.0
    assert (row["head_world_cpu_ms_per_step"], row["head_agent_cpu_ms_per_step"]) == (5.0, 4.0)


def test_a_failed_run_is_reported_with_its_command_not_flown_again(monkeypatch, tmp_path, capsys):
    """This checkout's runner always writes stepping.json (every DDS run is flown by it), so a run
    without one failed or ran past its time limit. The row leaves the side's figures empty, says
    so with the command that reproduces the run, flies no second run to stand in for it, and the
    page lists it under the table."""
    (tmp_path / "b").mkdir()
    (tmp_path / "h").mkdir()
    calls = []

    def run(root, argv, timeout_s, harness=None):
        calls.append(Path(root).name)
        out = Path(argv[argv.index("--out") + 1])
        t = float(argv[argv.index("--max-duration") + 1])
        if Path(root).name == "h":  # the head's run wrote its summary and series; the base's nothing
            _write_summary(out, t, t, 2.0, 4.0, _series(t, lambda n: 10.0, 2.0, 4.0))
        return 1.0, ""

    monkeypatch.setattr(speed, "_run", run)
    row = speed.dds_row({"base": tmp_path / "b", "head": tmp_path / "h"}, 20, 15.0)
    assert calls == ["b", "h"]
    assert row["base_steps_per_s"] is None and row["base_world_cpu_ms_per_step"] is None
    assert row["head_steps_per_s"] == 10.0
    (note,) = row["not_measured"]
    assert note.startswith("base steps/s: the run wrote no stepping.json")
    assert "fire_mission.runner ff_two_fires --uavs 20 --seed 1 --max-duration 58" in note
    assert str(tmp_path / "b") in note
    assert "not a measure" in capsys.readouterr().err
    text = _page(tmp_path, dds=[row])
    assert "Not measured (empty cells above):\n\n- 20 UAVs, ff_paper: base steps/s: the run wrote no" in text
    assert "Not comparable side by side:" not in text


def test_cpu_that_is_not_positive_over_the_window_is_flagged_not_printed(monkeypatch, tmp_path, capsys):
    """Session 25: under load the base's world CPU at 20 J3Cubs came out as -2.84 ms/step. Such a
    figure is not a measure: here a world whose CPU samples stand still through the window (a
    process sample that failed to move), the agents' 4 ms a step. The row keeps the world's
    cell empty and says why, the page lists it under the table, and the run warns on stderr."""

    def run(root, argv, timeout_s, harness=None):
        out = Path(argv[argv.index("--out") + 1])
        t = float(argv[argv.index("--max-duration") + 1])
        series = _series(t, lambda n: 10.0, 0.0, 4.0)
        series = [[w, k, 3.0, a] for w, k, _, a in series]  # the world's CPU stands at 3 s
        _write_summary(out, t, t, 2.0, 4.0, series)
        return 1.0, ""

    monkeypatch.setattr(speed, "_run", run)
    row = speed.dds_row({"base": tmp_path}, 20, 15.0, "jsbsim")
    assert row["base_steps_per_s"] == 10.0
    assert row["base_agent_cpu_ms_per_step"] == 4.0
    assert row["base_world_cpu_ms_per_step"] is None
    assert len(row["not_measured"]) == 1 and "base world CPU ms/step" in row["not_measured"][0]
    assert "0.000 ms of CPU over 150 steps, not positive" in row["not_measured"][0]
    assert "not a measure" in capsys.readouterr().err
    text = _page(tmp_path, dds=[row])
    assert "Not measured (empty cells above):" in text and "20 UAVs, jsbsim: base world CPU ms/step" in text


class _FakeProbe:
    """``speed.CpuProbe`` with set samples per root (no child process): outside the window (the
    take-off column, wall 1010-1020 s) a host four times slower, which the row must leave out."""

    samples_by_root: dict[str, list[float]] = {}
    current: list[str] = []

    def __init__(self) -> None:
        self.stamped: list[tuple[float, float]] = []

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        inside = self.samples_by_root[self.current[-1]]
        self.stamped = [(1010.0, 150.0), (1020.0, 150.0)]
        self.stamped += [(1065.0 + 5.0 * i, ms) for i, ms in enumerate(inside)]


@pytest.mark.parametrize(
    ("base_ms", "head_ms", "flagged"),
    [([37.0, 38.0, 36.0], [37.5, 36.5, 38.5], False), ([37.0, 38.0, 36.0], [61.0, 64.0, 52.0], True)],
)
def test_a_dds_row_names_the_hosts_speed_in_its_window_and_flags_unlike_windows(
    monkeypatch, tmp_path, capsys, base_ms, head_ms, flagged
):
    """Session 27: a fixed loop's CPU time on this host moved 1.7x from one ten-second sample to the
    next, idle. A row says how fast the host ran under each side in the window (the probe's
    median over the samples taken between the window's first and last sample of the run) and is
    flagged when the two differ by more than PROBE_TOLERANCE."""
    (tmp_path / "b").mkdir()
    (tmp_path / "h").mkdir()
    _FakeProbe.samples_by_root = {"b": base_ms, "h": head_ms}

    def run(root, argv, timeout_s, harness=None):
        _FakeProbe.current.append(Path(root).name)
        out = Path(argv[argv.index("--out") + 1])
        t = float(argv[argv.index("--max-duration") + 1])
        _write_summary(out, t, t, 2.0, 4.0, _series(t, lambda n: 10.0, 2.0, 4.0))
        return 1.0, ""

    monkeypatch.setattr(speed, "_run", run)
    monkeypatch.setattr(speed, "CpuProbe", _FakeProbe)
    row = speed.dds_row({"base": tmp_path / "b", "head": tmp_path / "h"}, 30, 15.0)
    assert row["base_probe_ms"] == 37.0
    assert row["head_probe_ms"] == (37.5 if not flagged else 61.0)
    assert bool(row.get("not_comparable")) is flagged
    text = _page(tmp_path, dds=[row])
    assert "probe ms b" in text and "probe ms h" in text
    assert ("Not comparable side by side:" in text) is flagged
    assert ("host's one-core speed differed" in capsys.readouterr().err) is flagged


def test_the_cpu_probe_samples_a_fixed_loop_while_it_is_open():
    """The real probe: a child that reports the loop's CPU ms about once a second (at least one
    sample over 1.5 s), each a positive figure of tens of ms, and nothing left running."""
    import time

    with speed.CpuProbe() as p:
        time.sleep(1.5)
        child = p._p
    assert child is not None and child.poll() is not None
    assert 1 <= len(p.samples_ms) <= 3
    assert all(1.0 < ms < 1000.0 for ms in p.samples_ms)
    assert [ms for _, ms in p.stamped] == p.samples_ms
    assert all(0.0 < b - a < 3.0 for (a, _), (b, _) in zip(p.stamped, p.stamped[1:], strict=False))
