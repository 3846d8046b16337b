"""Does a bag read as rosbag2 Jazzy's own? The checks ``ros2 bag`` would make, as far as they go
without rosbag2 itself.

- MCAP ``ros2`` profile (the MCAP specification's profiles/ros2.md): header profile ``ros2``;
  every schema ``ros2msg`` (or ``ros2idl``) named ``pkg/msg/Name``; every channel ``cdr`` with
  ``offered_qos_profiles`` in its metadata, plus ``topic_type_hash`` (RIHS01), which rosbag2
  Jazzy's MCAP storage writes and reads back when ``metadata.yaml`` is absent.
- ``metadata.yaml`` against rosbag2's version-9 layout: every key rosbag2_storage's YAML
  reader expects, QoS profiles as a sequence with the v9 policy names, durations as
  ``{sec, nsec}``, counts and times that agree with the MCAP file, ``ros_distro``.
- Optionally every message through ``deserialize(msgtype, cdr_bytes)``, e.g. rclpy's
  ``deserialize_message`` with the generated class (what a subscriber of ``ros2 bag play`` does).

:func:`check_bag` returns the problems found, one line each ([] for a sound bag).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import yaml
from mcap.reader import make_reader

from fire_uav_recording.bagfile import inspect_bag, read_metadata

__all__ = ["METADATA_V9_KEYS", "QOS_V9_KEYS", "check_bag"]

#: top-level keys of ``rosbag2_bagfile_information`` in a version-9 bag (rosbag2_storage yaml.hpp)
METADATA_V9_KEYS = frozenset(
    {
        "version",
        "storage_identifier",
        "duration",
        "starting_time",
        "message_count",
        "topics_with_message_count",
        "compression_format",
        "compression_mode",
        "relative_file_paths",
        "files",
        "custom_data",
        "ros_distro",
    }
)
TOPIC_V9_KEYS = frozenset(
    {"name", "type", "serialization_format", "offered_qos_profiles", "type_description_hash"}
)
QOS_V9_KEYS = frozenset(
    {
        "history",
        "depth",
        "reliability",
        "durability",
        "deadline",
        "lifespan",
        "liveliness",
        "liveliness_lease_duration",
        "avoid_ros_namespace_conventions",
    }
)
_QOS_NAMES = {
    "history": {"system_default", "keep_last", "keep_all", "unknown"},
    "reliability": {"system_default", "reliable", "best_effort", "unknown", "best_available"},
    "durability": {"system_default", "transient_local", "volatile", "unknown", "best_available"},
    "liveliness": {"system_default", "automatic", "manual_by_topic", "unknown", "best_available"},
}
_RIHS01 = re.compile(r"RIHS01_[0-9a-f]{64}")
_TYPE = re.compile(r"[A-Za-z][\w]*/msg/[A-Za-z][\w]*")


def _check_qos(where: str, profiles: Any, out: list[str]) -> None:
    if not isinstance(profiles, list):
        out.append(f"{where}: offered_qos_profiles is {type(profiles).__name__}, not a sequence")
        return
    for i, q in enumerate(profiles):
        if not isinstance(q, dict) or set(q) != QOS_V9_KEYS:
            got = sorted(q) if isinstance(q, dict) else q
            out.append(f"{where}: QoS profile {i} keys {got} are not the v9 set")
            continue
        for key, names in _QOS_NAMES.items():
            if q[key] not in names:
                out.append(f"{where}: QoS profile {i} {key} {q[key]!r} is not a v9 policy name")
        for key in ("deadline", "lifespan", "liveliness_lease_duration"):
            d = q[key]
            if not (isinstance(d, dict) and set(d) == {"sec", "nsec"}):
                out.append(f"{where}: QoS profile {i} {key} is not {{sec, nsec}}")
            elif (d["sec"], d["nsec"]) == (2147483647, 4294967295):
                out.append(
                    f"{where}: QoS profile {i} {key} uses the Foxy-era infinite (2147483647, 4294967295)"
                )


def check_bag(
    path: Path | str,
    *,
    deserialize: Callable[[str, bytes], object] | None = None,
    ros_distro: str = "jazzy",
) -> list[str]:
    """Problems that would make ``ros2 bag`` (Jazzy, MCAP storage) read ``path`` differently."""
    info = inspect_bag(path)
    out: list[str] = []
    if not info.complete:
        out.append(f"{info.mcap_path}: no MCAP footer (rosbag2 needs a summary or a full scan)")
        return out
    channels: dict[str, dict[str, str]] = {}
    counts: dict[str, int] = {}
    t_min, t_max = None, None
    with info.mcap_path.open("rb") as f:
        reader = make_reader(f)
        header = reader.get_header()
        if header.profile != "ros2":
            out.append(f"MCAP header profile {header.profile!r}, rosbag2 writes 'ros2'")
        summary = reader.get_summary()
        if summary is None:
            out.append("MCAP file has no summary section")
            return out
        for sch in summary.schemas.values():
            if sch.encoding not in ("ros2msg", "ros2idl"):
                out.append(f"schema {sch.name}: encoding {sch.encoding!r}, not ros2msg")
            if not _TYPE.fullmatch(sch.name):
                out.append(f"schema {sch.name!r}: not a pkg/msg/Name type")
            if not sch.data:
                out.append(f"schema {sch.name}: empty definition")
        for ch in summary.channels.values():
            where = f"channel {ch.topic}"
            if ch.message_encoding != "cdr":
                out.append(f"{where}: message encoding {ch.message_encoding!r}, not cdr")
            meta = dict(ch.metadata)
            if "offered_qos_profiles" not in meta:
                out.append(f"{where}: no offered_qos_profiles in the channel metadata")
            else:
                _check_qos(where, yaml.safe_load(meta["offered_qos_profiles"]) or [], out)
            if not _RIHS01.fullmatch(meta.get("topic_type_hash", "")):
                out.append(f"{where}: topic_type_hash {meta.get('topic_type_hash')!r} is not a RIHS01 hash")
            schema = summary.schemas.get(ch.schema_id)
            channels[ch.topic] = {"type": schema.name if schema else "", **meta}
        rosbag2_meta = [m for m in reader.iter_metadata() if m.name == "rosbag2"]
        if not rosbag2_meta or "serialized_metadata" not in rosbag2_meta[0].metadata:
            out.append("MCAP file has no 'rosbag2' metadata record with serialized_metadata")
        else:
            embedded = yaml.safe_load(rosbag2_meta[0].metadata["serialized_metadata"]) or {}
            if embedded.get("ros_distro") != ros_distro:
                out.append(
                    f"MCAP rosbag2 metadata: ros_distro {embedded.get('ros_distro')!r}, not {ros_distro!r}"
                )
        types = {ch.id: summary.schemas[ch.schema_id].name for ch in summary.channels.values()}
        for _sch, ch, msg in reader.iter_messages():
            counts[ch.topic] = counts.get(ch.topic, 0) + 1
            t_min = msg.log_time if t_min is None else min(t_min, msg.log_time)
            t_max = msg.log_time if t_max is None else max(t_max, msg.log_time)
            if deserialize is not None:
                try:
                    deserialize(types[ch.id], msg.data)
                except Exception as err:  # any failure is the finding
                    out.append(
                        f"{ch.topic} at {msg.log_time} ns: does not deserialize as {types[ch.id]}: {err}"
                    )
                    if len(out) > 50:
                        return out
    if not info.has_metadata:
        out.append(f"{info.path}: no metadata.yaml (rosbag2 rebuilds it from the MCAP channels)")
        return out
    meta = read_metadata(Path(info.path) / "metadata.yaml")
    missing, extra = METADATA_V9_KEYS - set(meta), set(meta) - METADATA_V9_KEYS
    if missing or extra:
        out.append(f"metadata.yaml: keys missing {sorted(missing)}, unknown {sorted(extra)} (v9 layout)")
    if meta.get("version") != 9:
        out.append(f"metadata.yaml: version {meta.get('version')!r}, not 9")
    if meta.get("ros_distro") != ros_distro:
        out.append(f"metadata.yaml: ros_distro {meta.get('ros_distro')!r}, not {ros_distro!r}")
    if meta.get("storage_identifier") != "mcap":
        out.append(f"metadata.yaml: storage_identifier {meta.get('storage_identifier')!r}, not mcap")
    total = sum(counts.values())
    if meta.get("message_count") != total:
        out.append(f"metadata.yaml: message_count {meta.get('message_count')} but the file has {total}")
    if total:
        start = (meta.get("starting_time") or {}).get("nanoseconds_since_epoch")
        dur = (meta.get("duration") or {}).get("nanoseconds")
        if start != t_min or dur != (t_max or 0) - (t_min or 0):
            out.append(
                f"metadata.yaml: starting_time/duration {start}/{dur} != the file's {t_min}/{t_max - t_min}"
            )
    seen = set()
    for entry in meta.get("topics_with_message_count") or []:
        tm = entry.get("topic_metadata") or {}
        name = tm.get("name")
        seen.add(name)
        where = f"metadata.yaml topic {name}"
        if set(tm) != TOPIC_V9_KEYS:
            out.append(f"{where}: keys {sorted(tm)} are not the v9 set")
        _check_qos(where, tm.get("offered_qos_profiles"), out)
        ch = channels.get(name)
        if ch is None:
            out.append(f"{where}: no such channel in the MCAP file")
            continue
        if tm.get("type") != ch["type"]:
            out.append(f"{where}: type {tm.get('type')} but the channel's schema is {ch['type']}")
        if tm.get("type_description_hash") != ch.get("topic_type_hash"):
            out.append(f"{where}: type_description_hash differs from the channel's topic_type_hash")
        if entry.get("message_count") != counts.get(name, 0):
            out.append(
                f"{where}: message_count {entry.get('message_count')} but the file has {counts.get(name, 0)}"
            )
    for name in set(channels) - seen:
        out.append(f"channel {name}: not in metadata.yaml")
    return out
