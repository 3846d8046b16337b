"""The envelope a JSBSim aircraft flies under the world's autopilot, measured (docs/airframes.md).

What a preset's envelope fields should say of the ``jsbsim`` backend, measured by stepping one
:class:`~.jsbsim_backend.JsbsimModel` at fixed commands (no agent, calm air, 100 Hz, launched
trimmed at 200 m), with the autopilot's own speed floor and the preset's speed ceiling lifted so
that the aircraft, not the preset, sets each figure (the bank limit and the roll rate stay the
preset's, which the autopilot flies by design):

- ``v_trim_min_mps``: the lowest airspeed at which JSBSim's trim finds level flight (1 g); NaN
  where the trim fails at every speed (the PC-7: ``JsbsimModel.launch``), and the search for
  ``v_hold_min_mps`` starts from the aircraft's configured 1 g stall ``jsbsim.v_stall_mps``;
- ``v_hold_min_mps``: the lowest commanded airspeed the autopilot holds level (speed within
  ``HOLD_TOL_MPS``, height rate within ``CLIMB_TOL_MPS`` over the last ``TAIL_S`` s, elevator
  not saturated) -- the aircraft's slowest usable speed, its 1.3 V_S in a preset's terms;
- ``v_level_max_mps``: the top speed of level flight: the fastest commanded airspeed, in 1 m/s steps
  up from ``v_hold_min_mps``, that the autopilot holds level as above (:func:`level_top_speed_mps`).
  Not a full-throttle run commanded far beyond it: with its speed error the total-energy
  autopilot (speed weight 0.5) put the pitch on its -15 deg stop, and the PC-7 dived at 15-23 m/s
  to 90 / 102 m/s (its level top speed is 77.7 / 78.2 m/s, empty / full, flown at full throttle
  with the height held for 150 / 400 s), while the J3Cub, its pitch loop short of the stop,
  climbed at 2.25 m/s at 40.3 m/s (it holds 46 m/s level at 98 % throttle);
- ``climb_max_mps``: the steady climb at the slowest usable speed and full throttle, commanded
  more than the aircraft can give;
- ``descent_max_mps``: the steepest commanded descent the autopilot holds at the slowest usable
  speed with the speed within ``HOLD_TOL_MPS`` (steeper, the aircraft gains speed);
- ``bank_max_deg`` / ``turn_rate_max_radps``: the largest bank and the steady turn rate of a
  level turn commanded at far more than the aircraft can turn, at the slowest usable speed;
- ``roll_rate_max_degps``: the largest roll rate in a reversal from that turn to the other side;
- ``accel_max_mps2``: the largest dV/dt (averaged over 1 s) of a full-throttle run from the
  slowest usable speed commanded to 120 m/s at a climb rate of 0, the autopilot's acceleration
  limit lifted. Not level: the total-energy autopilot pitches down for the speed (the PC-7 dives
  at 15-23 m/s, docs/airframes.md). Level, the flight path held first (speed
  weight 0), it is 1.05 m/s^2 for the J3Cub at 10 kg (the ``j3cub`` preset's 1.7 rests on this
  run's 2.5) and 0.64 m/s^2 for the PC-7 full (docs/airframes.md);
- ``tau_*_s``: 63 % rise times of the airspeed, climb-rate and bank responses to a step.

And the energy limit (:func:`full_throttle_climb`, a preset's ``jsbsim.excess_power``): at a
commanded airspeed and water load, the steady climb at full throttle with the speed held (the
autopilot's speed weight raised to ``SPEED_FIRST_WEIGHT``, so that the climb takes the shortfall),
which is the specific excess power P_s = climb + (v / g) dv/dt at steady speed; where the pitch
limit stops the climb before the power does (the speed then settles above the command), the
steepest climb held with the speed (bisection) and P_s as flown where the speed settled.

Units: SI; degrees where the name says so.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from fire_uav_common.scenario import Airframe
from fire_uav_common.scenario.airframes import G_MPS2

from .base import Command, FlightState
from .jsbsim_backend import FT_M, JsbsimModel

__all__ = [
    "MeasuredEnvelope",
    "fly",
    "full_throttle_climb",
    "holds_level",
    "level_top_speed_mps",
    "lowest_trim_speed_mps",
    "measure_envelope",
]

DT_S = 0.01
HOLD_TOL_MPS = 0.7  # [m/s] a held speed: within this of the command over the tail
CLIMB_TOL_MPS = 0.3  # [m/s] a held climb rate: within this of the command over the tail
TAIL_S = 5.0  # [s] the tail over which a steady value is read
Z0_M = 200.0
V_HOLD_SEARCH_MAX_MPS = 80.0  # [m/s] the slowest-held-speed search gives up here
V_TOP_SEARCH_MAX_MPS = 150.0  # [m/s] the level top speed search gives up here
SPEED_FIRST_WEIGHT = 10.0  # the TECS speed weight of the energy-limit measurement (module doc)


def _unlimited(af: Airframe, v_floor_mps: float) -> Airframe:
    """The preset with the autopilot's speed floor at ``v_floor_mps`` and the limits on speed,
    climb, descent and acceleration lifted (the autopilot clips its commands to them: the aircraft
    sets these figures), and the energy limit's split too (it would limit the climb to its own
    table). The bank limit and roll rate stay the preset's: the autopilot flies them by design
    (the bank figures are the flown ones under those limits)."""
    return dataclasses.replace(
        af,
        v_max_mps=max(af.v_max_mps, 120.0),
        climb_max_mps=20.0,
        descent_max_mps=20.0,
        accel_max_mps2=20.0,
        min_speed_factor=1.0,
        v_stall_mps=min(af.v_stall_mps, v_floor_mps),
        jsbsim=dataclasses.replace(af.jsbsim, v_floor_mps=v_floor_mps, excess_power=None),
    )


def fly(
    af: Airframe, commands: list[tuple[Command, float]], v0_mps: float, water_kg: float
) -> tuple[list[FlightState], list[float]]:
    """Launch at ``v0_mps`` (level, trimmed) and fly each (command, seconds) in turn; the states
    and the elevator commands of every substep."""
    m = JsbsimModel(af)
    s = m.launch(FlightState(0.0, 0.0, Z0_M, 0.0, water_kg=water_kg), Command(v0_mps, 0.0, 0.0), DT_S)
    rng = [np.random.default_rng(0)]
    out: list[FlightState] = []
    elev: list[float] = []
    for cmd, seconds in commands:
        for _ in range(round(seconds / DT_S)):
            (s,) = m.step([s], [cmd], DT_S, rng)
            out.append(s)
            assert m.fdm is not None
            elev.append(float(m.fdm["fcs/elevator-cmd-norm"]))
    return out, elev


def lowest_trim_speed_mps(af: Airframe, water_kg: float, lo: float = 10.0, hi: float = 40.0) -> float:
    """The lowest airspeed [m/s] JSBSim's trim finds level flight at (bisection to 0.1 m/s)."""

    def trims(v: float) -> bool:
        m = JsbsimModel(af)
        fdm = m._new_fdm(DT_S)
        fdm["ic/terrain-elevation-ft"] = -10000.0
        fdm["ic/h-sl-ft"] = Z0_M / FT_M
        fdm["ic/vt-fps"] = v / FT_M
        m.fdm = fdm
        m._set_water(water_kg)
        fdm.run_ic()
        fdm["propulsion/set-running"] = -1
        try:
            fdm["simulation/do_simple_trim"] = 1
        except RuntimeError:
            return False
        return True

    if not trims(hi):
        return math.nan
    while hi - lo > 0.1:
        mid = 0.5 * (lo + hi)
        if trims(mid):
            hi = mid
        else:
            lo = mid
    return hi


def holds_level(af: Airframe, v_mps: float, water_kg: float, seconds: float = 30.0) -> bool:
    """Whether the autopilot holds level flight at ``v_mps`` (module doc: ``v_hold_min_mps``)."""
    a = _unlimited(af, v_mps)
    traj, elev = fly(a, [(Command(v_mps, 0.0, 0.0), seconds)], v_mps + 2.0, water_kg)
    n = round(TAIL_S / DT_S)
    return (
        all(abs(f.airspeed_mps - v_mps) < HOLD_TOL_MPS for f in traj[-n:])
        and all(abs(f.climb_mps) < CLIMB_TOL_MPS for f in traj[-n:])
        and all(abs(e) < 0.999 for e in elev[-n:])
    )


def level_top_speed_mps(af: Airframe, v_held_mps: float, water_kg: float) -> float:
    """The fastest airspeed [m/s], in 1 m/s steps up from ``v_held_mps`` (one it holds), that the
    autopilot holds level (:func:`holds_level`; module doc: ``v_level_max_mps``)."""
    v = float(v_held_mps)
    while v + 1.0 <= V_TOP_SEARCH_MAX_MPS and holds_level(af, v + 1.0, water_kg):
        v += 1.0
    return v


def _tau_s(values: list[float], start: float, end: float) -> float:
    """63 % rise time [s] of ``values`` (one per substep) from ``start`` toward ``end``."""
    goal = start + 0.632 * (end - start)
    for i, x in enumerate(values):
        if (x - goal) * (end - start) >= 0.0:
            return (i + 1) * DT_S
    return math.nan


@dataclass(frozen=True)
class MeasuredEnvelope:
    """What the aircraft flies under the autopilot (module doc); ``water_kg`` the load aboard."""

    water_kg: float
    v_trim_min_mps: float
    v_hold_min_mps: float
    v_level_max_mps: float
    climb_max_mps: float
    descent_max_mps: float
    bank_max_deg: float
    turn_rate_max_radps: float
    roll_rate_max_degps: float
    accel_max_mps2: float
    tau_airspeed_s: float
    tau_climb_s: float
    tau_bank_s: float


def measure_envelope(af: Airframe, water_kg: float, v_slow_mps: float | None = None) -> MeasuredEnvelope:
    """Measure every figure of :class:`MeasuredEnvelope` for the preset's aircraft (module doc).

    Climb, descent and turn are flown at ``v_slow_mps`` (None: the autopilot's floor
    ``jsbsim.v_floor_mps``, the slowest the backend flies in a mission)."""
    n = round(TAIL_S / DT_S)
    v_trim = lowest_trim_speed_mps(af, water_kg)
    v_hold = math.ceil(v_trim if math.isfinite(v_trim) else af.jsbsim.v_stall_mps)
    while v_hold < V_HOLD_SEARCH_MAX_MPS and not holds_level(af, float(v_hold), water_kg):
        v_hold += 1
    v_hold_f = float(v_hold)
    v_slow = af.jsbsim.v_floor_mps if v_slow_mps is None else v_slow_mps
    a = _unlimited(af, v_slow)
    # the level top speed; and the acceleration of a full-throttle run from the slowest usable speed
    v_top = level_top_speed_mps(af, v_hold_f, water_kg)
    traj, _ = fly(a, [(Command(120.0, 0.0, 0.0), 90.0)], v_slow, water_kg)
    v = np.array([f.airspeed_mps for f in traj])
    k = round(1.0 / DT_S)
    accel = float(np.max((v[k:] - v[:-k]) / 1.0))
    # speed step response at mid range (not saturated by the acceleration limit as much)
    v_lo, v_hi = v_slow + 2.0, min(v_slow + 5.0, v_top - 1.0)
    traj, _ = fly(a, [(Command(v_lo, 0.0, 0.0), 20.0), (Command(v_hi, 0.0, 0.0), 30.0)], v_lo, water_kg)
    tau_v = _tau_s([f.airspeed_mps for f in traj[2000:]], traj[1999].airspeed_mps, v_hi)
    # climb at full throttle at the slowest usable speed
    traj, _ = fly(a, [(Command(v_slow, 10.0, 0.0), 40.0)], v_slow, water_kg)
    climb = float(np.mean([f.climb_mps for f in traj[-n:]]))
    tau_c = _tau_s([f.climb_mps for f in traj], 0.0, climb)
    # the steepest descent held at that speed, in 0.1 m/s steps
    descent = 0.0
    for sink10 in range(1, 101):
        sink = sink10 / 10.0
        traj, _ = fly(a, [(Command(v_slow, -sink, 0.0), 40.0)], v_slow, water_kg)
        ok = all(abs(f.airspeed_mps - v_slow) < HOLD_TOL_MPS for f in traj[-n:]) and all(
            abs(f.climb_mps + sink) < CLIMB_TOL_MPS for f in traj[-n:]
        )
        if not ok:
            break
        descent = sink
    # the hardest level turn at the slowest usable speed, then a reversal
    traj, _ = fly(
        a, [(Command(v_slow, 0.0, 5.0), 20.0), (Command(v_slow, 0.0, -5.0), 20.0)], v_slow, water_kg
    )
    bank = max(abs(f.bank_rad) for f in traj)
    turn = float(np.mean([abs(f.turn_rate_radps) for f in traj[2000 - n : 2000]]))
    phis = np.array([f.bank_rad for f in traj])
    roll = float(np.max(np.abs(np.diff(phis[2000:])))) / DT_S
    phi_ss = float(np.mean(phis[2000 - n : 2000]))
    tau_b = _tau_s(list(phis[:2000]), 0.0, phi_ss)
    return MeasuredEnvelope(
        water_kg=water_kg,
        v_trim_min_mps=v_trim,
        v_hold_min_mps=v_hold_f,
        v_level_max_mps=v_top,
        climb_max_mps=climb,
        descent_max_mps=descent,
        bank_max_deg=math.degrees(bank),
        turn_rate_max_radps=turn,
        roll_rate_max_degps=math.degrees(roll),
        accel_max_mps2=accel,
        tau_airspeed_s=tau_v,
        tau_climb_s=tau_c,
        tau_bank_s=tau_b,
    )


def full_throttle_climb(af: Airframe, v_mps: float, water_kg: float) -> tuple[float, float]:
    """(steepest climb held [m/s], specific excess power P_s [m/s]) at full throttle and the
    commanded airspeed ``v_mps`` (module doc: the energy limit). 50 s flown, the last 10 s read."""
    a = _unlimited(af, min(v_mps, af.jsbsim.v_floor_mps))
    a = dataclasses.replace(a, jsbsim=dataclasses.replace(a.jsbsim, tecs_speed_weight=SPEED_FIRST_WEIGHT))
    k = round(10.0 / DT_S)

    def climb_at(climb_c: float) -> tuple[float, float, float]:
        traj, _ = fly(a, [(Command(v_mps, climb_c, 0.0), 50.0)], v_mps, water_kg)
        vs = np.array([f.airspeed_mps for f in traj[-k:]])
        cs = np.array([f.climb_mps for f in traj[-k:]])
        vdot = (vs[-1] - vs[0]) / (k * DT_S)
        return float(vs.mean()), float(cs.mean()), float(cs.mean() + vs.mean() * vdot / G_MPS2)

    v, climb, ps = climb_at(15.0)
    if abs(v - v_mps) < HOLD_TOL_MPS:
        return climb, ps
    lo, hi = 0.0, climb  # the pitch limit first: bisect the steepest climb held with the speed
    while hi - lo > 0.05:
        mid = 0.5 * (lo + hi)
        v_m, c_m, _ = climb_at(mid)
        if abs(v_m - v_mps) < HOLD_TOL_MPS and abs(c_m - mid) < CLIMB_TOL_MPS:
            lo = mid
        else:
            hi = mid
    return lo, ps
