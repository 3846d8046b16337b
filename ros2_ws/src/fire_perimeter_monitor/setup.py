from glob import glob

from setuptools import find_packages, setup

package_name = "fire_perimeter_monitor"

setup(
    name=package_name,
    version="0.1.0",
    packages=find_packages(exclude=["test"]),
    data_files=[
        ("share/ament_index/resource_index/packages", ["resource/" + package_name]),
        ("share/" + package_name, ["package.xml"]),
        ("share/" + package_name + "/config", glob("config/*")),
    ],
    install_requires=["setuptools"],
    zip_safe=True,
    maintainer="fire-uav team",
    maintainer_email="fire-uav@example.org",
    description="Importance-based monitoring of a spreading fire's perimeter (on-board fire map, rate of spread, cell importance, planning windows) and a circling baseline.",
    license="Apache-2.0",
    entry_points={
        "console_scripts": [
            "perimeter_viewer = fire_perimeter_monitor.viewer_node:main",
        ],
    },
)
