"""The real World and the real Agents in one process, stepped in lockstep (no ROS, no DDS).

Test support only: the node never imports this module. :class:`Harness` builds
``fire_world_sim.world.World(scenario, seed, uav_count)`` and one :class:`~fire_uav_agent.agent_core.Agent`
per UAV from the same scenario, and steps them as the processes do in lockstep mode
(docs/protocol.md): world step k -> one bundle per live vehicle -> each agent's step k (with the
peers' step-(k-1) messages) -> commands and payload requests stamped t_{k+1} -> world step k+1.
Peer messages (state, fires, perimeter, front) go through each receiving agent's
:class:`~fire_uav_agent.peer_gate.PeerGate`, the node's gate (admission, duplicates, the lockstep
wait, the inbox order), and reach the agent with its next bundle; the injected loss is applied on
receipt by each agent's own peer link (seeded rule of ``fire_uav_agent.peer_link``), as in the
node. A stopped agent (:meth:`Harness.stop`, a killed process) sends nothing more and is no longer
waited for; the world lets its vehicle fall after the command timeout.

The conversions between the world's Python types and the agent's are :func:`agent_bundle`,
:func:`world_command` and :func:`peer_messages`, one function each; they round what the ROS
messages carry as float32 (water gauge, altimeter range, raster cells, perimeter arrays) the
way the messages do, so a harness run sees the numbers a ROS run sees.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from fire_uav_common import topics
from fire_uav_common.constants import VehicleStatus
from fire_uav_common.scenario import Scenario, load_scenario
from fire_uav_common.stamps import ns_to_s, s_to_ns
from fire_world_sim import world as wsim

from ..agent_config import config_from_scenario
from ..agent_core import Agent
from ..agent_types import Bundle, PeerPerimeter, StepOutput
from ..estimation import Samples
from ..fire_front import FrontCells
from ..front_consensus import PeerFront
from ..peer_gate import PeerGate, Rejected, RunStep
from ..peer_link import FireEntry, PeerFires, PeerState

__all__ = ["Harness", "agent_bundle", "peer_messages", "scenario_path", "world_command"]

PeerMessage = PeerState | PeerFires | PeerPerimeter | PeerFront


def scenario_path(name: str) -> Path:
    """Path of a scenario shipped with fire_world_sim (``"ff_two_fires"`` -> ``.../ff_two_fires.yaml``)."""
    import fire_world_sim

    root = Path(fire_world_sim.__file__).resolve().parents[1] / "scenarios"
    for base in (root, Path(fire_world_sim.__file__).resolve().parent / "scenarios"):
        p = base / f"{name}.yaml"
        if p.is_file():
            return p
    raise FileNotFoundError(f"no scenario {name!r} under {root}")


def _f32(x: float) -> float:
    return float(np.float32(x))


# --- conversions (the harness's counterpart of world_node._bundle_bytes and agent_node._to_*) ---
def agent_bundle(b: wsim.Bundle) -> Bundle:
    """World bundle -> agent bundle, as ``SensorBundle`` carries it (stamps [ns] -> [s])."""
    gps = np.array([(ns_to_s(g.stamp_ns), g.x_m, g.y_m) for g in b.gps], dtype=float).reshape(-1, 3)
    gps_var = np.array([g.variance_m2 for g in b.gps], dtype=float)
    alt = np.array([(ns_to_s(a.stamp_ns), _f32(a.range_m)) for a in b.altimeter], dtype=float).reshape(-1, 2)
    gyro = np.array([(ns_to_s(g.stamp_ns), g.omega_z_radps) for g in b.gyro], dtype=float).reshape(-1, 2)
    fires = np.array([(ns_to_s(f.stamp_ns), f.x_m, f.y_m, f.extent_m) for f in b.fires], dtype=float).reshape(
        -1, 4
    )
    c = b.cells
    cells = None
    cell_size_m = 0.0
    if c is not None:
        cell_size_m = _f32(c.cell_size_m)
        if len(c.x_m) > 0 and len(c.x_m) == len(c.y_m) == len(c.state):
            cells = (
                np.asarray(c.x_m, dtype=np.float32).astype(float),
                np.asarray(c.y_m, dtype=np.float32).astype(float),
                np.asarray(c.state, dtype=np.uint8).astype(np.int64),
            )
    return Bundle(
        step=int(b.step),
        stamp_s=ns_to_s(b.stamp_ns),
        samples=Samples(gps, gps_var, alt, gyro),
        fires=fires,
        water_kg=_f32(b.water_kg),
        vehicle=int(b.vehicle_status),
        control_period_s=float(b.control_period_s),
        cells=cells,
        cell_size_m=cell_size_m,
    )


def world_command(out: StepOutput) -> tuple[wsim.Command, list[int]]:
    """Agent output -> the world's command and payload actions for the next step."""
    v, vz, om = (float(x) for x in out.command)
    return wsim.Command(v, vz, om), [int(action) for action, _fire in out.payload_requests]


def peer_messages(out: StepOutput, perimeter_sequence: int = 0) -> list[PeerMessage]:
    """Agent output -> what its peers receive (``UavState`` with its fires, ``PerimeterMap``)."""
    st = out.state.as_peer_state()
    st = PeerState(**{**st.__dict__, "water_kg": _f32(st.water_kg)})
    fires = tuple(
        FireEntry(
            e.fire_id,
            e.active,
            e.x_m,
            e.y_m,
            e.extent_m,
            e.vx_mps,
            e.vy_mps,
            ns_to_s(s_to_ns(max(0.0, e.last_measurement_s) if math.isfinite(e.last_measurement_s) else 0.0)),
            e.front_x_m,
            e.front_y_m,
            e.max_spread_rate_mps,
        )  # fmt: skip
        for e in out.fires
    )
    msgs: list[PeerMessage] = [st, PeerFires(out.state.uav_id, out.fires_sequence, out.step, fires)]
    if out.perimeter is not None:
        fire_id, s = out.perimeter
        summary = {
            "center_x_m": float(s["center_x_m"]),
            "center_y_m": float(s["center_y_m"]),
            "outer_distance_m": np.asarray(s["outer_distance_m"], dtype=np.float32).astype(float),
            "outer_visit_time_s": np.asarray(s["outer_visit_time_s"], dtype=np.float32).astype(float),
        }
        fid = int(fire_id) if fire_id < 2**31 else -1
        msgs.append(PeerPerimeter(out.state.uav_id, perimeter_sequence, out.step, fid, summary))
    if out.front is not None:
        msgs.append(PeerFront(out.state.uav_id, out.state.sequence, out.step, front_as_sent(out.front)))  # type: ignore[arg-type]  # StepOutput.front is typed object (agent_types does not import fire_front)
    return msgs


def front_as_sent(c: FrontCells) -> FrontCells:
    """Front cells as ``FireFront`` carries them (float32 centres and rates, float64 times)."""
    return FrontCells(
        np.asarray(c.x_m, dtype=np.float32).astype(float),
        np.asarray(c.y_m, dtype=np.float32).astype(float),
        np.asarray(c.state, dtype=np.uint8).astype(np.int64),
        np.asarray(c.t_obs_s, dtype=float),
        np.asarray(c.ros_mps, dtype=np.float32).astype(float),
    )


# --- the harness --------------------------------------------------------------------------------
@dataclass
class Harness:
    """World + N agents in lockstep. ``seed`` None: the scenario's; ``uav_count`` 0: the scenario's."""

    scenario: Scenario
    seed: int | None = None
    uav_count: int = 0
    agent_options: dict = field(default_factory=dict)  # extra AgentConfig fields (monitor_alpha, ...)

    def __post_init__(self) -> None:
        self.world = wsim.World(self.scenario, self.seed, self.uav_count)
        n = self.world.uav_count
        if self.scenario.mission.prior_fires == "known" and "prior_fires" not in self.agent_options:
            from fire_world_sim.dispatch import prior_fire_estimates  # the briefing, as the runner gives it

            self.agent_options = {
                **self.agent_options,
                "prior_fires": tuple(prior_fire_estimates(self.scenario, self.world.seed)),
            }
        self.agents = [
            Agent(
                config_from_scenario(
                    self.scenario, i, uav_count=n, seed=self.world.seed, **self.agent_options
                )
            )
            for i in range(n)
        ]
        self.stopped: set[int] = set()
        self.outputs: list[StepOutput | None] = [None] * n
        self.result: wsim.StepResult | None = None
        self.events: list[wsim.Event] = []
        self._commands: dict[int, wsim.Command | None] = {}
        self._payload: dict[int, list[int]] = {}
        period_s = self.agents[0].cfg.control_period_s if n else 0.1
        self.gates: list[PeerGate] = [
            PeerGate(i, n, period_s, crash_threshold_steps=a.cfg.crash_threshold_steps)
            for i, a in enumerate(self.agents)
        ]
        self._perimeter_seq = [0] * n

    @classmethod
    def from_file(
        cls, path: str | Path, seed: int | None = None, uav_count: int = 0, **agent_options
    ) -> Harness:
        return cls(load_scenario(path), seed, uav_count, dict(agent_options))

    @property
    def step_index(self) -> int:
        """The next world step k."""
        return self.world.step_index

    def stop(self, uav_id: int) -> None:
        """The agent's process dies now: it is not stepped again and sends nothing more."""
        self.stopped.add(uav_id)
        for g in self.gates:
            if g.uav_id != uav_id:
                g.mark_gone(uav_id)

    def step(self) -> wsim.StepResult:
        """One lockstep round: world step k, then every running agent's step k."""
        r = self.world.step(self._commands, self._payload)
        self.result = r
        self.events += r.events
        self._commands, self._payload = {}, {}
        outs: list[StepOutput | None] = [None] * len(self.agents)
        for uid, b in sorted(r.bundles.items()):
            if uid in self.stopped:
                continue
            run = self._decide(uid, self.gates[uid].on_bundle(b.step, b))
            if run is None:
                raise RuntimeError(
                    f"harness: agent {uid} would wait at step {b.step} for {self.gates[uid].wait.describe(b.step)}"
                )
            out = self.agents[uid].step(agent_bundle(run.bundle), run.inbox)
            outs[uid] = out
            if out is None:
                continue
            self._commands[uid], self._payload[uid] = world_command(out)
        for uid, out in enumerate(outs):
            if out is None:
                continue
            if out.perimeter is not None:
                self._perimeter_seq[uid] += 1
            msgs = peer_messages(out, self._perimeter_seq[uid])
            final = int(r.bundles[uid].vehicle_status) == int(VehicleStatus.CRASHED)
            for j in range(len(self.agents)):
                if j != uid and j not in self.stopped:
                    self._deliver(j, msgs, final)
        self.outputs = outs
        return r

    def _deliver(self, j: int, msgs: list[PeerMessage], final: bool) -> None:
        """One agent's step messages to agent ``j``'s gate, as the node hands them over (the state
        first, with the count of what else was sent)."""
        gate = self.gates[j]
        state, fires, rest = msgs[0], msgs[1], msgs[2:]
        assert isinstance(state, PeerState) and isinstance(fires, PeerFires)
        sent = [0] * (1 + max(s.loss_index for s in topics.ALL_TOPICS if s.loss_index is not None))
        sent[topics.FLEET_STATE_SPEC.draw_index] = sent[topics.FLEET_FIRES_SPEC.draw_index] = 1
        for m in rest:
            spec = topics.FLEET_PERIMETER_SPEC if isinstance(m, PeerPerimeter) else topics.FLEET_FRONT_SPEC
            sent[spec.draw_index] += 1
        self._decide(j, gate.on_state(b"", state, fires, tuple(sent), final))
        for m in rest:
            if isinstance(m, PeerPerimeter):
                self._decide(j, gate.on_perimeter(b"", m))
            elif isinstance(m, PeerFront):
                self._decide(j, gate.on_front(m.uav_id, m.step, m))

    def _decide(self, uid: int, decisions: list) -> RunStep | None:
        """Count the gate's rejections in the agent's link (as the node does); the step to run, if any."""
        run = None
        for d in decisions:
            if isinstance(d, Rejected):
                self.agents[uid].link.count_rejection(d.reason)
            elif isinstance(d, RunStep):
                run = d
        return run

    def run(self, steps: int | None = None) -> wsim.StepResult | None:
        """Step until the world reports the mission complete (or for ``steps`` steps)."""
        n = 0
        while not self.world.complete and (steps is None or n < steps):
            self.step()
            n += 1
        return self.result

    def truth(self) -> tuple[list[wsim.VehicleTruthRecord], list]:
        """The last step's true vehicles and fires."""
        assert self.result is not None, "step the harness first"
        return self.result.vehicles, self.result.fires

    def messages_to(self, uav_id: int) -> Iterable[PeerMessage]:
        """Peer messages waiting for ``uav_id``'s next step (for tests)."""
        return tuple(self.gates[uav_id].inbox())
