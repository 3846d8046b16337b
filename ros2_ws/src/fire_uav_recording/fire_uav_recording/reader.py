"""Reading a mission bag: :func:`open_bag` validates it, repairs an unfinished one, and reads it.

rosbags' reader refuses an MCAP file without footer ("File end magic is invalid."); :func:`open_bag`
detects that, copies every complete chunk into a closed file in a temporary directory
(:func:`fire_uav_recording.salvage.salvage_mcap`) and reads that. Every problem with a bag is
raised as one :class:`BagError` whose message names the path and what is wrong.
"""

from __future__ import annotations

import contextlib
import shutil
import struct
import tempfile
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rosbags.highlevel import AnyReader, AnyReaderError
from rosbags.interfaces import Connection, ConnectionExtRosbag2, Qos
from rosbags.rosbag2 import ReaderError

from fire_uav_recording.bagfile import BagInfo, inspect_bag
from fire_uav_recording.errors import BagError, one_line
from fire_uav_recording.metadata import KEY_CLOSED, KEY_LOG_TIME_OFFSET_NS
from fire_uav_recording.salvage import SalvageResult, salvage_mcap

__all__ = ["MissionBag", "offered_qos", "open_bag"]


@dataclass
class MissionBag:
    """An open bag: ``reader`` (rosbags ``AnyReader``, types from the bag), its metadata, warnings."""

    info: BagInfo
    reader: AnyReader
    salvage: SalvageResult | None = None
    warnings: list[str] = field(default_factory=list)

    @property
    def custom_data(self) -> dict[str, str]:
        return self.info.custom_data

    @property
    def log_time_offset_ns(self) -> int:
        """Bag log time minus sim time [ns]: the wall epoch a ``stamp_wall_epoch`` recorder added (else 0)."""
        text = self.info.custom_data.get(KEY_LOG_TIME_OFFSET_NS, "0") or "0"
        try:
            return int(text)
        except ValueError:
            raise BagError(
                f"{self.info.path}: metadata {KEY_LOG_TIME_OFFSET_NS} is not an integer: {text!r}"
            ) from None

    @property
    def topics(self) -> dict[str, str]:
        """Topic name -> message type (``pkg/msg/Name``)."""
        return {c.topic: c.msgtype for c in self.reader.connections}

    def connections(self, topics: Sequence[str] | None = None) -> list[Connection]:
        if topics is None:
            return list(self.reader.connections)
        wanted = set(topics)
        return [c for c in self.reader.connections if c.topic in wanted]

    def raw_messages(
        self, topics: Sequence[str] | None = None, start_ns: int | None = None
    ) -> Iterator[tuple[Connection, int, bytes]]:
        """(connection, sim time [ns], CDR bytes) in time order; damage raises :class:`BagError`.

        The time is the bag timestamp less :attr:`log_time_offset_ns` (sim time at receipt);
        ``start_ns`` is sim time too.
        """
        conns = self.connections(topics)
        if not conns:
            return
        off = self.log_time_offset_ns
        start = None if start_ns is None else start_ns + off
        try:
            for conn, t_ns, raw in self.reader.messages(connections=conns, start=start):
                yield conn, t_ns - off, raw
        except (ReaderError, AnyReaderError, struct.error, ValueError, EOFError, OSError) as err:
            raise BagError(f"{self.info.mcap_path}: corrupted data: {one_line(err)}") from None
        except Exception as err:
            raise BagError(
                f"{self.info.mcap_path}: corrupted data: {type(err).__name__}: {one_line(err)}"
            ) from None

    def messages(self, topics: Sequence[str] | None = None) -> Iterator[tuple[str, int, Any]]:
        """(topic, sim time [ns] (bag timestamp less the offset), deserialized message) in time order."""
        for conn, t_ns, raw in self.raw_messages(topics):
            try:
                msg = self.reader.deserialize(raw, conn.msgtype)
            except Exception as err:
                raise BagError(
                    f"{self.info.mcap_path}: cannot decode a {conn.msgtype} on {conn.topic} at t={t_ns} ns: "
                    f"{one_line(err)}"
                ) from None
            yield conn.topic, t_ns, msg


def offered_qos(conn: Connection) -> list[Qos]:
    """The QoS profiles the recorded publishers offered on ``conn`` ([] if unknown)."""
    ext = conn.ext
    return list(ext.offered_qos_profiles) if isinstance(ext, ConnectionExtRosbag2) else []


@contextlib.contextmanager
def open_bag(path: Path | str, *, salvage: bool = True) -> Iterator[MissionBag]:
    """Open a mission bag for reading, repairing an unfinished MCAP file into a temporary copy.

    ``salvage=False`` makes an unfinished file an error. Raises :class:`BagError`.
    """
    info = inspect_bag(path)
    warnings: list[str] = []
    tmpdir: Path | None = None
    result: SalvageResult | None = None
    target = info.path if (info.complete and info.has_metadata) else info.mcap_path
    try:
        if not info.complete:
            if not salvage:
                raise BagError(
                    f"{info.mcap_path}: MCAP file has no footer (recorder killed or file truncated)"
                )
            tmpdir = Path(tempfile.mkdtemp(prefix="fire_uav_salvage_"))
            target = tmpdir / info.mcap_path.name
            result = salvage_mcap(info.mcap_path, target)
            warnings.append(
                f"{info.mcap_path}: MCAP file was not closed (recorder killed?); read {result.messages} "
                f"messages from {result.chunks} complete chunks, ignored the last {result.bytes_ignored} bytes"
            )
        elif info.custom_data.get(KEY_CLOSED) == "false":
            warnings.append(f"{info.path}: metadata.yaml says the recorder did not close the bag")
        try:
            reader = AnyReader([target])
            reader.open()
        except (AnyReaderError, ReaderError, FileNotFoundError, struct.error, ValueError, EOFError) as err:
            raise BagError(f"{info.path}: cannot open bag: {one_line(err)}") from None
        except Exception as err:
            raise BagError(f"{info.path}: cannot open bag: {type(err).__name__}: {one_line(err)}") from None
        try:
            yield MissionBag(info, reader, result, warnings)
        finally:
            with contextlib.suppress(Exception):
                reader.close()
    finally:
        if tmpdir is not None:
            shutil.rmtree(tmpdir, ignore_errors=True)
