"""The in-process harness (fire_uav_agent.testing.harness) a few steps at a time.

Fast on purpose (the mutation selection of ``fire_uav_agent.testing.harness`` runs this file once
per mutant; test_harness.py flies whole missions, ~15 s). Truths: the lockstep order of
docs/protocol.md (world step k, then every agent's step k with its peers' step-(k-1) messages),
the world's own records (a vehicle moves only when commanded; one left without commands falls
after ``vehicle.command_timeout_s``), the scenario's fields, and the bytes' readers.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from fire_uav_agent.agent_types import StepOutput
from fire_uav_agent.mission import Decision
from fire_uav_agent.peer_link import PeerFires, PeerState
from fire_uav_agent.testing.harness import (
    Harness,
    agent_bundle,
    peer_messages,
    refill_situation,
    scenario_path,
    world_command,
)
from fire_uav_common.codecs.uav_state import read_uav_state
from fire_uav_common.constants import EventType, Objective, PayloadAction, VehicleStatus
from fire_uav_common.scenario import load_scenario
from fire_world_sim import world as wsim


@pytest.fixture(scope="module")
def tiny():
    return load_scenario(scenario_path("tiny_test"), overrides={"uavs.count": 3})


def _senders(h: Harness, uid: int) -> list[tuple[str, int, int]]:
    return sorted((type(m).__name__, m.uav_id, m.step) for m in h.messages_to(uid))


def test_scenario_path_names_the_shipped_file_or_fails_naming_it():
    p = scenario_path("tiny_test")
    assert p.is_file() and p.name == "tiny_test.yaml" and load_scenario(p).name == "tiny_test"
    with pytest.raises(FileNotFoundError, match=r"no scenario 'no_such_scenario' under "):
        scenario_path("no_such_scenario")


def test_scenario_path_finds_the_scenarios_installed_inside_the_package(tmp_path, monkeypatch):
    """An installed fire_world_sim carries its scenarios in the package directory itself."""
    import fire_world_sim

    pkg = tmp_path / "site" / "fire_world_sim"
    (pkg / "scenarios").mkdir(parents=True)
    (pkg / "scenarios" / "only_here.yaml").write_text("name: only_here\n")
    monkeypatch.setattr(fire_world_sim, "__file__", str(pkg / "__init__.py"))
    assert scenario_path("only_here") == (pkg / "scenarios" / "only_here.yaml").resolve()
    with pytest.raises(
        FileNotFoundError, match=rf"^no scenario 'tiny_test' under {tmp_path / 'site' / 'scenarios'}$"
    ):
        scenario_path("tiny_test")


def test_the_fleet_size_and_seed_are_the_scenarios_unless_given(tiny):
    h = Harness(tiny)
    assert h.world.uav_count == 3 == len(h.agents) == len(h.gates) == len(h.outputs)
    assert h.world.seed == tiny.seed
    assert [(a.cfg.uav_id, a.cfg.uav_count, a.cfg.seed) for a in h.agents] == [
        (i, 3, tiny.seed) for i in range(3)
    ]
    assert [(g.uav_id, g.uav_count) for g in h.gates] == [(i, 3) for i in range(3)]
    # tiny_test flies 2: a count given is the fleet's, for the world and every agent
    h2 = Harness.from_file(scenario_path("tiny_test"), seed=5, uav_count=3, monitor_alpha=2.5)
    assert h2.world.seed == 5 and h2.world.uav_count == 3
    assert [(a.cfg.uav_id, a.cfg.uav_count, a.cfg.seed, a.cfg.monitor_alpha) for a in h2.agents] == [
        (i, 3, 5, 2.5) for i in range(3)
    ]
    assert Harness.from_file(scenario_path("tiny_test")).world.uav_count == 2


def test_the_gates_take_the_scenarios_period_and_crash_threshold(tiny):
    s = dataclasses.replace(
        tiny,
        timing=dataclasses.replace(tiny.timing, control_period_s=0.2, physics_period_s=0.02),
        mission=dataclasses.replace(tiny.mission, crash_threshold_steps=4),
    )
    h = Harness(s)
    assert [(g.control_period_s, g.crash_threshold_steps) for g in h.gates] == [(0.2, 4)] * 3


def test_a_fleet_of_one_and_a_fire_alone(tiny):
    one = Harness(tiny, uav_count=1)
    one.run(steps=3)
    assert len(one.agents) == 1 and one.outputs[0].step == 2 and list(one.messages_to(0)) == []
    none = Harness(dataclasses.replace(tiny, uavs=dataclasses.replace(tiny.uavs, count=0)))
    none.run(steps=3)  # no agent, no gate: the world alone
    assert none.agents == [] and none.gates == [] and none.step_index == 3


def test_known_fires_are_briefed_to_every_agent_as_the_runner_does(tiny):
    from fire_world_sim.dispatch import prior_fire_estimates

    known = dataclasses.replace(tiny, mission=dataclasses.replace(tiny.mission, prior_fires="known"))
    h = Harness(known, seed=4)
    briefing = tuple(prior_fire_estimates(known, 4))
    assert briefing and all(a.cfg.prior_fires == briefing for a in h.agents)
    own = ((100.0, 100.0, 5.0),)
    assert all(
        a.cfg.prior_fires == own for a in Harness(known, seed=4, agent_options={"prior_fires": own}).agents
    )
    assert all(a.cfg.prior_fires == () for a in Harness(tiny, seed=4).agents)  # unknown: no briefing


def test_truth_before_the_first_step_is_an_error(tiny):
    with pytest.raises(AssertionError, match="^step the harness first$"):
        Harness(tiny).truth()


def test_each_step_is_world_step_k_then_every_agents_step_k_with_the_peers_messages(tiny):
    h = Harness(tiny)
    assert h.step_index == 0
    for k in range(4):
        r = h.step()
        assert r.step == k and h.step_index == k + 1 and h.result is r
        assert [o.step for o in h.outputs] == [k, k, k]
        assert h.truth() == (r.vehicles, r.fires)
        for uid in range(3):
            # the peers' step-k state and fires wait for this agent's step k + 1; never its own
            want = sorted((kind, j, k) for j in range(3) if j != uid for kind in ("PeerFires", "PeerState"))
            assert _senders(h, uid) == want
            assert all(isinstance(m, PeerState | PeerFires) for m in h.messages_to(uid))


def test_the_agents_commands_fly_the_world_vehicles(tiny):
    h = Harness(tiny)
    h.run(steps=30)
    # takeoff slots every uavs.takeoff_interval_s (1 s in tiny_test): all three have climbed
    vs, _ = h.truth()
    assert [v.status for v in vs] == [VehicleStatus.AIRBORNE] * 3
    assert all(v.z_m > 1.0 for v in vs)
    assert all(v.commands_missed == 0 for v in vs)
    # UAV 0 asked to drop at step 27 (over tiny_test's fire): the world dropped its tank at step 28,
    # and the harness keeps every step's events (the takeoffs of steps 0-20 too)
    kinds = [(e.type, e.uav_id) for e in h.events]
    assert (EventType.DROP, 0) in kinds and vs[0].water_kg == 0.0
    assert {u for t, u in kinds if t == EventType.TAKEOFF} == {0, 1, 2}


def test_run_steps_counts_the_steps_and_stops_at_the_mission_end(tiny):
    h = Harness(tiny)
    assert h.run(steps=0) is None and h.step_index == 0
    r = h.run(steps=7)
    assert h.step_index == 7 and r is h.result and r.step == 6
    short = dataclasses.replace(tiny, timing=dataclasses.replace(tiny.timing, max_duration_s=0.55))
    h = Harness(short)
    r = h.run()
    assert r is not None and r.complete and h.world.complete
    assert h.step_index == r.step + 1 and r.stamp_ns >= 0.55e9
    assert h.run() is r and h.run(steps=3) is r  # nothing more to step


def test_a_stopped_agent_is_not_stepped_sends_nothing_and_its_vehicle_falls(tiny):
    h = Harness(tiny)
    h.run(steps=20)
    k = h.step_index
    h.stop(1)  # the middle one: the agents after it still run and send
    assert h.stopped == {1}
    h.step()
    assert h.outputs[1] is None and h.outputs[0].step == k == h.outputs[2].step
    assert _senders(h, 0) == [("PeerFires", 2, k), ("PeerState", 2, k)]
    assert _senders(h, 2) == [("PeerFires", 0, k), ("PeerState", 0, k)]
    # nothing more is delivered to it: its gate holds what it had before it stopped
    assert all(step < k for _, _, step in _senders(h, 1))
    # its peers' gates no longer wait for it (mark_gone): they keep running past the crash threshold
    timeout_steps = int(round(tiny.vehicle.command_timeout_s / tiny.timing.control_period_s))
    h.run(steps=timeout_steps + 5)
    vs, _ = h.truth()
    assert vs[1].status == VehicleStatus.CRASHED and vs[1].commands_missed > 0
    assert [vs[0].status, vs[2].status] == [VehicleStatus.AIRBORNE] * 2
    assert h.outputs[0].state.crashed_peers == (1,)


def test_an_agent_gone_without_its_peers_told_stops_the_harness_naming_the_wait(tiny):
    h = Harness(tiny)
    h.run(steps=5)
    h.stopped.add(2)  # a process killed while its peers' gates still expect it
    h.step()  # agents 0 and 1 run step 5 with agent 2's messages of step 4
    with pytest.raises(
        RuntimeError, match=r"^harness: agent 0 would wait at step 6 for uav 2: state of step 5$"
    ):
        h.step()


def test_a_crashed_vehicles_agent_sends_its_final_state(tiny):
    # UAVs 0 and 1 (30 m apart) take off 0.1 s apart and collide within the 35 m radius
    # (vehicle.collision_radius_m); UAV 2 is still on the ground then and flies on. The crashed
    # agents' states of their last step are marked final, so UAV 2's gate does not wait for their
    # next step (docs/protocol.md): without "final" the harness would stop at the next step
    s = dataclasses.replace(
        tiny,
        uavs=dataclasses.replace(tiny.uavs, takeoff_interval_s=0.1),
        vehicle=dataclasses.replace(tiny.vehicle, collision_radius_m=35.0),
    )
    h = Harness(s)
    h.run(steps=40)
    vs, _ = h.truth()
    assert [v.status for v in vs] == [VehicleStatus.CRASHED, VehicleStatus.CRASHED, VehicleStatus.AIRBORNE]
    assert h.outputs[0] is None and h.outputs[1] is None and h.outputs[2].step == 39


def test_world_command_is_the_agents_command_and_payload_actions():
    out = StepOutput.__new__(StepOutput)
    object.__setattr__(out, "command", np.array([1.5, -0.5, 0.25]))
    object.__setattr__(out, "payload_requests", [(PayloadAction.DROP, 3), (int(PayloadAction.DROP), 4)])
    cmd, actions = world_command(out)
    assert cmd == wsim.Command(1.5, -0.5, 0.25)
    assert all(type(v) is float for v in (cmd.v_lin_mps, cmd.v_z_mps, cmd.omega_z_radps))
    assert actions == [int(PayloadAction.DROP)] * 2 and all(type(a) is int for a in actions)


def test_the_agent_bundle_is_the_world_bundle_as_read_from_its_bytes(tiny):
    h = Harness(tiny)
    h.run(steps=3)
    b = h.result.bundles[1]
    ab = agent_bundle(b, 0.3)
    assert (ab.step, ab.water_kg, ab.vehicle) == (b.step, b.water_kg, b.vehicle_status)
    assert ab.stamp_s == pytest.approx(b.stamp_ns * 1e-9, abs=1e-12)
    assert ab.samples.gps.shape[0] == len(b.gps)
    assert np.allclose(ab.samples.gps[:, 1:], [[g.x_m, g.y_m] for g in b.gps], atol=1e-3)


def test_peer_messages_are_the_state_and_nothing_else_without_a_map_or_front(tiny):
    h = Harness(tiny)
    h.run(steps=2)
    out = h.outputs[0]
    sent = peer_messages(out, 123_000_000, True)
    assert sent.perimeter is None and sent.front is None
    w = read_uav_state(sent.state)
    assert w.final is True and w.uav_id == 0 and w.step == out.step
    assert read_uav_state(peer_messages(out, 123_000_000, False).state).final is False


def test_refill_situation_aims_at_the_first_lake_with_the_given_cell(tiny):
    a = Harness(tiny).agents[0]
    s = refill_situation(a)
    # REFILL of the first lake, already decided (not changed this step), no payload request, not a
    # stalled refill's direct run; no fire to aim at
    assert s.decision == Decision(Objective.REFILL, -1, None, False, False) and s.aim == ()
    assert s.lake == a.lakes[0]
    assert s.cell.dtype == bool and s.cell.shape == (a.grid.points.shape[0],) and s.cell.all()
    half = a.grid.points[:, 0] > 200.0
    assert refill_situation(a, half).cell is half


@pytest.fixture(scope="module")
def grass():
    """grass_running; its first World in a process loads the raster fire's compiled kernels
    (~1.4 s), paid here once for the tests below."""
    s = load_scenario(scenario_path("grass_running"))
    wsim.World(s, None, 1)
    return s


def test_late_peer_messages_are_counted_as_rejections_in_the_receivers_link(grass):
    """A state, a perimeter map or a front picture of an older step handed to a gate (as a late DDS
    delivery reaches the node) is refused and counted in the receiving agent's peer link (the
    front, unsigned, by the same id and step checks)."""
    h = Harness(grass, uav_count=3)
    h.run(steps=31)  # step 30: UAV 0 sends a perimeter map and a front picture
    out = h.outputs[0]
    sent = peer_messages(out, h.result.bundles[0].stamp_ns, False, 1, 1, 5.0)
    assert sent.perimeter is not None and sent.front is not None
    h.run(steps=2)
    from fire_uav_agent.incoming import peer_front, peer_perimeter
    from fire_uav_common.codecs.fire_front import read_fire_front
    from fire_uav_common.codecs.perimeter_map import read_perimeter_map

    rest = [
        peer_perimeter(read_perimeter_map(sent.perimeter), 0.1),
        peer_front(read_fire_front(sent.front), 0.1),
    ]
    h._deliver(2, sent, read_uav_state(sent.state), rest)
    assert h.agents[2].link.reject_reasons == {"stale step": 3}
    assert h.agents[1].link.reject_reasons == {}


def test_perimeter_maps_and_front_pictures_reach_the_peers_numbered_from_one(grass):
    """grass_running (a raster fire, monitors): each agent's n-th PerimeterMap and n-th FireFront
    carry sequence n and the step they were sent at, in every other agent's inbox."""
    h = Harness(grass, uav_count=3)
    sent_p, sent_f = [0, 0, 0], [0, 0, 0]
    seen_p = seen_f = 0
    for k in range(42):
        h.step()
        for uid, out in enumerate(h.outputs):
            sent_p[uid] += out.perimeter is not None
            sent_f[uid] += out.front is not None
        for j in range(3):
            for m in h.messages_to(j):
                if type(m).__name__ == "PeerPerimeter" and m.step == k:
                    assert m.uav_id != j and m.sequence == sent_p[m.uav_id] and h.outputs[m.uav_id].perimeter
                    seen_p += 1
                elif type(m).__name__ == "PeerFront" and m.step == k:
                    assert m.uav_id != j and m.sequence == sent_f[m.uav_id]
                    seen_f += 1
        for uid, out in enumerate(h.outputs):
            n_p = sum(
                1
                for j in range(3)
                for m in h.messages_to(j)
                if type(m).__name__ == "PeerPerimeter" and m.uav_id == uid and m.step == k
            )
            n_f = sum(
                1
                for j in range(3)
                for m in h.messages_to(j)
                if type(m).__name__ == "PeerFront" and m.uav_id == uid and m.step == k
            )
            assert (n_p, n_f) == (2 * (out.perimeter is not None), 2 * (out.front is not None)), (k, uid)
    assert (seen_p, seen_f) == (2 * sum(sent_p), 2 * sum(sent_f))
    assert max(sent_p) >= 2 and min(sent_f) >= 4  # the second map of one agent is numbered 2


def test_peer_messages_write_the_map_and_the_front_with_their_numbers(grass):
    h = Harness(grass, uav_count=3)
    h.run(steps=31)
    out = h.outputs[0]
    assert out.perimeter is not None and out.front is not None
    from fire_uav_common.codecs.fire_front import read_fire_front
    from fire_uav_common.codecs.perimeter_map import read_perimeter_map

    d = peer_messages(out, 777_000_000, False)  # the defaults: sequence 0, no cell size
    pm, fm = read_perimeter_map(d.perimeter), read_fire_front(d.front)
    assert (pm.stamp_ns, pm.uav_id, pm.sequence) == (777_000_000, 0, 0)
    assert (fm.stamp_ns, fm.uav_id, fm.sequence, fm.cell_size_m) == (777_000_000, 0, 0, 0.0)
    e = peer_messages(out, 888_000_000, False, 3, 4, 5.0)
    pm, fm = read_perimeter_map(e.perimeter), read_fire_front(e.front)
    assert (pm.stamp_ns, pm.sequence, pm.fire_id) == (888_000_000, 3, out.perimeter[0])
    assert (fm.stamp_ns, fm.sequence, fm.cell_size_m) == (888_000_000, 4, 5.0)
    w = read_uav_state(e.state)
    assert w.sent_per_topic and w.final is False
