"""World simulation of the fire UAV fleet: sim clock, vehicles, sensors, fire models (analytic
Gaussian, raster Rothermel) and suppression. The scenarios it runs ship in its ``scenarios/``
directory; the recorder and replay live in ``fire_uav_recording``.

Public, ROS-free API: :class:`fire_world_sim.world.World` (one control step at a time),
:mod:`fire_world_sim.vehicle`, :mod:`fire_world_sim.sensors`, :mod:`fire_world_sim.fires`
(the :class:`~fire_world_sim.fires.FireModel` protocol), :mod:`fire_world_sim.errors`.
The ROS node is :mod:`fire_world_sim.world_node`; its parameters are
:mod:`fire_world_sim.world_config`, its lockstep bookkeeping
:mod:`fire_world_sim.step_answers` (both ROS-free), its messages :mod:`fire_world_sim.ros_messages`.
"""
