from glob import glob

from setuptools import find_packages, setup

package_name = "fire_uav_common"

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
    description="Shared ROS-free pieces of the fire UAV fleet: topic names and QoS, seeded RNG streams, terrain.",
    license="Apache-2.0",
    entry_points={
        "console_scripts": [],
    },
)
