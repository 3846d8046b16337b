"""World simulation of the fire UAV fleet: sim clock, fire models (analytic Gaussian, raster Rothermel), vehicles, sensors, suppression, scenarios; mission recorder and replay.

Public, ROS-free API: :class:`fire_world_sim.world.World` (one control step at a time),
:mod:`fire_world_sim.vehicle`, :mod:`fire_world_sim.sensors`, :mod:`fire_world_sim.fires`.
The ROS adapter is :mod:`fire_world_sim.world_node`.
"""
