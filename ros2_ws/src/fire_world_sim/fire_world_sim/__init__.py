"""World simulation of the fire UAV fleet: sim clock, fire models (analytic Gaussian, raster Rothermel), vehicles, sensors, suppression, scenarios; mission recorder and replay."""
