"""Vehicle models and airframe presets of ``uavs.vehicle_model`` / ``uavs.airframe`` (docs/airframes.md).

``ff_paper`` is FF's unicycle (FF Eq. 4) with the ``vehicle:`` section's limits, unchanged.
``coordinated_turn`` is the kinematic fixed-wing guidance model of Beard & McLain, *Small
Unmanned Aircraft* (2012), ch. 9, whose envelope an :class:`Airframe` preset fills. The preset
also sets the limits the agents plan with (:func:`envelope_vehicle`): the lowest commanded
speed, the highest, the climb rate and the turn rate ``g tan(phi_max) / v_min`` (B&M Eq. 9.14,
the coordinated-turn condition), so that world and agents read one envelope.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from .fields import _Ctx, _mapping, _num, _str
from .types import G_MPS2, Airframe, ExcessPower, JsbsimSetup, Vehicle

__all__ = [
    "AIRFRAMES",
    "DEFAULT_AIRFRAME",
    "DEFAULT_AIRFRAMES",
    "G_MPS2",
    "ExcessPower",
    "JsbsimSetup",
    "VEHICLE_MODELS",
    "Airframe",
    "envelope_vehicle",
    "read_airframe",
]

#: ``uavs.vehicle_model`` values (fire_world_sim.vehicles has one backend per name)
VEHICLE_MODELS = ("ff_paper", "coordinated_turn", "jsbsim")
#: the preset ``coordinated_turn`` flies when ``uavs.airframe`` is not given
DEFAULT_AIRFRAME = "small_uav"
#: per fixed-wing model, the preset it flies when ``uavs.airframe`` is not given: ``jsbsim`` flies
#: the J3Cub, whose own envelope is ``j3cub``'s (docs/airframes.md)
DEFAULT_AIRFRAMES = {"coordinated_turn": DEFAULT_AIRFRAME, "jsbsim": "j3cub"}


#: The PC-7's energy limit under the world's autopilot (``jsbsim_envelope.full_throttle_climb``,
#: ``scripts/jsbsim_envelope.py --airframe tanker --excess-power``; docs/airframes.md): at each water load and commanded airspeed, full throttle, the steepest
#: climb held with the speed within 0.7 m/s, and P_s (the same where the speed holds; at 46.8 and
#: 50 m/s, where the 15 deg pitch limit bounds the climb first, the climb flown where the speed
#: settled, at 49.5-52.4 m/s). Full of water it climbs 3.2 m/s at 55 m/s, 0.7 m/s at 75 m/s; in
#: a 45 deg turn full the induced drag takes 2.3-3.7 m/s more of it (ExcessPower: P_s 0.1 m/s at best).
# fmt: off
PC7_EXCESS_POWER = ExcessPower(
    speeds_mps=(46.8, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0),
    water_kg=(0.0, 1000.0, 2000.0, 3000.0),
    mass_kg=(1494.5, 1840.7, 2187.1, 2529.7),  # JSBSim's inertia/weight-lbs with the water aboard
    climb_mps=(
        (7.27, 8.95, 9.76, 9.16, 7.76, 4.74, 1.22, -2.55),
        (4.87, 6.70, 6.87, 6.37, 5.63, 4.45, 1.40, -2.00),
        (2.44, 4.42, 4.79, 4.38, 3.75, 2.93, 1.82, -0.65),
        (0.00, 2.12, 3.21, 2.85, 2.31, 1.60, 0.71, -0.41),
    ),
    power_mps=(
        (8.35, 9.67, 9.76, 9.16, 7.76, 4.74, 1.22, -2.55),
        (6.46, 7.03, 6.87, 6.37, 5.63, 4.45, 1.40, -2.00),
        (4.60, 4.92, 4.79, 4.38, 3.75, 2.93, 1.82, -0.65),
        (2.78, 3.27, 3.21, 2.85, 2.31, 1.60, 0.71, -0.41),
    ),
)
# fmt: on

#: Presets; their figures and sources are listed in docs/airframes.md.
AIRFRAMES: dict[str, Airframe] = {
    # A small fixed-wing UAV of the Aerosonde class (B&M appendix E: 13.5 kg, cruise 25 m/s)
    # carrying a 10 kg water payload.
    "small_uav": Airframe(
        v_stall_mps=12.0,
        v_max_mps=30.0,
        bank_max_deg=45.0,
        roll_rate_max_degps=90.0,
        climb_max_mps=5.0,
        descent_max_mps=5.0,
        accel_max_mps2=3.0,
        tau_airspeed_s=1.5,
        tau_gamma_s=0.8,
        tau_bank_s=0.3,
        empty_mass_kg=15.0,
        water_capacity_kg=10.0,
        refill_rate_kgps=2.0,
        # jsbsim: the lightest powered aircraft shipped with JSBSim, the Piper J-3 Cub; the water
        # takes the pilot's point mass (docs/airframes.md: what it cannot fly of this envelope)
        jsbsim=JsbsimSetup(aircraft="J3Cub", v_floor_mps=20.0, v_stall_mps=17.0, water_pointmass=0),
        drop_flow_lps=5.0,  # a 2 s release (a choice: no drop test of this class is published)
    ),
    # The Piper J-3 Cub as JSBSim's model flies it under the world's autopilot, measured by
    # scripts/jsbsim_envelope.py (fire_world_sim.vehicles.jsbsim_envelope; docs/airframes.md), at
    # small_uav's 10 kg of water: the envelope the agents plan with on ``jsbsim`` by default.
    "j3cub": Airframe(
        v_stall_mps=16.5,  # JSBSim's trim finds level 1 g flight down to 16.5 m/s
        min_speed_factor=22.0 / 16.5,  # 22 m/s: the slowest speed it holds in a 37 deg level turn
        v_max_mps=30.0,  # an operating limit: it reaches about 40 m/s at full throttle
        bank_max_deg=40.0,  # the autopilot commands 35 deg (5 deg margin); flown at most 38.0 deg
        roll_rate_max_degps=40.0,  # reversal at 22 m/s: 40.5 deg/s
        climb_max_mps=1.4,  # full throttle at 22 m/s
        descent_max_mps=1.4,  # the steepest held at 22 m/s (idle; steeper gains speed)
        accel_max_mps2=1.7,
        tau_airspeed_s=3.5,
        tau_gamma_s=1.5,  # the climb rate's 63 % rise time
        tau_bank_s=0.9,
        empty_mass_kg=376.0,  # 830 lb: the J3Cub's 765 lb empty and 65 lb of fuel, no pilot
        water_capacity_kg=10.0,  # as small_uav; the water takes the pilot's point mass
        refill_rate_kgps=3.0,  # a choice: a 73 m scoop run at 22 m/s fits FF's 90 m lake
        jsbsim=JsbsimSetup(aircraft="J3Cub", v_floor_mps=22.0, v_stall_mps=17.0, water_pointmass=0),
        drop_flow_lps=5.0,
        # the agents' first-order model against the J3Cub, one UAV of ff_two_fires (seed 1, first
        # 120 s): rms 0.71 m/s in ground speed and 0.66 m/s in climb rate
        model_error_mps=0.7,
    ),
    # An amphibious single-engine scooper of the AT-802F Fire Boss class: about 3,000 kg of
    # water (800 US gal), scooped on a straight run.
    "tanker": Airframe(
        v_stall_mps=36.0,
        v_max_mps=75.0,
        bank_max_deg=45.0,
        roll_rate_max_degps=30.0,
        climb_max_mps=5.0,
        descent_max_mps=8.0,
        accel_max_mps2=1.0,
        tau_airspeed_s=4.0,
        tau_gamma_s=2.0,
        tau_bank_s=1.0,
        empty_mass_kg=4500.0,
        water_capacity_kg=3000.0,
        refill_rate_kgps=200.0,
        # jsbsim: the Pilatus PC-7, a single-turboprop trainer (MTOW ~2,700 kg), the water in its
        # payload point mass scaled by its payload / the tank (1,040 / 3,000 kg); not tuned further
        jsbsim=JsbsimSetup(
            aircraft="pc7",
            v_floor_mps=46.8,
            v_stall_mps=36.0,
            water_pointmass=0,
            water_weight_scale=0.347,
            simple_trim=False,  # JSBSim's trim fails for it (jsbsim_backend.JsbsimModel.launch)
            # the elevator's easing alone let it pull 2 g in a 40 deg bank (the course turned as a
            # 59.8 deg bank would, ff_two_fires_tanker): the load-factor limit before the pull
            load_protection=True,
            excess_power=PC7_EXCESS_POWER,
            # the agents' model (with the energy limit) against the PC-7, ff_two_fires_tanker seed 1,
            # 5 UAVs, first 120 s: rms 1.43 m/s in ground speed, 1.38 m/s in climb rate
            model_error_mps=1.4,
        ),
        drop_flow_lps=757.0,  # 200 US gal/s: AT-802F constant-flow settings span 77-450 gal/s
    ),
}

#: the numeric envelope fields a scenario may override (the preset's ``jsbsim`` setup is kept)
_FIELDS = tuple(f.name for f in dataclasses.fields(Airframe) if f.name not in ("jsbsim", "excess_power"))


def read_airframe(ctx: _Ctx, d: dict, model: str) -> Airframe | None:
    """``uavs.airframe`` of the already-read ``uavs`` mapping ``d``: None for ``ff_paper``.

    A preset name, or a mapping ``{preset: NAME, <field>: value, ...}`` whose fields replace
    the preset's. Checks: known preset, every field > 0 (``model_error_mps`` >= 0), ``v_stall_mps < v_max_mps``,
    ``bank_max_deg`` in (0, 80], ``min_speed_factor`` >= 1.
    """
    raw = d.get("airframe")
    if model == "ff_paper":
        if raw is not None:
            raise ctx.fail(
                "uavs.airframe", "only with a fixed-wing uavs.vehicle_model (ff_paper keeps vehicle:)"
            )
        return None
    default = DEFAULT_AIRFRAMES.get(model, DEFAULT_AIRFRAME)
    if raw is None:
        raw = default
    p = "uavs.airframe"
    named = isinstance(raw, str)  # a bare preset name: errors name uavs.airframe itself
    if named:
        raw = {"preset": raw}
    a = _mapping(ctx, raw, p, {"preset", *_FIELDS})
    name = _str(ctx, a, "preset", p, default)
    if name not in AIRFRAMES:
        raise ctx.fail(
            p if named else f"{p}.preset", f"unknown airframe {name!r}; presets: {sorted(AIRFRAMES)}"
        )
    base = AIRFRAMES[name]
    values: dict[str, Any] = {}
    for f in _FIELDS:
        if f == "model_error_mps":
            # on jsbsim the aircraft's own figure where the preset has none (the tanker's PC-7)
            own = base.jsbsim.model_error_mps if model == "jsbsim" else 0.0
            values[f] = _num(ctx, a, f, p, getattr(base, f) or own, ge=0)
        else:
            values[f] = _num(ctx, a, f, p, getattr(base, f), gt=0)
    # the energy limit is the JSBSim aircraft's: the agents fly by it on the jsbsim backend only
    energy = base.jsbsim.excess_power if model == "jsbsim" else None
    af = Airframe(**values, jsbsim=base.jsbsim, excess_power=energy)
    if not af.v_stall_mps < af.v_max_mps:
        raise ctx.fail(f"{p}.v_stall_mps", f"must be < v_max_mps ({af.v_max_mps:g}), got {af.v_stall_mps:g}")
    if not 0 < af.bank_max_deg <= 80:
        raise ctx.fail(f"{p}.bank_max_deg", f"must be in (0, 80] deg, got {af.bank_max_deg:g}")
    if af.min_speed_factor < 1:
        raise ctx.fail(f"{p}.min_speed_factor", f"must be >= 1, got {af.min_speed_factor:g}")
    if not af.v_min_mps < af.v_max_mps:
        raise ctx.fail(
            f"{p}.v_max_mps",
            f"must exceed the lowest commanded speed min_speed_factor x v_stall_mps ({af.v_min_mps:g}), "
            f"got {af.v_max_mps:g}",
        )
    return af


def envelope_vehicle(vehicle: Vehicle, airframe: Airframe | None) -> Vehicle:
    """The ``vehicle:`` limits the world's life-cycle and the agents use under ``airframe``.

    ``v_stall_mps`` becomes the lowest commanded speed (takeoff and landing keep their meaning:
    a command below it lands), ``vz_max_mps`` the smaller of climb and descent rate (the agents'
    limit is symmetric), ``omega_max_radps`` the turn rate at the bank limit and the lowest speed;
    tank, scoop rate and drop flow rate come from the preset. Every other field stays the scenario's.
    """
    if airframe is None:
        return vehicle
    return dataclasses.replace(
        vehicle,
        v_stall_mps=airframe.v_min_mps,
        v_max_mps=airframe.v_max_mps,
        vz_max_mps=min(airframe.climb_max_mps, airframe.descent_max_mps),
        omega_max_radps=airframe.turn_rate_max_radps(airframe.v_min_mps),
        water_capacity_kg=airframe.water_capacity_kg,
        refill_rate_kgps=airframe.refill_rate_kgps,
        drop_flow_lps=airframe.drop_flow_lps,
    )
