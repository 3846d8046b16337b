"""A 6-DoF airframe from the JSBSim flight dynamics library, flown by an autopilot.

JSBSim (https://github.com/JSBSim-Team/jsbsim, LGPL 2.1; PyPI ``jsbsim``) integrates the rigid-body
equations of one of its shipped aircraft (``Airframe.jsbsim.aircraft``); the autopilot of
:mod:`.autopilot` stands for the vehicle's own and turns the agent's command (v, v_z, omega)
into aileron, elevator, rudder and throttle at every physics substep. One instance of this class
holds one ``jsbsim.FGFDMExec``: the world makes one per vehicle (``per_vehicle``), so several
aircraft live in one process, each independent of the others.

Frames. The map frame is x east, y north, z up [m], yaw counter-clockwise from +x; JSBSim flies
on the WGS84 ellipsoid with latitude, longitude, altitude above sea level and a heading psi
clockwise from north. The map is a local tangent plane at the reference point lat = lon = 0:
x = a lon, y = a (1 - e^2) lat (the radii of curvature east and north there), z = altitude,
yaw = pi/2 - psi. Over a mission area of kilometres the plane's error is below a centimetre.
JSBSim's own ground is put far below (``ic/terrain-elevation-ft``), so its landing gear never
touches: the world's terrain is the floor and the world lands the vehicle (``VehicleSim``).

Water is the weight of one of the aircraft's point masses (``inertia/pointmass-weight-lbs[i]``),
set at launch and whenever the world's tank changes (refill, drop). Wind is JSBSim's
``atmosphere/wind-north-fps`` / ``wind-east-fps`` (the air's velocity). No process noise: the
vehicles' noise streams are not drawn.

FlightState out: position and heading as above; ``airspeed_mps`` the true airspeed,
``climb_mps`` the rate of climb, ``bank_rad`` the roll angle (positive into a counter-clockwise
turn, as ``coordinated_turn``), ``turn_rate_radps`` the turn rate of the course through the air
over the substep (the flight path's turn: for a level coordinated turn g tan(phi) / v),
``yaw_rate_radps`` the heading change over the substep divided by its length (the map
frame's yaw rate, which the gyro reads), ``water_kg`` the tank.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np
from fire_uav_common.angles import wrap_angle
from fire_uav_common.scenario import Airframe

from ..errors import ConfigError, SequenceError
from .autopilot import AirState, Autopilot
from .base import Command, FlightState

FT_M = 0.3048
LB_KG = 0.45359237
#: WGS84 semi-major axis [m] and first eccentricity squared
WGS84_A_M = 6378137.0
WGS84_E2 = 6.69437999014e-3
_EAST_M_PER_RAD = WGS84_A_M  # N cos(lat) at lat 0
_NORTH_M_PER_RAD = WGS84_A_M * (1.0 - WGS84_E2)  # meridian radius M at lat 0
#: JSBSim's ground, far below any map terrain [ft]
_GROUND_FT = -10000.0
#: the fallback trim (JsbsimModel._fly_to_trim): the height above the takeoff it flies at [m] and
#: its longest flight [s]
FLY_TRIM_HEIGHT_M = 300.0
FLY_TRIM_MAX_S = 60.0
#: the gust gradient distance over which a change of the world's wind reaches the aircraft [m]:
#: the longest of the 1 - cos discrete gust of 14 CFR 25.341(a) (H = 350 ft)
WIND_GRADIENT_M = 350.0 * FT_M


def map_to_geodetic(x_m: float, y_m: float) -> tuple[float, float]:
    """(lat, lon) [rad] of a map point on the tangent plane at lat = lon = 0."""
    return y_m / _NORTH_M_PER_RAD, x_m / _EAST_M_PER_RAD


def geodetic_to_map(lat_rad: float, lon_rad: float) -> tuple[float, float]:
    """(x, y) [m] of a geodetic point (the inverse of :func:`map_to_geodetic`)."""
    return lon_rad * _EAST_M_PER_RAD, lat_rad * _NORTH_M_PER_RAD


def yaw_to_psi(yaw_rad: float) -> float:
    """Map yaw (ccw from east) to JSBSim heading (cw from north) [rad, in [0, 2 pi)]."""
    return (math.pi / 2 - yaw_rad) % (2 * math.pi)


class JsbsimModel:
    """One JSBSim aircraft and its autopilot (the ``jsbsim`` value of ``uavs.vehicle_model``)."""

    name = "jsbsim"
    immediate = False
    per_vehicle = True  # the world makes one instance per vehicle: the FDM holds the state

    def __init__(self, airframe: Airframe) -> None:
        try:
            import jsbsim
        except ImportError as e:  # pragma: no cover - a requirement of the project
            raise ConfigError("uavs.vehicle_model: jsbsim needs the 'jsbsim' package") from e
        self._jsbsim = jsbsim
        self.af = airframe
        self.js = airframe.jsbsim
        self.fdm = None
        self.autopilot: Autopilot | None = None
        self._last: FlightState | None = None
        self._water_kg = 0.0
        self._dt_s = 0.0
        self._wind_to: tuple[float, float] | None = None
        self._wind_from = self._wind_now = (0.0, 0.0)
        self._wind_s_m = 0.0

    # --- set-up ---------------------------------------------------------------------------
    def _new_fdm(self, dt_s: float):
        jsbsim = self._jsbsim
        jsbsim.FGJSBBase().debug_lvl = 0  # no banner on stdout
        fdm = jsbsim.FGFDMExec(None)
        fdm.set_debug_level(0)
        if not fdm.load_model(self.js.aircraft):
            raise ConfigError(f"uavs.airframe.jsbsim.aircraft: JSBSim has no aircraft {self.js.aircraft!r}")
        fdm.set_dt(dt_s)
        return fdm

    def launch(self, state: FlightState, command: Command, dt_s: float = 0.01) -> FlightState:
        """Airborne at the commanded speed (within the envelope and the aircraft's floor), wings
        level, trimmed for level flight at the takeoff pose.

        JSBSim's own trim (``simulation/do_simple_trim``) finds the throttle and pitch of level
        flight for the J3Cub; for the PC-7 it fails at every speed and load tried (46.8-60 m/s,
        0-3,000 kg, engine running or spooled up for 30 s: "udot doesn't appear to be
        trimmable"; JSBSim's turboprop). Launched untrimmed, from throttle 0 and pitch 0, the
        PC-7 full of water sank 14 m in its first 8 s, which at the takeoff point is 12 s flown
        along the world's terrain floor. So where the trim fails, or is not tried
        (``jsbsim.simple_trim`` False: the PC-7, whose failing trim costs up to 7 s of CPU), the
        aircraft is trimmed by flying it (:meth:`_fly_to_trim`) and then put at the takeoff pose."""
        self._dt_s = dt_s
        v = Autopilot(self.af, 0.5, 0.0).speed_command_mps(command.v_lin_mps)
        fdm = self._initial_fdm(state, v, dt_s)
        trimmed = self.js.simple_trim
        if trimmed:
            try:
                fdm["simulation/do_simple_trim"] = 1
            except RuntimeError:  # JSBSim's "Trim Failed"
                trimmed = False
        if trimmed:
            self.autopilot = Autopilot(self.af, fdm["fcs/throttle-cmd-norm"], fdm["attitude/theta-rad"])
        else:
            self.autopilot = self._fly_to_trim(state, v, dt_s)
        self._last = self._state(state.water_kg)
        return self._last

    def _initial_fdm(self, state: FlightState, v_mps: float, dt_s: float):
        """A new FDM (this instance's from now on) at ``state``'s pose and water, level at
        ``v_mps``, its engines running."""
        fdm = self._new_fdm(dt_s)
        lat, lon = map_to_geodetic(state.x_m, state.y_m)
        fdm["ic/terrain-elevation-ft"] = _GROUND_FT
        fdm["ic/lat-geod-rad"] = lat
        fdm["ic/long-gc-rad"] = lon
        fdm["ic/h-sl-ft"] = state.z_m / FT_M
        fdm["ic/vt-fps"] = v_mps / FT_M
        fdm["ic/psi-true-rad"] = yaw_to_psi(state.yaw_rad)
        self.fdm = fdm
        self._set_water(state.water_kg)
        if not fdm.run_ic():
            raise ConfigError(f"uavs.airframe.jsbsim.aircraft: {self.js.aircraft} did not initialise")
        fdm["propulsion/set-running"] = -1
        return fdm

    def _fly_to_trim(self, state: FlightState, v_mps: float, dt_s: float) -> Autopilot:
        """Trim by flying: the aircraft starts ``FLY_TRIM_HEIGHT_M`` above the takeoff pose, its
        autopilot holds (v, 0, 0) from throttle 0.5 and pitch 0 until the climb rate has stayed
        within 0.2 m/s, the airspeed within 0.5 m/s of ``v_mps``, the heading within 0.5 deg of the
        takeoff's and the bank within 1 deg for 2 s (at most
        ``FLY_TRIM_MAX_S``), holding the takeoff heading (a turn rate of 0.3 1/s times the heading
        error: unheld, the PC-7 full of water drifted 4 deg), and then it is moved to the takeoff
        position with its speed, attitude, engine and autopilot as flown. The
        PC-7 at its 46.8 m/s floor settles in 16-30 s (0-3,000 kg of water). An aircraft that
        cannot hold the speed level is launched as it is at the limit."""
        self._initial_fdm(dataclasses.replace(state, z_m=state.z_m + FLY_TRIM_HEIGHT_M), v_mps, dt_s)
        fdm = self.fdm
        assert fdm is not None
        ap = Autopilot(self.af, 0.5, 0.0)
        need, steady = int(round(2.0 / dt_s)), 0
        for _ in range(int(round(FLY_TRIM_MAX_S / dt_s))):
            # a heading hold (turn rate 0.3 1/s x the heading error): the takeoff heading kept
            yaw = math.pi / 2 - fdm["attitude/psi-rad"]
            err = math.remainder(state.yaw_rad - yaw, 2 * math.pi)
            omega = 0.3 * err
            u = ap.update(self.air_state(), v_mps, 0.0, omega, dt_s, state.water_kg)
            fdm["fcs/aileron-cmd-norm"] = u.aileron
            fdm["fcs/elevator-cmd-norm"] = u.elevator
            fdm["fcs/rudder-cmd-norm"] = u.rudder
            fdm["fcs/throttle-cmd-norm"] = u.throttle
            fdm.run()
            a = self.air_state()
            level = (
                abs(a.climb_mps) < 0.2
                and abs(a.airspeed_mps - v_mps) < 0.5
                and abs(err) < math.radians(0.5)
                and abs(a.bank_rad) < math.radians(1.0)
            )
            steady = steady + 1 if level else 0
            if steady >= need:
                break
        self._move_to(state)
        return ap

    def _set_water(self, water_kg: float) -> None:
        assert self.fdm is not None
        self.fdm[f"inertia/pointmass-weight-lbs[{self.js.water_pointmass}]"] = (
            self.js.base_pointmass_lbs + self.js.water_weight_scale * max(water_kg, 0.0) / LB_KG
        )
        self._water_kg = water_kg

    def _reposition(self, s: FlightState) -> None:
        """Move the aircraft to a state the world changed (the terrain floor lifted it): its
        height (JSBSim's ``position/lat-geod-rad`` is read-only: writing it does nothing, so the
        latitude stays; the floor moves only the height)."""
        fdm = self.fdm
        assert fdm is not None
        lat, lon = map_to_geodetic(s.x_m, s.y_m)
        fdm["position/lat-geod-rad"] = lat
        fdm["position/long-gc-rad"] = lon
        fdm["position/h-sl-ft"] = s.z_m / FT_M

    def _move_to(self, s: FlightState) -> None:
        """Move the aircraft to ``s``'s map position (speed and attitude as they are). JSBSim takes
        a new latitude only as the geocentric one (``position/lat-gc-rad``): the geodetic latitude
        phi at height h is at geocentric atan2((N (1 - e^2) + h) sin phi, (N + h) cos phi), N the
        prime vertical radius a / sqrt(1 - e^2 sin^2 phi) (WGS84)."""
        fdm = self.fdm
        assert fdm is not None
        lat, lon = map_to_geodetic(s.x_m, s.y_m)
        sin_lat = math.sin(lat)
        n = WGS84_A_M / math.sqrt(1.0 - WGS84_E2 * sin_lat * sin_lat)
        h = s.z_m
        fdm["position/lat-gc-rad"] = math.atan2((n * (1.0 - WGS84_E2) + h) * sin_lat, (n + h) * math.cos(lat))
        fdm["position/long-gc-rad"] = lon
        fdm["position/h-sl-ft"] = s.z_m / FT_M

    def _state(self, water_kg: float) -> FlightState:
        fdm = self.fdm
        assert fdm is not None
        x, y = geodetic_to_map(fdm["position/lat-geod-rad"], fdm["position/long-gc-rad"])
        psidot = fdm["velocities/psidot-rad_sec"]
        return FlightState(
            x_m=x,
            y_m=y,
            z_m=fdm["position/h-sl-ft"] * FT_M,
            yaw_rad=wrap_angle(math.pi / 2 - fdm["attitude/psi-rad"]),
            airspeed_mps=fdm["velocities/vtrue-fps"] * FT_M,
            climb_mps=fdm["velocities/h-dot-fps"] * FT_M,
            bank_rad=-fdm["attitude/phi-rad"],  # map frame: positive banks into a ccw turn
            turn_rate_radps=-psidot,
            yaw_rate_radps=-psidot,
            water_kg=water_kg,
        )

    def air_state(self) -> AirState:
        fdm = self.fdm
        assert fdm is not None
        return AirState(
            airspeed_mps=fdm["velocities/vtrue-fps"] * FT_M,
            climb_mps=fdm["velocities/h-dot-fps"] * FT_M,
            bank_rad=fdm["attitude/phi-rad"],
            pitch_rad=fdm["attitude/theta-rad"],
            sideslip_rad=fdm["aero/beta-rad"],
            roll_rate_radps=fdm["velocities/p-rad_sec"],
            pitch_rate_radps=fdm["velocities/q-rad_sec"],
            load_factor=fdm["accelerations/Nz"],
        )

    # --- the substep ------------------------------------------------------------------------
    def step(
        self,
        states: Sequence[FlightState],
        commands: Sequence[Command],
        dt_s: float,
        rngs: Sequence[np.random.Generator],
        wind_mps: tuple[float, float] = (0.0, 0.0),
    ) -> list[FlightState]:
        """One substep of this instance's aircraft: ``states`` holds exactly its one state."""
        if len(states) != 1 or len(commands) != 1:
            raise SequenceError(f"jsbsim: one aircraft per model instance, got {len(states)} states")
        s, cmd = states[0], commands[0]
        if self.fdm is None or self.autopilot is None:
            self.launch(s, cmd, dt_s)
        fdm, ap = self.fdm, self.autopilot
        assert fdm is not None and ap is not None
        if dt_s != self._dt_s:
            fdm.set_dt(dt_s)
            self._dt_s = dt_s
        last = self._last
        if last is not None and (s.x_m, s.y_m, s.z_m) != (last.x_m, last.y_m, last.z_m):
            self._reposition(s)
        if s.water_kg != self._water_kg:
            self._set_water(s.water_kg)
        wind_e, wind_n = self._gust(wind_mps, dt_s)
        fdm["atmosphere/wind-east-fps"] = wind_e / FT_M
        fdm["atmosphere/wind-north-fps"] = wind_n / FT_M
        u = ap.update(self.air_state(), cmd.v_lin_mps, cmd.v_z_mps, cmd.omega_z_radps, dt_s, self._water_kg)
        fdm["fcs/aileron-cmd-norm"] = u.aileron
        fdm["fcs/elevator-cmd-norm"] = u.elevator
        fdm["fcs/rudder-cmd-norm"] = u.rudder
        fdm["fcs/throttle-cmd-norm"] = u.throttle
        yaw0 = self._last.yaw_rad if self._last is not None else s.yaw_rad
        course0 = self._air_course_rad()
        fdm.run()
        new = self._state(s.water_kg)
        # the gyro's yaw rate: the heading change over this substep; the turn rate: the change of
        # the course through the air (the flight path's turn, which the bank and lift bound)
        yaw_rate = math.remainder(new.yaw_rad - yaw0, 2 * math.pi) / dt_s
        turn = math.remainder(self._air_course_rad() - course0, 2 * math.pi) / dt_s
        self._last = dataclasses.replace(new, yaw_rate_radps=yaw_rate, turn_rate_radps=turn)
        return [self._last]

    def _gust(self, wind_mps: tuple[float, float], dt_s: float) -> tuple[float, float]:
        """The wind the aircraft flies in [m/s, (east, north)]: the world's, reached from the wind
        it flew in before (calm at launch: JSBSim's trim zeroes the wind) as a 1 - cos discrete
        gust (14 CFR 25.341(a)) over the gradient distance ``WIND_GRADIENT_M`` flown through the air.

        The world's wind is piecewise constant in time (``fires.raster.wind``, a weather
        schedule); applied as a step it is a sharp-edged gust, which no autopilot can meet: a
        2.5 m/s veer in a 35 deg turn at 23 m/s raised the load factor from 1.3 to 1.9 within one
        10 ms substep, a course turn that needs a 54 deg bank (grass_brush_hill seed 2, 480 s)."""
        target = (float(wind_mps[0]), float(wind_mps[1]))
        if target != self._wind_to:
            self._wind_from, self._wind_to, self._wind_s_m = self._wind_now, target, 0.0
        if self._wind_s_m < WIND_GRADIENT_M:
            v = self._last.airspeed_mps if self._last is not None else 0.0
            self._wind_s_m += max(v, 1.0) * dt_s
            f = 0.5 * (1.0 - math.cos(math.pi * min(self._wind_s_m / WIND_GRADIENT_M, 1.0)))
            (e0, n0), (e1, n1) = self._wind_from, self._wind_to
            self._wind_now = (e0 + f * (e1 - e0), n0 + f * (n1 - n0))
        return self._wind_now

    def _air_course_rad(self) -> float:
        """Direction of the velocity through the air [rad, map frame: ccw from east]."""
        fdm = self.fdm
        assert fdm is not None
        ve = fdm["velocities/v-east-fps"] - fdm["atmosphere/wind-east-fps"]
        vn = fdm["velocities/v-north-fps"] - fdm["atmosphere/wind-north-fps"]
        return math.atan2(vn, ve)
