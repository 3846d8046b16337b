"""Salvage: copy the complete records of an MCAP file cut short (no summary, no footer) into a closed one."""

from __future__ import annotations

import io
import struct
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from fire_uav_recording.bagfile import inspect_bag
from fire_uav_recording.errors import BagError, one_line

__all__ = ["SalvageResult", "repair_bag", "salvage_mcap"]


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
        writer.start(profile="ros2", library="fire_uav_recording salvage")
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
            reason = f"{type(err).__name__}: {one_line(err) or 'truncated record'}"
        except Exception as err:
            reason = f"{type(err).__name__}: {one_line(err)}"
        writer.finish()
    if messages == 0:
        raise BagError(f"{src}: no complete MCAP chunk to recover ({reason}, file size {size} bytes)")
    return SalvageResult(messages, chunks, max(0, size - good_offset), reason)


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
