"""Deprecated: a small stand-in world, kept only for ``scripts/bench_agent.py`` and one slow test.

Use :mod:`fire_uav_agent.testing.harness` (the real ``fire_world_sim`` World and the real Agents
in lockstep) for fleet tests; this module will go once the benchmark moves to the harness.

Not the project's world (fire_world_sim): a perfect-lockstep stand-in with the same contract
(docs/protocol.md): FF Eq. 4 at ``physics_period_s`` with input noise, multi-rate sensors with
dropouts (FF II-C), analytic drifting Gaussian fires that lose 3/4 of their area per drop
(FF V-B), refills over a lake, takeoff and landing rules, and peer messages delivered one step
later to every other agent.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from fire_uav_common import rng

from .agent_config import AgentConfig
from .agent_core import Agent
from .agent_types import Bundle, StepOutput
from .estimation import Samples, wrap_angle
from .peer_link import FireEntry, PeerFires, PeerState

__all__ = ["SimFire", "MiniWorld"]


@dataclass
class SimFire:
    x_m: float
    y_m: float
    sigma_m: float
    vx_mps: float = 0.0
    vy_mps: float = 0.0
    out: bool = False


@dataclass
class _Vehicle:
    s: np.ndarray
    status: int = 0
    water_kg: float = 2000.0
    cmd: np.ndarray = field(default_factory=lambda: np.zeros(3))
    alive: bool = True  # its agent runs


def peer_messages(out: StepOutput) -> tuple[PeerState, PeerFires]:
    st = out.state.as_peer_state()
    fires = PeerFires(out.state.uav_id, out.fires_sequence, out.step, tuple(out.fires))
    return st, fires


class MiniWorld:
    def __init__(
        self,
        configs: list[AgentConfig],
        fires: list[SimFire],
        seed: int = 0,
        extinction_sigma_m: float = 2.0,
        gps_p: float = 0.9,
        alt_p: float = 0.8,
        gyro_p: float = 0.7,
    ) -> None:
        self.cfgs = configs
        self.agents = [Agent(c) for c in configs]
        c0 = configs[0]
        self.T = c0.control_period_s
        self.dt = c0.physics_period_s
        self.fires = fires
        self.ext = extinction_sigma_m
        self.p = (gps_p, alt_p, gyro_p)
        self.rng = rng.stream(seed, "minisim")
        self.vehicles = [
            _Vehicle(np.array(c.start_pose, dtype=float), water_kg=c.vehicle.water_capacity_kg)
            for c in configs
        ]
        self.step_k = 0
        self.pending: list[list[PeerState | PeerFires]] = [[] for _ in configs]
        self.drops = 0
        self.drop_times: list[float] = []
        self.errors: list[np.ndarray] = []  # (x, y, z, yaw) estimate errors per agent-step
        self.outputs: list[StepOutput | None] = [None] * len(configs)

    def _integrate(self, v: _Vehicle, c: AgentConfig) -> Samples:
        t0 = self.step_k * self.T
        n = int(round(self.T / self.dt))
        lim = c.limits
        cmd = v.cmd.copy()
        gps, alt, gyro = [], [], []
        terrain = c.terrain
        if v.status == 0 and cmd[0] >= lim.v_stall_mps and cmd[1] > 0:
            v.status = 1
        for j in range(1, n + 1):
            t = t0 + j * self.dt
            if v.status == 1:
                u = np.array(
                    [
                        np.clip(cmd[0], lim.v_stall_mps, lim.v_max_mps),
                        np.clip(cmd[1], -lim.vz_max_mps, lim.vz_max_mps),
                        np.clip(cmd[2], -lim.omega_max_radps, lim.omega_max_radps),
                    ]
                )
                w = u + self.rng.normal(0.0, c.vehicle.process_noise_sigma, 3)
                th = v.s[3]
                v.s = v.s + self.dt * np.array([w[0] * math.cos(th), w[0] * math.sin(th), w[1], w[2]])
                v.s[3] = wrap_angle(v.s[3])
                e = float(terrain.elevation(v.s[0], v.s[1]))
                v.s[2] = max(v.s[2], e)
                if self.rng.random() < self.p[2]:
                    gyro.append((t, w[2] + self.rng.normal(0.0, c.sensors.gyro.sigma_radps)))
            if j % max(1, int(round(0.1 / self.dt))) == 0 and self.rng.random() < self.p[0]:
                gps.append((t, *(v.s[:2] + self.rng.normal(0.0, c.sensors.gps.sigma_m, 2))))
            if j % max(1, int(round(0.04 / self.dt))) == 0 and self.rng.random() < self.p[1]:
                h = v.s[2] - float(terrain.elevation(v.s[0], v.s[1]))
                if h <= c.sensors.altimeter.max_range_m:
                    alt.append((t, h + self.rng.normal(0.0, c.sensors.altimeter.sigma_m)))
        if v.status == 1:
            h = v.s[2] - float(terrain.elevation(v.s[0], v.s[1]))
            if h < c.vehicle.landing_height_m and cmd[0] < lim.v_stall_mps:
                v.status = 2
        return Samples(
            gps=np.array(gps).reshape(-1, 3),
            gps_var_m2=np.full(len(gps), c.sensors.gps.sigma_m**2),
            alt=np.array(alt).reshape(-1, 2),
            gyro=np.array(gyro).reshape(-1, 2),
        )

    def step(self) -> None:
        t1 = (self.step_k + 1) * self.T
        for f in self.fires:
            if not f.out:
                f.x_m += f.vx_mps * self.T
                f.y_m += f.vy_mps * self.T
        outs: list[StepOutput | None] = []
        for i, (agent, v, c) in enumerate(zip(self.agents, self.vehicles, self.cfgs, strict=True)):
            if not v.alive:
                outs.append(None)
                continue
            samples = self._integrate(v, c)
            dets = []
            if v.status == 1:
                for f in self.fires:
                    if not f.out and math.hypot(f.x_m - v.s[0], f.y_m - v.s[1]) <= c.fire_range_m:
                        dets.append(
                            (
                                t1,
                                f.x_m + self.rng.normal(0, 2.0),
                                f.y_m + self.rng.normal(0, 2.0),
                                f.sigma_m + self.rng.normal(0, 1.0),
                            )
                        )
            b = Bundle(self.step_k, t1, samples, np.array(dets).reshape(-1, 4), v.water_kg, v.status, self.T)
            out = agent.step(b, self.pending[i])
            self.pending[i] = []
            outs.append(out)
            if out is None:
                continue
            err = out.state.s - v.s
            err[3] = wrap_angle(err[3])
            if v.status == 1:
                self.errors.append(np.concatenate([err, [i, t1]]))
            v.cmd = np.array(out.command)
            for action, _fid in out.payload_requests:
                if action == 1 and v.water_kg > 0:
                    self.drops += 1
                    self.drop_times.append(t1)
                    for f in self.fires:
                        # same hit rule as the world: within max(footprint, sigma)
                        if not f.out and math.hypot(f.x_m - v.s[0], f.y_m - v.s[1]) <= max(
                            c.drop_radius_m, f.sigma_m
                        ):
                            f.sigma_m /= 2.0
                            if f.sigma_m < self.ext:
                                f.out = True
                    v.water_kg = 0.0
                elif action == 2:
                    lake_ok = any(lk.contains(v.s[0], v.s[1]) for lk in c.lakes)
                    h = v.s[2] - float(c.terrain.elevation(v.s[0], v.s[1]))
                    if (
                        lake_ok
                        and h <= c.vehicle.refill_height_m
                        and v.cmd[0] <= c.limits.v_stall_mps + c.vehicle.refill_speed_margin_mps
                    ):
                        v.water_kg = min(c.vehicle.water_capacity_kg, v.water_kg + 400.0 * self.T)
        for i, out in enumerate(outs):
            if out is None:
                continue
            st, fi = peer_messages(out)
            for j in range(len(self.agents)):
                if j != i and self.vehicles[j].alive:
                    self.pending[j] += [st, fi]
        self.outputs = outs
        self.step_k += 1

    def run(self, duration_s: float) -> None:
        for _ in range(int(round(duration_s / self.T))):
            self.step()


def fire_entry(fire_id: int, x: float, y: float, extent: float, lm: float, active: bool = True) -> FireEntry:
    return FireEntry(fire_id, active, x, y, extent, 0.0, 0.0, lm)
