"""The debrief half of the report on small in-memory missions worked out by hand (fast): the
timeline and the faults with what the fleet did, the safety figures, the per-fire and per-UAV
rows, the page's wording, and the numbers it shares with the runner's console summary."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
from fire_mission.summary import LiveSummary
from fire_report.data import RecordedEvent, RecordedMission
from fire_report.debrief import (
    Fault,
    fire_rows,
    flare_ups,
    parse_fault_texts,
    run_faults,
    scenario_outages,
    timeline,
    uav_rows,
    with_responses,
)
from fire_report.metrics import compute_metrics, settled_index
from fire_report.page import fmt, render_page, summary_cards
from fire_report.report import place_figures
from fire_uav_common.constants import EventType, FireStatus

NAN = math.nan
SCENARIO = {
    "name": "two_fires",
    "area": {"x_min_m": 0, "x_max_m": 1000, "y_min_m": 0, "y_max_m": 1000},
    "uavs": {"first": {"x_m": 100.0, "y_m": 200.0}, "spacing": {"dx_m": 0.0, "dy_m": 30.0}},
    "fires": {"model": "analytic"},
}


def _ev(
    t, type_, uav=-1, peer=-1, fire=-1, value=0.0, detail="", x=NAN, y=NAN, source="world"
) -> RecordedEvent:
    return RecordedEvent(t, type_, uav, peer, fire, x, y, value, detail, source)


def _fire(x: float, y: float, out_at: float | None, t_end: float = 60.0) -> dict[str, np.ndarray]:
    t = np.arange(0.0, t_end + 0.05, 0.5)
    n = t.size
    status = np.full(n, int(FireStatus.ACTIVE))
    if out_at is not None:
        status[t >= out_at] = FireStatus.EXTINGUISHED
    return {"t": t, "x": np.full(n, x), "y": np.full(n, y), "extent": np.full(n, 20.0),
            "area": np.full(n, 1256.0), "status": status, "drops": np.zeros(n, int)}  # fmt: skip


def _mission(world: list[RecordedEvent], fleet: list[RecordedEvent], **kw) -> RecordedMission:
    m = RecordedMission(path="mem", custom_data={"fire_uav.uav_count": "4", "fire_uav.seed": "1"},
                scenario=kw.pop("scenario", SCENARIO), warnings=[], topics={})  # fmt: skip
    m.world_events = sorted(world, key=lambda e: e.t_s)
    m.fleet_events = sorted(fleet, key=lambda e: e.t_s)
    for k, v in kw.items():
        setattr(m, k, v)
    return m


def kill_and_outage() -> tuple[RecordedMission, list[Fault]]:
    """4 UAVs, two fires; UAV 2 killed at 20 s (falls at 23 s); link 0 -> 1 cut 10-30 s."""
    W, F = EventType, "fleet"
    world = [
        _ev(0.0, W.TAKEOFF, uav=0), _ev(2.0, W.TAKEOFF, uav=1), _ev(4.0, W.TAKEOFF, uav=2), _ev(6.0, W.TAKEOFF, uav=3),
        _ev(12.0, W.DROP, uav=0, fire=1, value=100.0, x=600, y=600),
        _ev(13.0, W.EXTINGUISHED, fire=1),
        _ev(15.0, W.DROP, uav=3, fire=-1, value=100.0, x=10, y=10),
        _ev(18.0, W.DROP, uav=1, fire=0, value=100.0, x=300, y=300),
        _ev(23.0, W.CRASH, uav=2, detail="no valid command for 3.0 s", x=500, y=500),
        _ev(33.0, W.DROP, uav=0, fire=0, value=100.0, x=300, y=300),
        _ev(35.0, W.EXTINGUISHED, fire=0),
        _ev(50.0, W.LANDED, uav=0, x=101.0, y=200.0),
        _ev(51.0, W.LANDED, uav=1, x=100.0, y=233.0),
        _ev(52.0, W.LANDED, uav=3, x=100.0, y=290.0),
        _ev(52.0, W.MISSION_COMPLETE, value=1.0, detail="all fires out and every surviving vehicle landed"),
    ]  # fmt: skip
    fleet = [
        _ev(8.0, W.FIRE_DETECTED, uav=1, fire=65536, x=305, y=298, source=F),
        _ev(9.0, W.FIRE_DETECTED, uav=3, fire=196608, x=598, y=603, source=F),
        _ev(11.0, W.PEER_CRASHED, uav=1, peer=0, source=F),
        _ev(22.1, W.PEER_CRASHED, uav=0, peer=2, source=F),
        _ev(22.2, W.PEER_CRASHED, uav=3, peer=2, source=F),
        _ev(22.3, W.PEER_CRASHED, uav=1, peer=2, source=F),
        _ev(30.1, W.PEER_REJOINED, uav=1, peer=0, source=F),
    ]
    m = _mission(world, fleet, truth_fires={0: _fire(300.0, 300.0, 35.0), 1: _fire(600.0, 600.0, 13.0)})
    faults = [Fault("kill", 20.0, 2), Fault("outage", 10.0, 0, 1, 30.0)]
    return m, with_responses(faults, m)


def test_timeline_tells_the_mission_in_time_order_with_the_kill_and_the_outage():
    m, faults = kill_and_outage()
    metrics = compute_metrics(m)
    entries = timeline(m, metrics, faults)
    assert [e.t_s for e in entries] == sorted(e.t_s for e in entries)
    texts = [e.text for e in entries]
    expected = [
        "Fires 0, 1 are burning when the mission starts.",
        "UAV 0 takes off, the first of 4.",
        "UAV 1 detects fire 0.",
        "UAV 3 detects fire 1.",
        "Link from UAV 0 to UAV 1 cut (injected outage).",
        "UAV 1 declares UAV 0 lost (not heard for 10 control steps).",
        "UAV 0 drops 100 kg of water on fire 1.",
        "Fire 1 is out, after 1 drop.",
        "UAV 3 drops 100 kg of water and misses every fire.",
        "UAV 2's process killed (injected fault).",
        "UAVs 0, 1, 3 declare UAV 2 lost (not heard for 10 control steps).",
        "UAV 2 is lost (injected fault): no valid command for 3.0 s.",
        "Link from UAV 0 to UAV 1 restored.",
        "UAV 1 hears UAV 0 again.",
        "Fire 0 is out, after 2 drops.",
        "UAV 0 lands, 1.0 m from its takeoff point.",
        "UAV 1 lands, 3.0 m from its takeoff point.",
        "Mission complete: all fires out and every surviving vehicle landed.",
    ]
    positions = [texts.index(x) for x in expected]  # each is there ...
    assert positions == sorted(positions)  # ... in this order


def test_each_fault_says_what_the_fleet_did_and_when():
    _, faults = kill_and_outage()
    outage, kill = faults  # by time
    assert outage.kind == "outage" and kill.kind == "kill"
    assert (
        "UAV 1 stopped hearing UAV 0 and declared it lost at 11.0 s (1.0 s into the outage)"
        in outage.response
    )
    assert "heard it again at 30.1 s" in outage.response
    assert "its vehicle fell at 23.0 s (no valid command for 3.0 s)" in kill.response
    assert (
        "UAVs 0, 1, 3 declared it lost between 22.1 and 22.3 s (first 2.1 s after the fault)" in kill.response
    )
    assert outage.title == "Link outage UAV 0 \u2192 UAV 1, 10\u201330 s"


def test_a_crash_that_was_not_injected_is_named_so():
    m, _ = kill_and_outage()
    entries = timeline(m, compute_metrics(m), [])
    assert "UAV 2 is lost (not injected): no valid command for 3.0 s." in [e.text for e in entries]
    rows = uav_rows(m, compute_metrics(m), [])
    assert rows[2]["end"] == "lost at 23.0 s (not injected)"
    # a bag read outside its run directory: the command line's faults are not known
    unknown = [e.text for e in timeline(m, compute_metrics(m), [], known=False) if e.kind == "loss"]
    assert unknown == [
        "UAV 2 is lost (injected or not: unknown without the run's summary): no valid command for 3.0 s."
    ]
    assert uav_rows(m, compute_metrics(m), [], known=False)[2]["end"].endswith(
        "(injected or not: unknown without the run's summary)"
    )


def test_safety_metrics_landing_error_from_the_scenarios_start_poses():
    m, _ = kill_and_outage()
    m.separation = {"t": np.array([1.0, 2.0, 3.0]), "min_separation_m": np.array([np.inf, 40.0, 19.2]),
                    "collisions": np.array([0, 0, 0])}  # fmt: skip
    s = compute_metrics(m)
    # homes: (100, 200), (100, 230), (100, 260), (100, 290)
    assert s["landing_error_m"] == pytest.approx({"0": 1.0, "1": 3.0, "3": 0.0})
    assert s["landed"] == [0, 1, 3] and s["min_separation_m"] == 19.2 and s["collisions"] == 0
    assert s["touchdown_spacing_m"] == pytest.approx(math.hypot(1.0, 33.0))
    assert s["fires_total"] == 2 and s["fires_active_at_end"] == 0


def test_fire_and_uav_rows():
    m, faults = kill_and_outage()
    metrics = compute_metrics(m)
    f0, f1 = fire_rows(m, metrics, raster=False)
    assert (f0["detected_s"], f0["detected_by"], f0["drops"], f0["first_drop_s"], f0["out_s"]) == (
        8.0,
        1,
        2,
        18.0,
        35.0,
    )
    assert (f1["detected_s"], f1["detected_by"], f1["drops"], f1["out_s"]) == (9.0, 3, 1, 13.0)
    assert "burned_ha" not in f0  # an analytic fire has no burned area to speak of
    rows = {r["uav"]: r for r in uav_rows(m, metrics, faults)}
    assert rows[2]["end"] == "lost at 23.0 s (injected)" and rows[0]["end"] == "landed at 50.0 s"
    assert rows[0]["drops"] == 2 and rows[0]["water_kg"] == 200.0 and rows[0]["takeoff_s"] == 0.0
    assert rows[1]["landing_error_m"] == pytest.approx(3.0)


def test_fault_texts_of_the_runner_and_the_run_directory(tmp_path):
    texts = [
        "kill uav 2 at 20 s (offline from step 200)",
        "freeze uav 1 at 5 s (offline steps 50-64)",
        "resume uav 1 at 6.5 s",
        "stall uav 3 at 7 s for 800 ms wall",
        "kill uav 4 at 30 s (offline from step 300): not applied, agent not running",
    ]
    got = parse_fault_texts(texts)
    assert got == [Fault("kill", 20.0, 2), Fault("freeze", 5.0, 1, end_s=6.5), Fault("stall", 7.0, 3)]
    run = tmp_path / "run"
    (run / "params").mkdir(parents=True)
    (run / "summary.json").write_text(json.dumps({"faults_injected": texts[:1]}))
    (run / "params" / "agent_0.yaml").write_text(
        "/**:\n  ros__parameters:\n    outage_from: [0, 3]\n    outage_to: [1, 2]\n"
        "    outage_start_s: [10.0, 40.0]\n    outage_end_s: [30.0, 45.5]\n"
    )
    assert run_faults(run / "bag") == [
        Fault("kill", 20.0, 2),
        Fault("outage", 10.0, 0, 1, 30.0),
        Fault("outage", 40.0, 3, 2, 45.5),
    ]
    assert run_faults(tmp_path / "elsewhere" / "bag") == []  # a bag outside a run directory
    # a run with the runner's records reads them, not the texts (which here say something else)
    records = [
        {"kind": "freeze", "uav_id": 1, "t_s": 5.0, "applied": True},
        {"kind": "resume", "uav_id": 1, "t_s": 6.5, "applied": True},
        {"kind": "stall", "uav_id": 3, "t_s": 7.0, "applied": True, "wall_ms": 800.0},
        {"kind": "kill", "uav_id": 4, "t_s": 30.0, "applied": False},
        {"kind": "outage", "from": 0, "to": 1, "start_s": 10.0, "end_s": 30.0},
        {"kind": "kill"},  # another version's record: skipped
    ]
    (run / "summary.json").write_text(json.dumps({"faults_injected": texts[:1], "faults": records}))
    assert run_faults(run / "bag") == [
        Fault("freeze", 5.0, 1, end_s=6.5),
        Fault("stall", 7.0, 3),
        Fault("outage", 10.0, 0, 1, 30.0),
        Fault("outage", 40.0, 3, 2, 45.5),
    ]
    # the loss rate: the runner's --loss from the agents' parameters, else the scenario's
    from fire_report.report import loss_probability

    m = _mission([], [], states={0: {}})
    m.path = str(run / "bag")
    assert loss_probability(m) == 0.05  # not given on the command line: the scenario's default
    with (run / "params" / "agent_0.yaml").open("a") as f:
        f.write("    loss_probability: 0.2\n")
    assert loss_probability(m) == 0.2
    sc = {"comms": {"outages": [{"from": 1, "to": 0, "start_s": 2, "end_s": 3}]}}
    assert scenario_outages(sc) == [Fault("outage", 2.0, 1, 0, 3.0, "scenario")]


def test_packet_counts_leave_out_the_answers_to_the_last_step_as_the_console_does():
    """The world ends the mission at 8.6 s; the agents' states answering that step reach the bag
    but not always the supervisor: both count each UAV's newest state before it."""
    t = np.array([8.4, 8.5, 8.6])
    assert settled_index(t, 8.6) == 1 and settled_index(t, 9.0) == 2 and settled_index(t[2:], 8.6) == 0
    states = {
        u: {"t": t, "step": np.array([84, 85, 86]), "received": np.array([10, 11, 12]) * (u + 1),
            "lost": np.array([1, 2, 3]) * (u + 1), "rejected": np.zeros(3, int)}
        for u in (0, 1)
    }  # fmt: skip
    m = _mission([_ev(8.6, EventType.MISSION_COMPLETE, value=1.0)], [], states=states)
    report = compute_metrics(m)
    live = LiveSummary(uav_count=2)
    for u, s in states.items():
        for k in range(3):
            live.add_state(u, float(s["t"][k]), (int(s["received"][k]), int(s["lost"][k]), 0), [0, 1], 3)
    live.mission_time_s = 8.6
    live.settle_states()
    console = live.as_dict(outcome="complete", wall_s=1.0, steps=86)
    assert report["packets_lost_total"] == console["packets_lost"] == 2 + 4
    assert sum(p["received"] for p in report["packets"].values()) == console["packets_received"] == 11 + 22


def test_the_no_fleet_run_does_not_claim_containment_while_fires_burn():
    """``--uavs 0`` of an analytic two-fire mission: both fires burn to the time limit."""
    world = [_ev(60.1, EventType.MISSION_COMPLETE, value=0.0, detail="max_duration_s")]
    m = _mission(
        world, [], truth_fires={0: _fire(300.0, 300.0, None, 60.1), 1: _fire(600.0, 600.0, None, 60.1)}
    )
    m.custom_data["fire_uav.uav_count"] = "0"
    metrics = compute_metrics(m)
    assert metrics["contained_at_s"] is None
    assert (metrics["fires_total"], metrics["fires_active_at_end"]) == (2, 2)
    page = _page(m, metrics, [])
    assert "contained" not in page.lower() and "max_duration_s" not in page
    assert "The mission reached its time limit at 60.1 s, 2 of 2 fires still burning." in page
    cards = dict((k, v) for k, v, _ in summary_cards(metrics, [], [], raster=False))
    assert cards["fires put out"] == "0 of 2"


def _page(m: RecordedMission, metrics: dict, faults: list[Fault]) -> str:
    return render_page(
        metrics, {}, entries=timeline(m, metrics, faults), fires=fire_rows(m, metrics, False),
        uavs=uav_rows(m, metrics, faults), faults=faults, figures={}, sections=[], raster=False,
        collision_radius_m=3.0,
    )  # fmt: skip


def test_the_page_speaks_plainly_and_links_its_sections():
    m, faults = kill_and_outage()
    metrics = compute_metrics(m)
    metrics["loss_probability"] = 0.05
    page = _page(m, metrics, faults)
    visible = re.sub(r"<style>.*?</style>|<[^>]+>", " ", page, flags=re.S)
    for code in (
        "drops_per_fire",
        "peers_declared_crashed",
        "perimeter_distance_error",
        "packets_lost",
        "{",
        "}",
    ):
        assert code not in visible, code
    assert "FF Fig" not in visible and "Tr(P)" not in visible and "tracks 65537" not in visible
    anchors = set(re.findall(r'<section id="([^"]+)"', page))
    links = set(re.findall(r'href="#([^"]+)"', page))
    assert links <= anchors and {"summary", "timeline", "fires", "uavs", "safety", "faults"} <= anchors
    # the order of a debrief: outcome first, diagnostics (if any) and recording details last
    order = [
        page.index(f'<section id="{a}"')
        for a in ("summary", "timeline", "fires", "uavs", "safety", "faults", "recording")
    ]
    assert order == sorted(order)
    assert "Mission complete at 52.0 s" in visible
    assert "UAV 2&#x27;s process killed at 20 s" in page and "0.05" in visible


def test_numbers_are_rounded_for_people_and_figures_placed():
    assert fmt(137.10000000000002) == "137.1" and fmt(0.967741935483871, 2) == "0.97"
    assert fmt(11625) == "11,625" and fmt(None) == "\u2013" and fmt(2.0, 1, "s") == "2.0 s"
    placed = place_figures([("voronoi_phases.png", "a"), ("faults.png", "b"), ("fire_0_estimates.png", "c"),
                            ("drops.png", "d"), ("ekf_error.png", "e")])  # fmt: skip
    assert placed == {"maps": [("voronoi_phases.png", "a")], "faults": [("faults.png", "b")],
                      "diagnostics": [("fire_0_estimates.png", "c"), ("ekf_error.png", "e")],
                      "fires": [("drops.png", "d")]}  # fmt: skip


def test_a_fire_that_flares_up_after_going_out_is_told_so():
    """A raster fire the world declared out at 13.1 s burns again from 20 s (wet cells that had
    not been put out) and goes out for good at 26.1 s after a third drop."""
    W = EventType
    world = [
        _ev(11.0, W.DROP, uav=0, fire=0, value=2000.0), _ev(12.9, W.DROP, uav=1, fire=0, value=2000.0),
        _ev(13.1, W.EXTINGUISHED, fire=0),
        _ev(25.7, W.DROP, uav=0, fire=0, value=1960.0), _ev(26.1, W.EXTINGUISHED, fire=0),
    ]  # fmt: skip
    f = _fire(300.0, 300.0, 13.1)
    f["status"][(f["t"] >= 20.0) & (f["t"] < 26.1)] = FireStatus.ACTIVE
    m = _mission(world, [], truth_fires={0: f})
    assert flare_ups(m) == [(0, 20.0)]
    metrics = compute_metrics(m)
    texts = [e.text for e in timeline(m, metrics, [])]
    i = texts.index("Fire 0 is out, after 2 drops.")
    j = texts.index("Fire 0 flares up again (cells the water had not put out).")
    k = texts.index("Fire 0 is out again, after 3 drops.")
    assert i < j < k
    (row,) = fire_rows(m, metrics, raster=True)
    assert row["out_s"] == 26.1 and not row["burning_at_end"] and row["drops"] == 3


def test_map_panels_are_in_time_order_and_a_lost_uav_stays_marked():
    """UAV 0 drops at 5 s before UAV 1 is up (at 12 s): the firefighting panel still comes after
    takeoff; UAV 1, lost at 30 s, is left out of the partition but drawn where it fell."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from fire_report.figures import _draw_crashes, _positions_at, phase_times
    from fire_uav_common.constants import Objective

    t = np.arange(0.0, 60.0, 1.0)
    obj0 = np.where(t < 1.0, Objective.GROUNDED, np.where(t < 50.0, Objective.SUPPRESS, Objective.LAND))
    obj1 = np.where(t < 12.0, Objective.GROUNDED, Objective.SUPPRESS)
    states = {u: {"t": t, "x": t + 10 * u, "y": t, "objective": o} for u, o in ((0, obj0), (1, obj1))}
    world = [_ev(5.0, EventType.DROP, uav=0, fire=0, value=100.0), _ev(8.0, EventType.DROP, uav=0, fire=0, value=100.0),
             _ev(30.0, EventType.CRASH, uav=1, x=250.0, y=260.0)]  # fmt: skip
    m = _mission(world, [], states=states)
    phases = phase_times(m)
    assert [p[1] for p in phases] == sorted(p[1] for p in phases)
    assert phases[0] == ("takeoff", 12.0) and phases[1][0] == "firefighting" and phases[1][1] >= 12.0
    assert set(_positions_at(m, 40.0)) == {0}
    fig, ax = plt.subplots()
    _draw_crashes(ax, m, 20.0)
    assert not ax.lines
    _draw_crashes(ax, m, 40.0)
    assert [tuple(line.get_xydata()[0]) for line in ax.lines] == [(250.0, 260.0)]
    assert [x.get_text() for x in ax.texts] == ["UAV 1 lost"]
    plt.close(fig)
