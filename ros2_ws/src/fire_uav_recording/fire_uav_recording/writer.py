"""The crash-safe bag writer: a :class:`rosbags.rosbag2.Writer` for MCAP bags that survive SIGKILL.

:class:`BagWriter`

- closes an MCAP chunk and flushes the file every :meth:`BagWriter.flush` (the recorder
  calls it once a second), so a process killed with SIGKILL loses at most the last period;
- writes ``metadata.yaml`` when it opens and at each flush (rosbags writes it only in
  ``close()``), with ``fire_uav.closed_cleanly: "false"`` until the bag is closed;
- writes what rosbag2 Jazzy's MCAP storage writes and reads back (rosbag2_storage_mcap
  ``MCAPStorage::create_topic`` / ``get_metadata``): each channel's metadata carries
  ``offered_qos_profiles`` *and* ``topic_type_hash`` (the RIHS01 hash), and ``ros_distro`` is
  :data:`ROS_DISTRO` in ``metadata.yaml`` and in the MCAP ``rosbag2`` metadata record
  (rosbags writes ``rosbags`` there).

rosbags' writer leaves no footer and no summary when the process dies; the readers of this
package repair that (:mod:`fire_uav_recording.salvage`).
"""

from __future__ import annotations

from io import BytesIO
from pathlib import Path
from typing import cast

import yaml
from rosbags.interfaces import Connection, ConnectionExtRosbag2
from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer, WriterError
from rosbags.rosbag2.metadata import dump_qos_v8, dump_qos_v9
from rosbags.rosbag2.storage_mcap import Channel, McapWriter, write_channel, write_string

from fire_uav_recording.errors import BagError
from fire_uav_recording.metadata import KEY_CLOSED

__all__ = ["INFINITE_DURATION", "ROS_DISTRO", "BagWriter"]

ROS_DISTRO = "jazzy"  # what rosbag2 writes as ros_distro (the distribution the fleet runs on)
#: (sec, nsec) of an infinite QoS duration as rmw (RMW_DURATION_INFINITE, 2**63 - 1 ns) and so
#: rosbag2 Jazzy spell it; Foxy-era bags used (2147483647, 4294967295)
INFINITE_DURATION = (9223372036, 854775807)


def _jazzy_metadata_text(text: str) -> str:
    """rosbags' serialized bag metadata with ``ros_distro`` set to :data:`ROS_DISTRO`."""
    doc = yaml.safe_load(text) or {}
    doc["ros_distro"] = ROS_DISTRO
    return yaml.safe_dump(doc, default_flow_style=False).strip()


class _FlushingMcapWriter(McapWriter):
    """rosbags' MCAP storage writer that pushes each finished chunk to the OS at once."""

    def close_chunk(self) -> None:
        super().close_chunk()
        self.bio.flush()

    def add_connection(self, connection: Connection, offered_qos_profiles: str) -> None:
        """Add the channel with rosbag2 Jazzy's metadata: QoS profiles and ``topic_type_hash``."""
        meta = BytesIO()
        write_string(meta, "offered_qos_profiles")
        write_string(meta, offered_qos_profiles)
        write_string(meta, "topic_type_hash")
        write_string(meta, connection.digest)
        self.channels.append(
            Channel(
                connection.id,
                connection.msgtype,
                connection.topic,
                cast(ConnectionExtRosbag2, connection.ext).serialization_format,
                meta.getvalue(),
            )
        )
        self.channel_stats[connection.id] = 0
        write_channel(self.chunk.bio, self.channels[-1], self.schemas)

    def close(self, version: int, metadata: str) -> None:
        super().close(version, _jazzy_metadata_text(metadata))

    def pending_bytes(self) -> int:
        """Bytes of the chunk being assembled in memory (lost if the process dies now)."""
        return self.chunk.bio.tell()


class BagWriter(Writer):
    """A :class:`rosbags.rosbag2.Writer` for MCAP bags that survive SIGKILL up to the last flush.

    Use as a context manager, or ``open()`` / ``close()``. ``compress=True`` zstd-compresses
    each MCAP chunk (rosbag2's "storage" compression; ``metadata.yaml`` then says no
    compression, as rosbag2 does for chunk compression).
    """

    STORAGE_PLUGINS = {**Writer.STORAGE_PLUGINS, StoragePlugin.MCAP: _FlushingMcapWriter}

    def __init__(
        self,
        path: Path | str,
        *,
        custom_data: dict[str, str] | None = None,
        compress: bool = True,
        version: int = 9,
    ) -> None:
        path = Path(path)
        if path.exists():
            raise BagError(f"{path}: exists already; refusing to overwrite a bag (choose a new output)")
        if not path.parent.is_dir():
            raise BagError(f"{path}: parent directory {path.parent} does not exist")
        try:
            super().__init__(path, version=version, storage_plugin=StoragePlugin.MCAP)  # type: ignore[arg-type]
        except WriterError as err:
            raise BagError(f"{path}: {err}") from None
        if compress:
            self.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
        for key, value in (custom_data or {}).items():
            self.set_custom_data(key, str(value))
        self.set_custom_data(KEY_CLOSED, "false")

    def open(self) -> None:
        try:
            super().open()
        except (WriterError, OSError) as err:
            raise BagError(f"{self.path}: cannot create bag: {err}") from None
        self.write_metadata_snapshot()

    @property
    def mcap_path(self) -> Path:
        return self.path / f"{self.path.name}.mcap"

    def flush(self) -> None:
        """Close the chunk being assembled (if any), flush the file, rewrite ``metadata.yaml``."""
        storage = self.storage
        if storage is None:
            return
        assert isinstance(storage, _FlushingMcapWriter)
        if storage.pending_bytes():
            storage.close_chunk()
        storage.bio.flush()
        self.write_metadata_snapshot()

    def close(self) -> None:
        """Write the MCAP summary and footer and the final ``metadata.yaml`` (closed_cleanly: true)."""
        if self.storage is None:
            return
        self.set_custom_data(KEY_CLOSED, "true")
        super().close()
        self.write_metadata_snapshot()  # rosbags wrote ros_distro "rosbags"; rosbag2 writes the distro

    def write_metadata_snapshot(self) -> None:
        """Write ``metadata.yaml`` for what has been written so far (atomic replace)."""
        dump_qos = dump_qos_v9 if self.version >= 9 else dump_qos_v8
        count = sum(self.counts.values())
        start = self.min_timestamp if count else 0
        duration = max(0, self.max_timestamp - self.min_timestamp) if count else 0
        info = {
            "version": self.version,
            "storage_identifier": "mcap",
            "relative_file_paths": [self.mcap_path.name],
            "duration": {"nanoseconds": duration},
            "starting_time": {"nanoseconds_since_epoch": start},
            "message_count": count,
            "topics_with_message_count": [
                {
                    "topic_metadata": {
                        "name": c.topic,
                        "type": c.msgtype,
                        "serialization_format": c.ext.serialization_format,
                        "offered_qos_profiles": dump_qos(c.ext.offered_qos_profiles),
                        "type_description_hash": c.digest,
                    },
                    "message_count": self.counts[c.id],
                }
                for c in self.connections
                if isinstance(c.ext, ConnectionExtRosbag2)
            ],
            "compression_format": "",
            "compression_mode": "",
            "files": [
                {
                    "path": self.mcap_path.name,
                    "starting_time": {"nanoseconds_since_epoch": start},
                    "duration": {"nanoseconds": duration},
                    "message_count": count,
                }
            ],
            "custom_data": dict(self.custom_data),
            "ros_distro": ROS_DISTRO,
        }
        text = yaml.safe_dump({"rosbag2_bagfile_information": info}, default_flow_style=False)
        tmp = self.metapath.with_suffix(".yaml.tmp")
        tmp.write_text(text, encoding="utf8")
        tmp.replace(self.metapath)
