from glob import glob

from setuptools import find_packages, setup

package_name = "fire_uav_recording"

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
    description="Mission recording of the fire UAV fleet: crash-safe rosbag2/MCAP writer, validating reader with salvage, recorder and replay nodes.",
    license="Apache-2.0",
    entry_points={
        "console_scripts": [
            "recorder = fire_uav_recording.recorder_node:main",
            "replay = fire_uav_recording.replay_node:main",
            "foxglove_bridge = fire_uav_recording.foxglove_bridge_node:main",
        ],
    },
)
