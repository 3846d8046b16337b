"""A rosbags typestore that knows the fleet's messages (``fire_uav_msgs``), from their ``.msg`` files."""

from __future__ import annotations

import functools
import os
from pathlib import Path
from typing import Any

from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore

from fire_uav_recording.errors import BagError

__all__ = ["FLEET_MSG_PACKAGE", "ensure_type", "find_msg_dir", "fleet_typestore", "register_msg_dir"]

FLEET_MSG_PACKAGE = "fire_uav_msgs"


def find_msg_dir(package: str = FLEET_MSG_PACKAGE) -> Path:
    """Directory holding ``package``'s installed ``.msg`` files.

    Looks in ``<prefix>/share/<package>/msg`` for each prefix of ``AMENT_PREFIX_PATH``, then in
    the source tree next to this package (``ros2_ws/src/<package>/msg``).
    """
    for prefix in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
        if prefix:
            cand = Path(prefix) / "share" / package / "msg"
            if cand.is_dir():
                return cand
    # .../ros2_ws/src/fire_uav_recording/fire_uav_recording/typestore.py -> .../ros2_ws/src/<package>/msg
    cand = Path(__file__).resolve().parents[2] / package / "msg"
    if cand.is_dir():
        return cand
    raise BagError(f"cannot find the .msg files of {package}: not in AMENT_PREFIX_PATH nor at {cand}")


def register_msg_dir(typestore: Typestore, msg_dir: Path, package: str) -> list[str]:
    """Register every ``.msg`` in ``msg_dir`` as ``<package>/msg/<Name>``; return the type names."""
    typs: dict[str, Any] = {}
    for path in sorted(msg_dir.glob("*.msg")):
        name = f"{package}/msg/{path.stem}"
        typs.update(get_types_from_msg(path.read_text(encoding="utf8"), name))
    typestore.register(typs)
    return sorted(typs)


@functools.lru_cache(maxsize=4)
def fleet_typestore(msg_dir: Path | None = None) -> Typestore:
    """ROS 2 Jazzy typestore with the fleet's ``fire_uav_msgs`` registered from their ``.msg`` files.

    The rihs01 hashes rosbags computes from them match the ones of the colcon build.
    """
    store = get_typestore(Stores.ROS2_JAZZY)
    register_msg_dir(store, msg_dir or find_msg_dir(), FLEET_MSG_PACKAGE)
    return store


def ensure_type(typestore: Typestore, msgtype: str) -> bool:
    """Make ``msgtype`` (``pkg/msg/Name``) known to ``typestore``, loading its package from the ament index.

    Returns False if no definition can be found.
    """
    if msgtype in typestore.fielddefs:
        return True
    package = msgtype.split("/", 1)[0]
    try:
        register_msg_dir(typestore, find_msg_dir(package), package)
    except Exception:  # BagError (not found) or a definition rosbags cannot parse
        return False
    return msgtype in typestore.fielddefs
