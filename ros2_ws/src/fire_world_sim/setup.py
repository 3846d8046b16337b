from glob import glob

from setuptools import find_packages, setup

package_name = "fire_world_sim"

setup(
    name=package_name,
    version="0.1.0",
    packages=find_packages(exclude=["test"]),
    data_files=[
        ("share/ament_index/resource_index/packages", ["resource/" + package_name]),
        ("share/" + package_name, ["package.xml"]),
        ("share/" + package_name + "/config", glob("config/*")),
        ("share/" + package_name + "/scenarios", glob("scenarios/*.yaml")),
    ],
    install_requires=["setuptools"],
    zip_safe=True,
    maintainer="fire-uav team",
    maintainer_email="fire-uav@example.org",
    description="World simulation of the fire UAV fleet: sim clock, fire models (analytic Gaussian, raster Rothermel), vehicles, sensors, suppression, scenarios.",
    license="Apache-2.0",
    entry_points={
        "console_scripts": [
            "world_node = fire_world_sim.world_node:main",
        ],
    },
)
