"""Swappable vehicle-model backends: one interface, ``step(states, commands, dt_s, rngs) -> states``.

Each backend integrates the flight of a list of airborne vehicles over one physics substep; the
life-cycle (takeoff, landing, crash), the tank and the terrain floor stay in
:class:`~fire_world_sim.vehicle.VehicleSim`, the same for every backend. ``uavs.vehicle_model``
picks the backend (:func:`make_vehicle_model`):

- ``ff_paper`` (:class:`FfPaperModel`): FF Eq. 4, the unicycle that follows its command at once;
- ``coordinated_turn`` (:class:`CoordinatedTurnModel`): Beard & McLain ch. 9, bank-limited;
- ``jsbsim`` (:class:`JsbsimModel`): a 6-DoF JSBSim aircraft flown by an autopilot; it holds the
  aircraft's state, so the world makes one instance per vehicle (``per_vehicle``).
"""

from __future__ import annotations

from fire_uav_common.scenario import Scenario

from ..errors import ConfigError
from .base import Command, FlightState, VehicleModel
from .coordinated_turn import CoordinatedTurnModel
from .ff_paper import FfPaperModel
from .jsbsim_backend import JsbsimModel

__all__ = [
    "Command",
    "CoordinatedTurnModel",
    "FfPaperModel",
    "FlightState",
    "JsbsimModel",
    "VehicleModel",
    "make_vehicle_model",
]


def make_vehicle_model(scenario: Scenario) -> VehicleModel:
    """The backend named by ``scenario.uavs.vehicle_model`` (its envelope from ``uavs.airframe``)."""
    u = scenario.uavs
    if u.vehicle_model == "ff_paper":
        return FfPaperModel(scenario.vehicle.process_noise_sigma)
    if u.vehicle_model == "coordinated_turn":
        if u.airframe is None:
            raise ConfigError("uavs.airframe: coordinated_turn needs an airframe preset")
        return CoordinatedTurnModel(u.airframe, scenario.vehicle.process_noise_sigma)
    if u.vehicle_model == "jsbsim":
        if u.airframe is None:
            raise ConfigError("uavs.airframe: jsbsim needs an airframe preset")
        return JsbsimModel(u.airframe)
    raise ConfigError(f"uavs.vehicle_model: unknown model {u.vehicle_model!r}")
