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

Every message travels as the bytes the nodes publish (sensor bundle, peer state, perimeter map,
front picture), written and read by the same codecs (``fire_uav_common.codecs``, through the
agent's ``outgoing`` and ``incoming``), so a harness run sees the numbers a ROS run sees (float32
fields, stamps of whole nanoseconds) and rounds nothing itself.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from fire_uav_common.codecs.fire_front import read_fire_front
from fire_uav_common.codecs.perimeter_map import read_perimeter_map
from fire_uav_common.codecs.sensor_bundle import read_sensor_bundle, write_sensor_bundle
from fire_uav_common.codecs.uav_state import WireState, read_uav_state
from fire_uav_common.constants import Objective, VehicleStatus
from fire_uav_common.scenario import Scenario, load_scenario
from fire_world_sim import world as wsim

from ..agent_config import config_from_scenario
from ..agent_core import Agent
from ..agent_types import Bundle, PeerPerimeter, StepOutput
from ..front_consensus import PeerFront
from ..guidance import Situation
from ..incoming import peer_front, peer_perimeter
from ..mission import Decision
from ..outgoing import front_bytes, perimeter_bytes, sent_per_topic, state_bytes
from ..peer_gate import PeerGate, Rejected, RunStep
from ..peer_link import PeerFires, PeerState

__all__ = [
    "Harness",
    "PeerBytes",
    "agent_bundle",
    "peer_messages",
    "refill_situation",
    "scenario_path",
    "world_command",
]

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


def refill_situation(agent: Agent, cell: np.ndarray | None = None) -> Situation:
    """The guidance stage's input for ``agent`` in REFILL toward its first lake, its Voronoi cell
    ``cell`` (a mask over ``agent.grid.points``; all of them if None). REFILL reads no planner
    view, so none is given."""
    mask = np.ones(agent.grid.points.shape[0], bool) if cell is None else cell
    return Situation(
        Decision(Objective.REFILL, -1, None, False, False),
        (),
        agent.lakes[0],
        None,  # type: ignore[arg-type]  # REFILL does not read the planner view
        mask,
    )


# --- conversions -----------------------------------------------------------------------------------
def agent_bundle(b: wsim.SensorBundleRecord, gyro_sigma_radps: float) -> Bundle:
    """World bundle -> agent bundle, through the bytes the world node publishes."""
    return read_sensor_bundle(write_sensor_bundle(b, gyro_sigma_radps)).bundle


def world_command(out: StepOutput) -> tuple[wsim.Command, list[int]]:
    """Agent output -> the world's command and payload actions for the next step."""
    v, vz, om = (float(x) for x in out.command)
    return wsim.Command(v, vz, om), [int(action) for action, _fire in out.payload_requests]


@dataclass(frozen=True)
class PeerBytes:
    """What one agent sends its peers at a step, as the node publishes it: the UavState (with the
    fire picture and the count of the rest), and the PerimeterMap and FireFront if any."""

    state: bytes
    perimeter: bytes | None = None
    front: bytes | None = None


def peer_messages(
    out: StepOutput,
    stamp_ns: int,
    final: bool,
    perimeter_sequence: int = 0,
    front_sequence: int = 0,
    cell_size_m: float = 0.0,
) -> PeerBytes:
    """Agent output -> the bytes its peers receive (the node's ``outgoing`` writers)."""
    pm = perimeter_bytes(out, stamp_ns, perimeter_sequence)
    fm = front_bytes(out, stamp_ns, front_sequence, cell_size_m)
    sent = sent_per_topic(pm is not None, fm is not None)
    return PeerBytes(state_bytes(out, stamp_ns, sent, final), pm, fm)


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
        self.events: list[wsim.MissionEventRecord] = []
        self._commands: dict[int, wsim.Command | None] = {}
        self._payload: dict[int, list[int]] = {}
        period_s = self.agents[0].cfg.control_period_s if n else 0.1
        self.gates: list[PeerGate] = [
            PeerGate(i, n, period_s, crash_threshold_steps=a.cfg.crash_threshold_steps)
            for i, a in enumerate(self.agents)
        ]
        self._perimeter_seq = [0] * n
        self._front_seq = [0] * n
        self._gyro_sigma_radps = float(self.scenario.sensors.gyro.sigma_radps)

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
            out = self.agents[uid].step(agent_bundle(run.bundle, self._gyro_sigma_radps), run.inbox)
            outs[uid] = out
            if out is None:
                continue
            self._commands[uid], self._payload[uid] = world_command(out)
        for uid, out in enumerate(outs):
            if out is None:
                continue
            front = self.agents[uid].front
            self._perimeter_seq[uid] += out.perimeter is not None
            self._front_seq[uid] += front is not None and out.front is not None
            b = r.bundles[uid]
            final = int(b.vehicle_status) == int(VehicleStatus.CRASHED)
            cell_size_m = 0.0 if front is None else front.cfg.cell_size_m
            sent = peer_messages(
                out, b.stamp_ns, final, self._perimeter_seq[uid], self._front_seq[uid], cell_size_m
            )
            wire = read_uav_state(sent.state)
            rest: list[PeerPerimeter | PeerFront] = []
            period_s = self.agents[uid].cfg.control_period_s
            if sent.perimeter is not None:
                rest.append(peer_perimeter(read_perimeter_map(sent.perimeter), period_s))
            if sent.front is not None:
                rest.append(peer_front(read_fire_front(sent.front), period_s))
            for j in range(len(self.agents)):
                if j != uid and j not in self.stopped:
                    self._deliver(j, sent, wire, rest)
        self.outputs = outs
        return r

    def _deliver(
        self, j: int, sent: PeerBytes, wire: WireState, rest: list[PeerPerimeter | PeerFront]
    ) -> None:
        """One agent's step messages to agent ``j``'s gate, as the node hands them over (the state
        first: it says what else was sent); ``rest``: the perimeter map and front read from
        ``sent`` (once: every receiver reads the same bytes)."""
        gate = self.gates[j]
        self._decide(j, gate.on_state(sent.state, wire.state, wire.fires, wire.sent_per_topic, wire.final))
        for m in rest:
            if isinstance(m, PeerPerimeter):
                self._decide(j, gate.on_perimeter(sent.perimeter or b"", m))
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
