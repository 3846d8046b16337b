from glob import glob

from setuptools import find_packages, setup

package_name = "fire_uav_agent"

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
    description="One firefighting UAV as a ROS 2 process: EKF state estimation, peer link with loss and crash detection, fire consensus, weighted Voronoi-Lloyd coverage control, mission life-cycle, coverage search.",
    license="Apache-2.0",
    entry_points={
        "console_scripts": [
            "uav_agent = fire_uav_agent.agent_node:main",
        ],
    },
)
