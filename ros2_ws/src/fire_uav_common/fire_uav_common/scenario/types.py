"""The scenario's frozen dataclasses and value sets (docs/scenario.md); built by the readers.

Attribute names are the YAML keys, units in the names; positions in the ``map`` frame (x east,
y north, z up, metres). The outage key ``from`` is the attribute ``from_``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from fire_uav_common.errors import ArgumentError, ScheduleError
from fire_uav_common.terrain import Lake, Terrain

#: Standard fuel model numbers the raster fire supports: Anderson (1982) / Albini (1976) 1-13
#: and Scott & Burgan (2005) 40 (101-204).
FUEL_MODELS = (
    *range(1, 14),
    *range(101, 110),
    *range(121, 125),
    *range(141, 150),
    *range(161, 166),
    *range(181, 190),
    *range(201, 205),
)
#: ``fires.raster.landscape.crown`` values (fire_world_sim.fires.behavior.CROWN_METHODS)
CROWN_METHODS = ("none", "finney")
#: ``fires.raster.wind_limit`` values (fire_world_sim.fires.rothermel reads them from here)
WIND_LIMITS = ("behave", "andrews2013", "none")
#: ``fires.model`` values
FIRE_MODELS = ("analytic", "raster")
#: ``fires.drop_model`` values: today's disc of ``drop_radius_m`` (every burning cell in it goes
#: out), or a ground pattern with a coverage per cell (fire_world_sim.drop_pattern)
DROP_MODELS = ("disc", "pattern")
#: ``mission.tactic`` values: head attack (fastest front first), flank attack from an anchor, or
#: auto (head or flank per fire from the head's intensity: ``fire_uav_agent.tactics.auto_choice``)
TACTICS = ("head", "flank", "auto")
#: standard gravity [m/s^2]
G_MPS2 = 9.80665
#: ``mission.prior_fires`` values
PRIOR_FIRES_MODES = ("unknown", "known")
#: ``mission.lake_sequence`` values: none (every refilling UAV descends to scoop, FF IV-D b), or stack
#: (a fixed-wing over analytic fires descends only while it holds the lake, the others hold in a
#: stack above it: ``fire_uav_agent.lake_sequence``; and one UAV of a layer at a time in its landing
#: entry area; docs/airframes.md). Not "off": YAML reads a bare ``off`` as false
LAKE_SEQUENCES = ("none", "stack")
#: ``mission.vertical_band`` values: how the avoider judges two UAVs' heights (fire_uav_agent.separation):
#: ``now`` (the height difference now), ``predicted`` (over its horizon, each height straight at its
#: vertical speed), or ``auto`` (the default: predicted for ff_paper's unicycle, now for a
#: fixed-wing; docs/suppression.md "Vertical rates in the avoider")
VERTICAL_BANDS = ("auto", "now", "predicted")


@dataclass(frozen=True)
class Area:
    """Mission area [m], map frame."""

    x_min_m: float
    x_max_m: float
    y_min_m: float
    y_max_m: float

    @property
    def width_m(self) -> float:
        return self.x_max_m - self.x_min_m

    @property
    def height_m(self) -> float:
        return self.y_max_m - self.y_min_m

    def contains(self, x_m: float, y_m: float) -> bool:
        return self.x_min_m <= x_m <= self.x_max_m and self.y_min_m <= y_m <= self.y_max_m


@dataclass(frozen=True)
class Timing:
    control_period_s: float = 0.1
    physics_period_s: float = 0.01
    max_duration_s: float = 900.0

    @property
    def substeps(self) -> int:
        """Physics substeps per control step."""
        return round(self.control_period_s / self.physics_period_s)


@dataclass(frozen=True)
class Vehicle:
    """Vehicle limits and payload (FF II-B, Eq. 5)."""

    v_stall_mps: float = 44.7
    v_max_mps: float = 100.0
    vz_max_mps: float = 100.0
    omega_max_radps: float = 10.0
    water_capacity_kg: float = 2000.0
    flight_height_m: float = 30.0
    process_noise_sigma: float = 1.0
    refill_height_m: float = 15.0
    refill_speed_margin_mps: float = 10.0
    refill_rate_kgps: float = 400.0
    landing_height_m: float = 1.0
    command_timeout_s: float = 3.0
    collision_radius_m: float = 3.0  # [m] two airborne vehicles closer than this (3-D) both crash; 0 = off
    drop_flow_lps: float = 1000.0  # [L/s] tank flow rate of a drop (fires.drop_model: pattern only)


@dataclass(frozen=True)
class ExcessPower:
    """An aircraft's energy limit at full throttle: the specific excess power P_s = (T - D) v / W
    [m/s] and the steepest climb it holds [m/s], tabulated over airspeed and water aboard (measured
    under the ``jsbsim`` backend's autopilot: ``fire_world_sim.vehicles.jsbsim_envelope``,
    docs/airframes.md).

    Energy conservation bounds what the aircraft flies: climb rate + (v / g) dv/dt <= P_s(v, m)
    (the specific energy rate; A. A. Lambregts, "Vertical flight path and speed control autopilot
    design using total energy principles", AIAA 83-2239, 1983; B&M Eq. 9.18's airspeed response
    under it). Where the pitch limit bounds the climb before the power does (the PC-7 full of water
    near its 46.8 m/s floor) ``climb_mps`` is below ``power_mps``. :meth:`split` is the order in
    which the autopilot spends it, climb first: world and agents read the same rule.

    In a turn at load factor n the induced drag, k n^2 W^2 / q for a parabolic polar, grows by
    (n^2 - 1) times its level value, which lowers P_s by B(v) m (n^2 - 1) (B&M sec. 4.3's drag
    polar; the turn's n = 1 / cos(phi), B&M Eq. 9.14's coordinated turn). With P_s = A(v) / m -
    B(v) m at each speed (thrust power less parasitic drag over the weight, less the induced part),
    the lightest and heaviest rows (``mass_kg``: the aircraft's mass at each water row, as JSBSim
    weighs it) give B(v), and B(v) = c / v (the induced power per weight falls as 1 / v) with c
    their median over the speeds (at 75-80 m/s the table's rows do not follow the polar); no
    ``mass_kg``: no turn term.

    ``speeds_mps`` and ``water_kg`` ascending; ``climb_mps[i][j]`` and ``power_mps[i][j]`` at
    ``water_kg[i]`` and ``speeds_mps[j]``; bilinear between the points, the end values beyond them.
    ``margin``: the share of the measured figures the split spends (the throttle keeps a reserve to
    track with). A positive figure is multiplied by it, a negative one (a hard turn full of water,
    where the aircraft at full throttle must descend or slow) divided by it: either way the figure
    spent is the more cautious one, a smaller climb or a steeper required descent.
    """

    speeds_mps: tuple[float, ...]
    water_kg: tuple[float, ...]
    climb_mps: tuple[tuple[float, ...], ...]
    power_mps: tuple[tuple[float, ...], ...]
    mass_kg: tuple[float, ...] = ()
    margin: float = 0.9

    def __post_init__(self) -> None:
        ns, nw = len(self.speeds_mps), len(self.water_kg)
        rows = (self.climb_mps, self.power_mps)
        if ns < 2 or nw < 1 or any(len(t) != nw or any(len(r) != ns for r in t) for t in rows):
            raise ArgumentError(f"ExcessPower: tables must be {nw} x {ns} (water x speed), with >= 2 speeds")
        if self.mass_kg and (len(self.mass_kg) != nw or nw < 2):
            raise ArgumentError(
                f"ExcessPower: mass_kg needs one mass per water row (>= 2), got {self.mass_kg}"
            )
        for axis in (self.speeds_mps, self.water_kg, self.mass_kg):
            if any(axis[k + 1] <= axis[k] for k in range(len(axis) - 1)):
                raise ArgumentError(f"ExcessPower: axis must be ascending, got {axis}")

    @staticmethod
    def _bracket(axis: tuple[float, ...], x: float) -> tuple[int, float]:
        if len(axis) == 1 or x <= axis[0]:
            return 0, 0.0
        if x >= axis[-1]:
            return len(axis) - 2, 1.0
        i = max(k for k in range(len(axis) - 1) if axis[k] <= x)
        return i, (x - axis[i]) / (axis[i + 1] - axis[i])

    def _row(self, row: tuple[float, ...], v_mps: float) -> float:
        j, f = self._bracket(self.speeds_mps, v_mps)
        return row[j] + f * (row[j + 1] - row[j])

    def _at(self, table: tuple[tuple[float, ...], ...], v_mps: float, water_kg: float) -> float:
        if len(self.water_kg) == 1:
            return self._row(table[0], v_mps)
        i, f = self._bracket(self.water_kg, water_kg)
        lo, hi = self._row(table[i], v_mps), self._row(table[i + 1], v_mps)
        return lo + f * (hi - lo)

    def induced_mps(self, v_mps: float, water_kg: float) -> float:
        """B(v) m = c m / v: the part of P_s [m/s] that level flight's induced drag takes (class doc)."""
        if not self.mass_kg:
            return 0.0
        i, f = self._bracket(self.water_kg, water_kg)
        m = self.mass_kg[i] + f * (self.mass_kg[i + 1] - self.mass_kg[i])
        return self._induced_c * m / max(v_mps, 1.0)

    @property
    def _induced_c(self) -> float:
        """c of B(v) = c / v (the induced power 2 k W / (rho S v) per weight falls as 1 / v): the
        median over the table's speeds of B(v) v, each B(v) from the lightest and heaviest rows,
        P_s = A / m - B m at two masses."""
        m1, m2 = self.mass_kg[0], self.mass_kg[-1]
        cs = sorted(
            max((p2 - p1 * m1 / m2) / (m1 * m1 / m2 - m2), 0.0) * v
            for v, p1, p2 in zip(self.speeds_mps, self.power_mps[0], self.power_mps[-1], strict=True)
        )
        k = len(cs)
        return 0.5 * (cs[(k - 1) // 2] + cs[k // 2])

    def _spend(self, x: float) -> float:
        return self.margin * x if x > 0.0 else x / self.margin

    def climb_max_at(self, v_mps: float, water_kg: float, load_factor: float = 1.0) -> float:
        """The steepest climb held at full throttle, airspeed v and load factor n [m/s] (the table,
        times ``margin``, less the turn's induced drag)."""
        turn = self.induced_mps(v_mps, water_kg) * (max(load_factor, 1.0) ** 2 - 1.0)
        return self._spend(self._at(self.climb_mps, v_mps, water_kg) - turn)

    def power_at(self, v_mps: float, water_kg: float, load_factor: float = 1.0) -> float:
        """P_s at full throttle, airspeed v and load factor n [m/s] (the table, times ``margin``,
        less the turn's induced drag)."""
        turn = self.induced_mps(v_mps, water_kg) * (max(load_factor, 1.0) ** 2 - 1.0)
        return self._spend(self._at(self.power_mps, v_mps, water_kg) - turn)

    def split(
        self,
        v_mps: float,
        water_kg: float,
        climb_c_mps: float,
        accel_c_mps2: float,
        climb_now_mps: float | None = None,
        load_factor: float = 1.0,
        v_floor_mps: float = 0.0,
    ) -> tuple[float, float]:
        """(climb command [m/s], acceleration command [m/s^2]) within the energy limit, climb first.

        The climb command is kept within :meth:`climb_max_at`; the acceleration within what the
        rest of P_s gives, (g / v) (P_s - climb), ``climb_now_mps`` the climb that spends it (None:
        the climb command as limited, where the autopilot splits its commands; the modelled climb
        where the agent predicts the speed). A climb command is cut to level flight at most, and
        the aircraft slows where P_s is short of that; at or below ``v_floor_mps`` (the slowest it
        flies) the speed is held first: the climb is cut to P_s, a descent if P_s < 0 (a hard turn
        full of water), and the acceleration is not below 0."""
        v = max(v_mps, 1.0)
        n = load_factor
        climb = min(climb_c_mps, max(self.climb_max_at(v, water_kg, n), min(climb_c_mps, 0.0)))
        p_s = self.power_at(v, water_kg, n)
        if v_mps <= v_floor_mps and accel_c_mps2 >= 0.0 and climb > p_s:
            climb = p_s  # the speed first at the floor
        spent = climb if climb_now_mps is None else climb_now_mps
        accel = min(accel_c_mps2, G_MPS2 * (p_s - spent) / v)
        if v_mps <= v_floor_mps:
            accel = max(accel, min(accel_c_mps2, 0.0))
        return climb, accel


@dataclass(frozen=True)
class JsbsimSetup:
    """What the ``jsbsim`` backend flies for a preset: a JSBSim aircraft and its autopilot's gains.

    ``aircraft``: a model shipped with the ``jsbsim`` wheel (``aircraft/<name>/<name>.xml``);
    ``v_floor_mps``: the lowest airspeed [m/s] the autopilot holds on this aircraft (its own
    slow-flight margin, which may exceed the preset's lowest commanded speed: docs/airframes.md);
    ``v_stall_mps``: the aircraft's own lowest 1 g speed [m/s] (its bank limit at low speed);
    ``water_pointmass``: index of the aircraft's point mass that carries the water (its weight is
    ``base_pointmass_lbs`` + ``water_weight_scale`` x water: a scale below 1 carries the preset's tank
    on an aircraft with a smaller payload); the gains are the autopilot's (fire_world_sim.vehicles.autopilot):
    roll PID on aileron, rudder on sideslip, pitch PD on elevator, the total-energy controller's
    proportional / integral gains on throttle (``tecs_*_t``) and on pitch (``tecs_*_d``), and the
    speed loop ``k_speed_1ps`` that turns an airspeed error into a commanded acceleration, ``k_load``
    the elevator's easing of a pull that would turn the course beyond the envelope,
    ``load_protection`` the load-factor limit on the pitch command and the bank before the pull;
    ``excess_power`` the aircraft's measured energy limit (:class:`ExcessPower`: the autopilot splits
    its commands by it, and the agents on ``jsbsim`` model it), ``model_error_mps`` the agents'
    model error against this aircraft where the preset gives none.
    """

    aircraft: str = "J3Cub"
    v_floor_mps: float = 20.0
    v_stall_mps: float = 17.0
    water_pointmass: int = 0
    base_pointmass_lbs: float = 0.0
    water_weight_scale: float = 1.0
    # JSBSim's own trim at launch; False: the backend trims by flying (JSBSim's trim fails for the
    # PC-7 at every speed and load, after up to 7 s of CPU: fire_world_sim.vehicles.jsbsim_backend)
    simple_trim: bool = True
    bank_margin_deg: float = 5.0
    pitch_max_deg: float = 15.0
    pitch_rate_max_degps: float = 10.0
    kp_roll: float = 3.0
    ki_roll: float = 0.1
    kd_roll: float = 0.5
    k_beta: float = 2.0
    kp_pitch: float = 3.0
    kd_pitch: float = 0.6
    tecs_kp_t: float = 2.0
    tecs_ki_t: float = 0.6
    tecs_kp_d: float = 0.6
    tecs_ki_d: float = 1.0
    k_speed_1ps: float = 0.5
    throttle_min: float = 0.1
    tecs_speed_weight: float = 0.5
    k_load: float = 6.0
    # the load-factor protection on the pitch command and the bank (autopilot module doc); False:
    # the elevator's easing alone (k_load), which holds the J3Cub within its envelope and not the PC-7
    load_protection: bool = False
    # the aircraft's energy limit, measured; None: the autopilot splits no command by it (the J3Cub)
    excess_power: ExcessPower | None = None
    # [m/s] the agents' model error against this aircraft, where the preset's model_error_mps is 0
    # (a preset flown by coordinated_turn too: there the model is exact)
    model_error_mps: float = 0.0


@dataclass(frozen=True)
class Airframe:
    """Envelope of a fixed-wing airframe for the ``coordinated_turn`` model (B&M ch. 9).

    ``v_stall_mps`` is the 1 g stall speed at the full-load mass ``empty_mass_kg +
    water_capacity_kg``; at mass m and load factor n the stall speed is
    ``v_stall * sqrt(n m / m_full)`` (lift = n W at C_L,max). The autopilot never commands less
    than ``min_speed_factor * v_stall_mps`` (the usual 1.3 V_S margin of approach speeds).
    Time constants are those of the first-order responses of airspeed, flight-path angle and
    bank (B&M Eq. 9.18-9.20 with their autopilot loops closed).
    """

    v_stall_mps: float
    v_max_mps: float
    bank_max_deg: float
    roll_rate_max_degps: float
    climb_max_mps: float
    descent_max_mps: float
    accel_max_mps2: float
    tau_airspeed_s: float
    tau_gamma_s: float
    tau_bank_s: float
    empty_mass_kg: float
    water_capacity_kg: float
    refill_rate_kgps: float
    min_speed_factor: float = 1.3
    jsbsim: JsbsimSetup = field(default_factory=JsbsimSetup)  # what the jsbsim backend flies
    drop_flow_lps: float = 5.0  # [L/s] tank flow rate of a drop (fires.drop_model: pattern)
    # [m/s] rms error of the first-order model above (the agents' on-board one) against the
    # aircraft in speed and climb rate; 0: the aircraft is that model (coordinated_turn)
    model_error_mps: float = 0.0
    # the aircraft's energy limit the agents' model flies by (``jsbsim.excess_power`` on the ``jsbsim``
    # backend, set by the scenario loader; None elsewhere: ``coordinated_turn`` has no energy limit)
    excess_power: ExcessPower | None = None

    @property
    def v_min_mps(self) -> float:
        """Lowest commanded airspeed [m/s] (the agents' v_stall)."""
        return self.min_speed_factor * self.v_stall_mps

    @property
    def scoop_run_m(self) -> float:
        """The straight run [m] over water that fills the empty tank: the scoop time
        water_capacity / refill_rate flown at the lowest commanded speed (the slowest pass)."""
        return self.v_min_mps * self.water_capacity_kg / self.refill_rate_kgps

    @property
    def bank_max_rad(self) -> float:
        return math.radians(self.bank_max_deg)

    def turn_rate_max_radps(self, v_mps: float) -> float:
        """Highest coordinated turn rate at airspeed ``v_mps``: g tan(phi_max) / v (B&M Eq. 9.14)."""
        return G_MPS2 * math.tan(self.bank_max_rad) / max(v_mps, 1e-6)

    def stall_speed_mps(self, water_kg: float, load_factor: float = 1.0) -> float:
        """Stall speed [m/s] at the water load and load factor n (lift n W = q S C_L,max)."""
        m_full = self.empty_mass_kg + self.water_capacity_kg
        m = self.empty_mass_kg + max(0.0, water_kg)
        return self.v_stall_mps * math.sqrt(max(load_factor, 0.0) * m / m_full)


@dataclass(frozen=True)
class Pose:
    """Start pose: position [m] map frame, yaw [rad] ccw from +x."""

    x_m: float = 50.0
    y_m: float = 250.0
    z_m: float = 0.0
    yaw_rad: float = -math.pi / 2


@dataclass(frozen=True)
class Spacing:
    dx_m: float = 0.0
    dy_m: float = 30.0


@dataclass(frozen=True)
class Uavs:
    count: int = 5
    first: Pose = field(default_factory=Pose)
    spacing: Spacing = field(default_factory=Spacing)
    takeoff_interval_s: float = 2.0
    vehicle_model: str = "ff_paper"  # VEHICLE_MODELS (fire_uav_common.scenario.airframes)
    airframe: Airframe | None = None  # the fixed-wing models' envelope; None for ff_paper


@dataclass(frozen=True)
class GpsSpec:
    rate_hz: float = 10.0
    sigma_m: float = 3.0
    p_valid: float = 0.9


@dataclass(frozen=True)
class AltimeterSpec:
    rate_hz: float = 25.0
    sigma_m: float = 1.5
    p_valid: float = 0.8
    max_range_m: float = 40.0


@dataclass(frozen=True)
class GyroSpec:
    rate_hz: float = 100.0
    sigma_radps: float = 0.3
    p_valid: float = 0.7


@dataclass(frozen=True)
class FireSensorSpec:
    rate_hz: float = 10.0
    range_m: float = 70.0
    position_sigma_m: float = 2.0
    extent_sigma_m: float = 1.0
    p_valid: float = 1.0


@dataclass(frozen=True)
class Sensors:
    gps: GpsSpec = field(default_factory=GpsSpec)
    altimeter: AltimeterSpec = field(default_factory=AltimeterSpec)
    gyro: GyroSpec = field(default_factory=GyroSpec)
    fire: FireSensorSpec = field(default_factory=FireSensorSpec)


@dataclass(frozen=True)
class AnalyticFire:
    """FF IV-A Gaussian fire: centre [m] drifting at (vx_mps, vy_mps) from start_s [s]."""

    x_m: float
    y_m: float
    sigma_m: float
    vx_mps: float = 0.0
    vy_mps: float = 0.0
    start_s: float = 0.0


@dataclass(frozen=True)
class Origin:
    x_m: float = 0.0
    y_m: float = 0.0


@dataclass(frozen=True)
class FuelPatch:
    x_min_m: float
    x_max_m: float
    y_min_m: float
    y_max_m: float
    fuel_model: int


#: a wind grid's speed unit -> metres per second per unit (WindNinja's ``output_speed_units``)
SPEED_UNITS = {"mps": 1.0, "mph": 0.44704, "kph": 1.0 / 3.6, "kts": 1852.0 / 3600.0}
DEFAULT_SPEED_UNITS = "mph"  # WindNinja's default output_speed_units


@dataclass(frozen=True)
class WindGrid:
    """Where a gridded 20-ft wind is: a WindNinja ``*_vel.asc`` (``speed_path``) with its
    ``*_ang.asc`` (``direction_path``), or a 2-band GeoTIFF (``speed_path``, no
    ``direction_path``); absolute paths. ``speed_units``: a key of :data:`SPEED_UNITS`."""

    speed_path: str
    direction_path: str | None = None
    speed_units: str = DEFAULT_SPEED_UNITS


@dataclass(frozen=True)
class Wind:
    """Piecewise-constant wind from start_s [s]: speed [m/s], direction it blows TOWARD [deg ccw from +x].

    With ``grid`` (a landscape only) each cell's 20-ft wind is the grid's, resampled to the cell
    (:mod:`.wind_grid`); ``speed_mps`` / ``direction_deg`` are then the domain wind (given, or
    the mean wind vector of the grid over the burnable cells), which the vehicles drift with.
    """

    start_s: float
    speed_mps: float
    direction_deg: float
    grid: WindGrid | None = None


@dataclass(frozen=True)
class Ignition:
    x_m: float
    y_m: float
    start_s: float = 0.0


@dataclass(frozen=True)
class Moistures:
    """Fuel moisture by class [fraction of dry mass] (1 h, 10 h, 100 h dead; live herbaceous, woody)."""

    m_1h: float = 0.06
    m_10h: float = 0.08
    m_100h: float = 0.10
    m_herb: float = 0.75
    m_woody: float = 0.60


@dataclass(frozen=True)
class RasterLandscape:
    """The raster fire's ground from a LANDFIRE landscape (``fires.raster.landscape``).

    ``source``: the landscape file or directory (absolute). ``window``: (x_min, y_min, x_max,
    y_max) in the landscape's projected metres, or None for all of it. The map frame's origin is
    the window's (or the landscape's) south-west corner, ``projected_origin`` in projected metres:
    map (x, y) = projected (x, y) - projected_origin. Wind entries are then the 20-ft wind;
    each cell's midflame wind is it times the cell's wind adjustment factor.
    """

    source: str
    name: str = ""
    window: tuple[float, float, float, float] | None = None
    cell_size_m: float | None = None
    projected_origin: tuple[float, float] = (0.0, 0.0)
    moisture: Moistures = field(default_factory=Moistures)
    foliar_moisture: float = 1.0
    crown: str = "finney"
    min_lake_diameter_m: float = 60.0


@dataclass(frozen=True)
class Raster:
    cell_size_m: float = 5.0
    nx: int = 200
    ny: int = 200
    origin: Origin = field(default_factory=Origin)
    fuel_model: int = 1
    fuel_patches: tuple[FuelPatch, ...] = ()
    moisture: float = 0.06
    wind: tuple[Wind, ...] = (Wind(0.0, 0.0, 0.0),)
    ignitions: tuple[Ignition, ...] = ()
    wet_duration_s: float = 600.0
    spread_factor: float = 1.0
    wind_limit: str = "behave"  # behave | andrews2013 | none (fire_world_sim.fires.rothermel)
    landscape: RasterLandscape | None = None  # the grid, fuels, terrain and water from a landscape


@dataclass(frozen=True)
class Fires:
    model: str = "analytic"
    extinction_sigma_m: float = 2.0
    drop_radius_m: float | None = None
    drop_model: str = "disc"  # DROP_MODELS: disc of drop_radius_m, or a ground pattern
    analytic: tuple[AnalyticFire, ...] = ()
    raster: Raster | None = None


@dataclass(frozen=True)
class LinkOutage:
    """Directed link ``from_id -> to_id`` down for sim time in [start_s, end_s) [s]: the scenario's
    ``comms.outages`` (YAML keys ``from``, ``to``), the runner's ``--outage`` and the agents' peer
    link all hold this one type."""

    from_id: int
    to_id: int
    start_s: float
    end_s: float

    def __post_init__(self) -> None:
        if self.from_id < 0 or self.to_id < 0:
            raise ScheduleError(f"outage ids must be >= 0, got {self.from_id} -> {self.to_id}")
        if not self.end_s >= self.start_s:
            raise ScheduleError(f"outage end_s {self.end_s} before start_s {self.start_s}")


@dataclass(frozen=True)
class Comms:
    loss_probability: float = 0.05
    outages: tuple[LinkOutage, ...] = ()


@dataclass(frozen=True)
class MissionSettings:
    crash_threshold_steps: int = 10
    grid_resolution_m: float = 5.0
    sigma_water_m: float = 40.0
    sigma_landing_m: float = 10.0
    use_safety_band: bool = True
    safety_radius_m: float = 10.0
    monitors_per_fire: int = 0
    search_first: bool = False
    tactic: str = "auto"  # raster suppression: head | flank | auto (TACTICS; fire_uav_agent.tactics); auto: docs/studies.md
    prior_fires: str = "unknown"  # known: agents start with noisy estimates of every fire (FF III-C, IV-D c)
    prior_position_sigma_m: float = 10.0  # [m] noise of a known fire's initial centre estimate
    prior_extent_sigma_fraction: float = 0.2  # [-] relative noise of a known fire's initial extent
    # stack: one fixed-wing at a time low over the lake (LAKE_SEQUENCES; opt-in, docs/airframes.md)
    lake_sequence: str = "none"
    # [s] after the last known fire is out, the fleet sweeps the area (our addition to FF IV-D d,
    # fire_uav_agent.mission): it lands once its sensors have covered every point of the area since,
    # after post_search_s at the least and post_search_max_s at the most
    post_search_s: float = 45.0
    post_search_max_s: float = 300.0
    vertical_band: str = "auto"  # VERTICAL_BANDS: the avoider's height check


@dataclass(frozen=True)
class Scenario:
    """A validated scenario; ``path`` is the file it came from ('' when built from a dict)."""

    name: str
    area: Area
    description: str = ""
    seed: int = 0
    terrain: Terrain = field(default_factory=Terrain)
    lakes: tuple[Lake, ...] = ()
    timing: Timing = field(default_factory=Timing)
    vehicle: Vehicle = field(default_factory=Vehicle)
    uavs: Uavs = field(default_factory=Uavs)
    sensors: Sensors = field(default_factory=Sensors)
    fires: Fires = field(default_factory=Fires)
    comms: Comms = field(default_factory=Comms)
    mission: MissionSettings = field(default_factory=MissionSettings)
    path: str = ""
    notes: tuple[str, ...] = field(default=(), compare=False)  # what the loader left out, for the log

    def uav_start_poses(self, count: int | None = None) -> list[tuple[float, float, float, float]]:
        """Start poses (x_m, y_m, z_m, yaw_rad) of UAVs 0..count-1 (default ``uavs.count``)."""
        n = self.uavs.count if count is None else count
        if n < 0:
            raise ArgumentError(f"count must be >= 0, got {n}")
        f, s = self.uavs.first, self.uavs.spacing
        return [(f.x_m + i * s.dx_m, f.y_m + i * s.dy_m, f.z_m, f.yaw_rad) for i in range(n)]

    def takeoff_time_s(self, uav_id: int) -> float:
        """Earliest sim time [s] UAV ``uav_id`` may take off (FF IV-D a)."""
        return uav_id * self.uavs.takeoff_interval_s
