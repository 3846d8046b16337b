"""Mission bags on disk: a typestore with the fleet's messages, a crash-safe writer, a validating reader.

Pure Python (rosbags, mcap, PyYAML): no rclpy, so the report and the tests use it without ROS.

A mission bag is a rosbag2 directory (``metadata.yaml`` + one ``<name>.mcap``) written by
:class:`BagWriter`, a :class:`rosbags.rosbag2.Writer` that also

- closes an MCAP chunk and flushes the file every :meth:`BagWriter.flush` (the recorder
  calls it once a second), so a process killed with SIGKILL loses at most the last period;
- writes ``metadata.yaml`` when it opens and at each flush (rosbags writes it only in
  ``close()``), with ``fire_uav.closed_cleanly: "false"`` until the bag is closed.

rosbags' writer leaves no footer and no summary when the process dies; rosbags' reader then
refuses the file ("File end magic is invalid."). :func:`open_bag` detects that, copies every
complete chunk into a closed MCAP file in a temporary directory (:func:`salvage_mcap`, which
reads the file sequentially with ``mcap``'s stream reader and needs no summary) and reads
that. Every problem with a bag is raised as one :class:`BagError` whose message names the
path and what is wrong.
"""

from __future__ import annotations

import contextlib
import functools
import io
import os
import shutil
import struct
import tempfile
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml
from rosbags.highlevel import AnyReader, AnyReaderError
from rosbags.interfaces import Connection, ConnectionExtRosbag2, Qos
from rosbags.rosbag2 import (
    CompressionFormat,
    CompressionMode,
    ReaderError,
    StoragePlugin,
    Writer,
    WriterError,
)
from rosbags.rosbag2.metadata import dump_qos_v8, dump_qos_v9
from rosbags.rosbag2.storage_mcap import McapWriter
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore

__all__ = [
    "KEY_CLOSED",
    "KEY_RECORDER_STARTED",
    "KEY_SCENARIO_FILE",
    "KEY_SCENARIO_YAML",
    "KEY_SEED",
    "KEY_SOFTWARE_VERSION",
    "KEY_UAV_COUNT",
    "MCAP_MAGIC",
    "BagError",
    "BagInfo",
    "BagWriter",
    "MissionBag",
    "SalvageResult",
    "find_msg_dir",
    "fleet_typestore",
    "inspect_bag",
    "open_bag",
    "salvage_mcap",
]

MCAP_MAGIC = b"\x89MCAP0\r\n"
FLEET_MSG_PACKAGE = "fire_uav_msgs"

# custom_data keys of metadata.yaml (all values are strings, rosbag2 requires it)
KEY_SCENARIO_FILE = "fire_uav.scenario_file"  # path the recorder was given
KEY_SCENARIO_YAML = "fire_uav.scenario_yaml"  # the file's full text ("" if none)
KEY_SEED = "fire_uav.seed"  # int, as text
KEY_UAV_COUNT = "fire_uav.uav_count"  # int, as text
KEY_SOFTWARE_VERSION = "fire_uav.software_version"  # fire_world_sim version (+ rosbags version)
KEY_RECORDER_STARTED = "fire_uav.recorder_started_utc"  # ISO 8601 wall time
KEY_CLOSED = "fire_uav.closed_cleanly"  # "true" once close() ran, "false" in the snapshots


class BagError(Exception):
    """A bag cannot be written or read; the message names the path and the problem (one line)."""


# --- typestore ----------------------------------------------------------------------------
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
    # .../ros2_ws/src/fire_world_sim/fire_world_sim/bag_io.py -> .../ros2_ws/src/<package>/msg
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
    except (BagError, Exception):
        return False
    return msgtype in typestore.fielddefs


# --- writing ------------------------------------------------------------------------------
class _FlushingMcapWriter(McapWriter):
    """rosbags' MCAP storage writer that pushes each finished chunk to the OS at once."""

    def close_chunk(self) -> None:
        super().close_chunk()
        self.bio.flush()

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
            "ros_distro": "rosbags",
        }
        text = yaml.safe_dump({"rosbag2_bagfile_information": info}, default_flow_style=False)
        tmp = self.metapath.with_suffix(".yaml.tmp")
        tmp.write_text(text, encoding="utf8")
        tmp.replace(self.metapath)


# --- reading ------------------------------------------------------------------------------
@dataclass(frozen=True)
class BagInfo:
    """What :func:`inspect_bag` found at a path."""

    path: Path  # as given: a bag directory or a bare .mcap file
    mcap_path: Path  # the MCAP file holding the messages
    custom_data: dict[str, str]  # metadata.yaml custom_data ({} for a bare file or none)
    has_metadata: bool  # metadata.yaml present and readable
    complete: bool  # the MCAP file ends with a footer (the writer closed it)


def _one_line(text: object) -> str:
    return " ".join(str(text).split())


def _read_metadata(path: Path) -> dict[str, Any]:
    try:
        doc = yaml.safe_load(path.read_text(encoding="utf8"))
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as err:
        raise BagError(f"{path}: unreadable metadata.yaml: {_one_line(err)}") from None
    if not isinstance(doc, dict) or not isinstance(doc.get("rosbag2_bagfile_information"), dict):
        raise BagError(f"{path}: not rosbag2 metadata (no 'rosbag2_bagfile_information' mapping)")
    return doc["rosbag2_bagfile_information"]


def _check_mcap_file(path: Path) -> bool:
    """Check the MCAP start magic; return whether the file ends with the end magic."""
    try:
        size = path.stat().st_size
        with path.open("rb") as f:
            head = f.read(8)
            if size >= 16:
                f.seek(-8, os.SEEK_END)
                tail = f.read(8)
            else:
                tail = b""
    except OSError as err:
        raise BagError(f"{path}: cannot read: {err.strerror}") from None
    if size == 0:
        raise BagError(f"{path}: empty file, no MCAP data")
    if head != MCAP_MAGIC:
        raise BagError(f"{path}: not an MCAP file (bad magic at byte 0)")
    return tail == MCAP_MAGIC


def inspect_bag(path: Path | str) -> BagInfo:
    """Validate that ``path`` is a rosbag2 MCAP directory or an ``.mcap`` file; raise :class:`BagError`."""
    path = Path(path)
    if not path.exists():
        raise BagError(f"{path}: no such bag (path does not exist)")
    custom: dict[str, str] = {}
    has_meta = False
    if path.is_dir():
        meta_path = path / "metadata.yaml"
        mcaps = sorted(path.glob("*.mcap"))
        if meta_path.exists():
            info = _read_metadata(meta_path)
            storage = info.get("storage_identifier", "")
            if storage != "mcap":
                raise BagError(f"{path}: storage {storage!r} not supported, only MCAP bags")
            files = info.get("relative_file_paths") or []
            if len(files) != 1:
                raise BagError(f"{path}: split bags ({len(files)} files) are not supported")
            mcap_path = path / str(files[0])
            if not mcap_path.exists():
                raise BagError(f"{path}: metadata.yaml names {files[0]} but that file is missing")
            custom = {str(k): str(v) for k, v in (info.get("custom_data") or {}).items()}
            has_meta = True
        elif len(mcaps) == 1:
            mcap_path = mcaps[0]
        elif mcaps:
            raise BagError(
                f"{path}: no metadata.yaml and {len(mcaps)} .mcap files; cannot tell which to read"
            )
        else:
            raise BagError(f"{path}: not a rosbag2 bag (no metadata.yaml and no .mcap file)")
    elif path.suffix == ".mcap":
        mcap_path = path
    else:
        raise BagError(f"{path}: not a bag (expected a rosbag2 directory or an .mcap file)")
    complete = _check_mcap_file(mcap_path)
    return BagInfo(path, mcap_path, custom, has_meta, complete)


@dataclass(frozen=True)
class SalvageResult:
    """What :func:`salvage_mcap` recovered."""

    messages: int
    chunks: int
    bytes_ignored: int  # trailing bytes that did not form a complete record
    stop_reason: str  # "footer" for a complete file, else why reading stopped


def salvage_mcap(src: Path, dst: Path) -> SalvageResult:
    """Copy every complete record of ``src`` (which may lack summary and footer) into a closed MCAP ``dst``.

    Reads ``src`` sequentially; a chunk cut short is dropped whole, so the copy holds the
    messages up to the last complete chunk. Raises :class:`BagError` when the file is not
    MCAP or no message at all can be recovered.
    """
    from mcap.exceptions import McapError
    from mcap.records import Channel, Chunk, Footer, Message, Schema
    from mcap.stream_reader import StreamReader, breakup_chunk
    from mcap.writer import CompressionType
    from mcap.writer import Writer as McapFileWriter

    size = src.stat().st_size
    schema_map: dict[int, int] = {}
    channel_map: dict[int, int] = {}
    messages = chunks = 0
    good_offset = 8
    reason = "end of data without footer"
    with src.open("rb") as fin, dst.open("wb") as fout:
        writer = McapFileWriter(fout, compression=CompressionType.ZSTD)
        writer.start(profile="ros2", library="fire_world_sim.bag_io salvage")
        reader = StreamReader(fin, emit_chunks=True, validate_crcs=True, record_size_limit=size)
        try:
            for record in reader.records:
                records: Iterable[Any]
                if isinstance(record, Chunk):
                    records = breakup_chunk(record, validate_crc=True)
                    chunks += 1
                else:
                    records = (record,)
                for rec in records:
                    if isinstance(rec, Schema):
                        if rec.id not in schema_map:
                            schema_map[rec.id] = writer.register_schema(rec.name, rec.encoding, rec.data)
                    elif isinstance(rec, Channel):
                        if rec.id not in channel_map:
                            channel_map[rec.id] = writer.register_channel(
                                rec.topic,
                                rec.message_encoding,
                                schema_map.get(rec.schema_id, 0),
                                rec.metadata,
                            )
                    elif isinstance(rec, Message):
                        if rec.channel_id in channel_map:
                            writer.add_message(
                                channel_map[rec.channel_id],
                                rec.log_time,
                                rec.data,
                                rec.publish_time,
                                rec.sequence,
                            )
                            messages += 1
                    elif isinstance(rec, Footer):
                        reason = "footer"
                good_offset = fin.tell()
        except (McapError, EOFError, struct.error, ValueError, OSError, MemoryError) as err:
            reason = f"{type(err).__name__}: {_one_line(err) or 'truncated record'}"
        except Exception as err:
            reason = f"{type(err).__name__}: {_one_line(err)}"
        writer.finish()
    if messages == 0:
        raise BagError(f"{src}: no complete MCAP chunk to recover ({reason}, file size {size} bytes)")
    return SalvageResult(messages, chunks, max(0, size - good_offset), reason)


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
        """(connection, bag timestamp [ns], CDR bytes) in time order; damage raises :class:`BagError`."""
        conns = self.connections(topics)
        if not conns:
            return
        try:
            yield from self.reader.messages(connections=conns, start=start_ns)
        except (ReaderError, AnyReaderError, struct.error, ValueError, EOFError, OSError) as err:
            raise BagError(f"{self.info.mcap_path}: corrupted data: {_one_line(err)}") from None
        except Exception as err:
            raise BagError(
                f"{self.info.mcap_path}: corrupted data: {type(err).__name__}: {_one_line(err)}"
            ) from None

    def messages(self, topics: Sequence[str] | None = None) -> Iterator[tuple[str, int, Any]]:
        """(topic, bag timestamp [ns], deserialized message) in time order."""
        for conn, t_ns, raw in self.raw_messages(topics):
            try:
                msg = self.reader.deserialize(raw, conn.msgtype)
            except Exception as err:
                raise BagError(
                    f"{self.info.mcap_path}: cannot decode a {conn.msgtype} on {conn.topic} at t={t_ns} ns: "
                    f"{_one_line(err)}"
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
            raise BagError(f"{info.path}: cannot open bag: {_one_line(err)}") from None
        except Exception as err:
            raise BagError(f"{info.path}: cannot open bag: {type(err).__name__}: {_one_line(err)}") from None
        try:
            yield MissionBag(info, reader, result, warnings)
        finally:
            with contextlib.suppress(Exception):
                reader.close()
    finally:
        if tmpdir is not None:
            shutil.rmtree(tmpdir, ignore_errors=True)


def repair_bag(src: Path | str, dst: Path | str) -> SalvageResult:
    """Write a closed copy of the bag at ``src`` (directory or .mcap) as a new bag directory ``dst``."""
    info = inspect_bag(src)
    dst = Path(dst)
    if dst.exists():
        raise BagError(f"{dst}: exists already; refusing to overwrite")
    dst.mkdir(parents=True)
    result = salvage_mcap(info.mcap_path, dst / f"{dst.name}.mcap")
    if info.has_metadata:
        text = (Path(info.path) / "metadata.yaml").read_text(encoding="utf8")
        doc = yaml.safe_load(io.StringIO(text))
        meta = doc["rosbag2_bagfile_information"]
        meta["relative_file_paths"] = [f"{dst.name}.mcap"]
        for f in meta.get("files") or []:
            f["path"] = f"{dst.name}.mcap"
        (dst / "metadata.yaml").write_text(yaml.safe_dump(doc, default_flow_style=False), encoding="utf8")
    return result
