"""What is at a path: a rosbag2 MCAP directory or a bare ``.mcap`` file, validated without reading it."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from fire_uav_recording.errors import BagError, one_line

__all__ = ["MCAP_MAGIC", "BagInfo", "inspect_bag"]

MCAP_MAGIC = b"\x89MCAP0\r\n"


@dataclass(frozen=True)
class BagInfo:
    """What :func:`inspect_bag` found at a path."""

    path: Path  # as given: a bag directory or a bare .mcap file
    mcap_path: Path  # the MCAP file holding the messages
    custom_data: dict[str, str]  # metadata.yaml custom_data ({} for a bare file or none)
    has_metadata: bool  # metadata.yaml present and readable
    complete: bool  # the MCAP file ends with a footer (the writer closed it)


def read_metadata(path: Path) -> dict[str, Any]:
    try:
        doc = yaml.safe_load(path.read_text(encoding="utf8"))
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as err:
        raise BagError(f"{path}: unreadable metadata.yaml: {one_line(err)}") from None
    if not isinstance(doc, dict) or not isinstance(doc.get("rosbag2_bagfile_information"), dict):
        raise BagError(f"{path}: not rosbag2 metadata (no 'rosbag2_bagfile_information' mapping)")
    return doc["rosbag2_bagfile_information"]


def check_mcap_file(path: Path) -> bool:
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
            info = read_metadata(meta_path)
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
    complete = check_mcap_file(mcap_path)
    return BagInfo(path, mcap_path, custom, has_meta, complete)
