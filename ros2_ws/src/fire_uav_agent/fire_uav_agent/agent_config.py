"""What an agent knows a priori: :class:`AgentConfig`, :class:`GuidanceConfig`, and the scenario mapping.

:class:`AgentConfig` holds the scenario's own frozen sub-configs (``timing``, ``vehicle``,
``sensors``, ``mission``: ``fire_uav_common.scenario``) instead of copies of their fields, so a
new scenario field reaches the agent without being copied by hand. The agent never reads the
scenario's ``fires`` (the truth), only ``fires.drop_radius_m`` (the footprint of its own drop), the
drop model and, for pattern drops, the raster fire's fuel map (the ground, not the fire:
``coverage_levels``).

Units are in the field names: [m], [s], [m/s], [rad], [kg]; positions in the map frame.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

from fire_uav_common import scenario as sc
from fire_uav_common.drop_coverage import CoverageLevels, coverage_levels_of
from fire_uav_common.scenario import LinkOutage
from fire_uav_common.terrain import Lake, Terrain

from .coverage import ControlGains, VehicleLimits
from .errors import ConfigError
from .separation import SeparationConfig, detect_range_m

__all__ = ["DEFAULT_DROP_RADIUS_M", "AgentConfig", "GuidanceConfig", "config_from_scenario"]

#: [m] drop footprint radius when the scenario leaves ``fires.drop_radius_m`` null (the raster default)
DEFAULT_DROP_RADIUS_M = 20.0


@dataclass(frozen=True)
class GuidanceConfig:
    """Named constants of the agent's guidance (FF Eqs. 8-15 around the Lloyd controller)."""

    lake_approach_margin_m: float = 150.0  # [m] fly low and slow within lake radius + this (FF IV-D b)
    refill_height_fraction: float = 0.5  # [-] approach height = this * vehicle.refill_height_m
    refill_speed_fraction: float = 0.3  # [-] speed cap = v_stall + this * vehicle.refill_speed_margin_mps
    land_approach_radius_m: float = 120.0  # [m] start descending this close to the start point
    land_flat_fraction: float = 0.3  # [-] hold the lowest height inside this fraction of the radius
    land_height_fraction: float = 0.5  # [-] lowest approach height = this * vehicle.landing_height_m
    touchdown_agl_fraction: float = 0.8  # [-] below this * landing_height_m above ground: touch down
    touchdown_sink_mps: float = 0.5  # [m/s] sink rate commanded at touch-down (v_lin = 0: the world lands it)
    drop_radius_fraction: float = 0.7  # [-] release within this * drop_radius_m (EKF error margin)
    consensus_negative_range_max_m: float = 50.0  # [m] cap of the "no fire here" range
    consensus_negative_range_fraction: float = 0.7  # [-] "no fire here" range = this * sensor range
    monitor_speed_margin_mps: float = 5.0  # [m/s] perimeter monitors fly at v_stall + this
    touchdown_radius_m: float = 2.5  # [m] touch down only this close to the takeoff point (FF IV-D d)
    go_around_radius_m: float = 25.0  # [m] this close to the takeoff point, not lined up: fly straight out
    go_around_heading_rad: float = 0.5  # [rad] "lined up": heading within this of the bearing to the point
    # FF mode (analytic fires): altitude layers around the flight height, our addition: at
    # 100 m/s a peer closes 20 m per control step and turns at 10 rad/s, so the velocity-obstacle
    # filter alone let two UAVs crossing at a drop point pass at 3.6 m (8 UAVs); two layers 14 m
    # apart (23 and 37 m AGL for 30 m, inside the 40 m altimeter range) keep even-odd pairs apart
    # in 3-D, the filter the rest. 1 layer: everyone at the flight height (FF as printed).
    ff_layers: int = 2
    ff_layer_step_m: float = 14.0  # [m] > separation.vertical_m + altitude error

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            name, value = f.name, getattr(self, f.name)
            if not value >= 0:
                raise ConfigError(f"GuidanceConfig.{name} must be >= 0, got {value}")
        if not 0 < self.land_flat_fraction < 1:
            raise ConfigError(
                f"GuidanceConfig.land_flat_fraction must be in (0, 1), got {self.land_flat_fraction}"
            )


@dataclass(frozen=True)
class AgentConfig:
    """Everything an agent knows a priori (scenario parts + parameters). Units in names."""

    uav_id: int
    uav_count: int
    seed: int = 0
    area_m: tuple[float, float, float, float] = (0.0, 600.0, 0.0, 600.0)  # x_min, x_max, y_min, y_max
    terrain: Terrain = field(default_factory=Terrain)
    lakes: tuple[Lake, ...] = ()
    start_pose: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)  # x, y, z [m], yaw [rad]
    takeoff_interval_s: float = 2.0  # scenario uavs.takeoff_interval_s
    timing: sc.Timing = field(default_factory=sc.Timing)
    vehicle: sc.Vehicle = field(default_factory=sc.Vehicle)
    sensors: sc.Sensors = field(default_factory=sc.Sensors)
    mission: sc.MissionSettings = field(default_factory=sc.MissionSettings)
    airframe: sc.Airframe | None = None  # scenario uavs.airframe: the fixed-wing envelope (None: ff_paper)
    loss_probability: float = 0.05  # scenario comms.loss_probability, or the runner's override
    outages: tuple[LinkOutage, ...] = ()  # scenario comms.outages, or the runner's override
    drop_radius_m: float = (
        DEFAULT_DROP_RADIUS_M  # water footprint radius (world hits within max(this, sigma))
    )
    # the tank's drop is a ground pattern (scenario fires.drop_model: pattern), whose coverage falls
    # with the release height and speed: raster drop runs low and slow (guidance.Guide)
    pattern_drops: bool = False
    # pattern drops: the run's last leg along the front (guidance.Guide._drop_leg); off by default:
    # on grass_running_tanker it put fewer cells out than the straight run (docs/airframes.md)
    drop_leg: bool = False
    # pattern drops on a raster fire: the coverage level [gal/100 ft^2] the fuel map's fuel needs per
    # place (scenario fires.raster's fuel_model and fuel_patches, or its landscape's fuel layer: the
    # ground, known before the fire as the terrain is); None: not known, every drop run is flown
    coverage_levels: CoverageLevels | None = None
    gains: ControlGains = field(default_factory=ControlGains)
    guidance: GuidanceConfig = field(default_factory=GuidanceConfig)
    separation: SeparationConfig = field(default_factory=SeparationConfig)
    avoidance: bool = True  # turn-rate-limited avoidance in every phase (:mod:`.separation`)
    # known-fires mode (scenario mission.prior_fires: known): the dispatch briefing, (x_m, y_m, extent_m)
    # per fire, the same for every agent (parameter prior_fires); () = find the fires with the sensors
    prior_fires: tuple[tuple[float, float, float], ...] = ()
    extinction_extent_m: float = 2.0  # FF III-C step 4
    monitor_circling: bool = False  # monitors circle (PM VI-E baseline) instead of importance-based
    monitor_alpha: float = 1.0  # PM Eq. 7 heterogeneity-adjusting factor
    perimeter_every_steps: int = 10  # publish the monitor's PerimeterMap every n steps (~1 Hz)
    front_every_steps: int = 10  # raster: publish the front picture (FireFront) every n steps (~1 Hz)

    def __post_init__(self) -> None:
        if not 0 <= self.uav_id < self.uav_count:
            raise ConfigError(
                f"uav_id must be in 0..uav_count-1, got uav_id={self.uav_id}, uav_count={self.uav_count}"
            )
        if not self.control_period_s > 0 or not self.physics_period_s > 0:
            raise ConfigError("control_period_s and physics_period_s must be > 0")
        if self.crash_threshold_steps < 1:
            raise ConfigError(f"crash_threshold_steps must be >= 1, got {self.crash_threshold_steps}")
        if not 0.0 <= self.loss_probability <= 1.0:
            raise ConfigError(f"loss_probability must be in [0, 1], got {self.loss_probability}")
        for k, f in enumerate(self.prior_fires):
            if len(f) != 3 or not all(math.isfinite(v) for v in f) or not f[2] > 0:
                raise ConfigError(f"prior_fires[{k}] must be finite (x_m, y_m, extent_m > 0), got {f!r}")

    # --- views of the sub-configs (read-only) --------------------------------------------------
    @property
    def control_period_s(self) -> float:
        """[s] control period T (scenario timing)."""
        return self.timing.control_period_s

    @property
    def physics_period_s(self) -> float:
        """[s] physics / EKF substep (scenario timing)."""
        return self.timing.physics_period_s

    @property
    def limits(self) -> VehicleLimits:
        """FF Eq. 5 limits of the scenario's vehicle."""
        return VehicleLimits.of(self.vehicle)

    @property
    def fire_range_m(self) -> float:
        """[m] fire sensor range (scenario sensors.fire.range_m)."""
        return self.sensors.fire.range_m

    @property
    def crash_threshold_steps(self) -> int:
        return self.mission.crash_threshold_steps

    @property
    def monitors_per_fire(self) -> int:
        return self.mission.monitors_per_fire

    @property
    def fires_known(self) -> bool:
        """Known-fires mode (FF III-C): the fleet lands as soon as its fires are out, no sweep."""
        return self.mission.prior_fires == "known"

    @property
    def search_first(self) -> bool:
        return self.mission.search_first


def _outage(o: Any) -> LinkOutage:
    return LinkOutage(int(o.from_id), int(o.to_id), float(o.start_s), float(o.end_s))


def _pose4(p) -> tuple[float, float, float, float]:
    """(x_m, y_m, z_m, yaw_rad) as floats."""
    x, y, z, yaw = (float(v) for v in p)
    return (x, y, z, yaw)


def config_from_scenario(
    scenario: sc.Scenario,
    uav_id: int,
    uav_count: int | None = None,
    seed: int | None = None,
    loss_probability: float | None = None,
    outages: tuple[LinkOutage, ...] | None = None,
    crash_threshold_steps: int | None = None,
    monitors_per_fire: int | None = None,
    **agent_options: Any,
) -> AgentConfig:
    """Build the agent's a-priori config from a ``fire_uav_common.scenario.Scenario``.

    Reads only area, terrain, lakes, timing, vehicle, sensors, uavs (own start pose, airframe), comms,
    mission, the drop footprint and model and the raster fire's fuel map -- never the fires' ignitions,
    wind or moisture. Arguments not None override the scenario
    (runner flags); ``agent_options`` are further :class:`AgentConfig` fields (monitor_alpha, ...).
    """
    n = int(uav_count if uav_count is not None else scenario.uavs.count)
    if not 0 <= uav_id < n:  # before the start poses are indexed by it
        raise ConfigError(f"uav_id must be in 0..uav_count-1, got uav_id={uav_id}, uav_count={n}")
    a = scenario.area
    mission = scenario.mission
    if crash_threshold_steps is not None:
        mission = dataclasses.replace(mission, crash_threshold_steps=int(crash_threshold_steps))
    if monitors_per_fire is not None:
        mission = dataclasses.replace(mission, monitors_per_fire=int(monitors_per_fire))
    drop = scenario.fires.drop_radius_m
    if "separation" not in agent_options:
        # mission.vertical_band: the avoider's height check (separation module doc); auto: predicted
        # for FF's unicycle, whose commanded v_z is the flown one, the height now for a fixed-wing
        band = mission.vertical_band
        predicted = band == "predicted" or (band == "auto" and scenario.uavs.airframe is None)
        sep = SeparationConfig(vertical_rates=predicted)
        af = scenario.uavs.airframe
        if af is not None:
            # a fixed-wing sees its peers as far as its turning horizon reaches at its top speed
            # (separation.detect_range_m: the tanker 1,822 m, small_uav 308 m, the J3Cub 364 m);
            # the turn rate as agent_core's avoider has it, capped by the vehicle's omega_max
            rate = min(scenario.vehicle.omega_max_radps, af.turn_rate_max_radps(af.v_max_mps))
            # the vertical resolution (separation module doc) on coordinated_turn only: measured
            # there (grass_brush_hill seed 3, small_uav: 5.1 -> 12.8 m; ff_two_fires seeds 1-3 kept
            # >= 10 m); on jsbsim the J3Cub's ff_two_fires seed 2 came to 6.4 m with it (13.9 m
            # without; docs/suppression.md, "Vertical resolution on fixed-wings")
            resolve = scenario.uavs.vehicle_model == "coordinated_turn"
            sep = dataclasses.replace(
                sep, detect_m=detect_range_m(sep, af.v_max_mps, rate), vertical_resolution=resolve
            )
        agent_options = {**agent_options, "separation": sep}
    return AgentConfig(
        uav_id=uav_id,
        uav_count=n,
        seed=int(seed if seed is not None else scenario.seed),
        area_m=(float(a.x_min_m), float(a.x_max_m), float(a.y_min_m), float(a.y_max_m)),
        terrain=scenario.terrain,
        lakes=tuple(scenario.lakes),
        start_pose=_pose4(scenario.uav_start_poses(n)[uav_id]),
        takeoff_interval_s=float(scenario.uavs.takeoff_interval_s),
        timing=scenario.timing,
        vehicle=scenario.vehicle,
        sensors=scenario.sensors,
        mission=mission,
        airframe=scenario.uavs.airframe,
        loss_probability=float(
            loss_probability if loss_probability is not None else scenario.comms.loss_probability
        ),
        outages=tuple(outages) if outages is not None else tuple(_outage(o) for o in scenario.comms.outages),
        drop_radius_m=float(drop) if drop else DEFAULT_DROP_RADIUS_M,
        pattern_drops=scenario.fires.drop_model == "pattern",
        coverage_levels=(
            coverage_levels_of(scenario.fires.raster) if scenario.fires.drop_model == "pattern" else None
        ),
        **agent_options,
    )
