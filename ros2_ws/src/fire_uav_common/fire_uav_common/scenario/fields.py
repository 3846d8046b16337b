"""Field readers of the scenario loader: each checks one value and names its dotted path on error.

Every reader takes the :class:`_Ctx` (the file name), the parsed mapping ``d``, the key and the
path of ``d``; a wrong value raises :class:`ScenarioError` as ``file: path.key: what is wrong``.
:func:`_record` reads a whole all-numbers section straight from its dataclass (field names are
the allowed keys, the dataclass defaults the YAML defaults, fields without one are required).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, TypeVar

from ..errors import ScenarioError

T = TypeVar("T")


class _Ctx:
    def __init__(self, file: str) -> None:
        self.file = file
        self.paths_relative_to: str | None = None  # the scenario's `paths_relative_to`, once read

    def base_dir(self) -> Path:
        """The folder relative file paths in the scenario start from: its ``paths_relative_to``
        if given, else the scenario file's folder (the working directory for a mapping)."""
        if self.paths_relative_to is not None:
            return Path(self.paths_relative_to)
        return Path(self.file).parent if self.file != "<dict>" else Path.cwd()

    def fail(self, path: str, msg: str) -> ScenarioError:
        return ScenarioError(f"{self.file}: {path}: {msg}" if path else f"{self.file}: {msg}")


def _join(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key


def _mapping(
    ctx: _Ctx, value: Any, path: str, allowed: set[str], required: frozenset[str] | set[str] = frozenset()
) -> dict:
    if value is None:
        value = {}
    if not isinstance(value, Mapping):
        raise ctx.fail(path, f"must be a mapping, got {type(value).__name__}")
    for k in value:
        if not isinstance(k, str):
            raise ctx.fail(path, f"keys must be strings, got {k!r}")
        if k not in allowed:
            raise ctx.fail(_join(path, k), f"unknown field; expected one of {sorted(allowed)}")
    for k in sorted(required):
        if k not in value:
            raise ctx.fail(_join(path, k), "required field missing")
    return dict(value)


def _num(
    ctx: _Ctx,
    d: dict,
    key: str,
    path: str,
    default: float | None = None,
    *,
    gt: float | None = None,
    ge: float | None = None,
    le: float | None = None,
    lt: float | None = None,
) -> float:
    p = _join(path, key)
    if key not in d or (d[key] is None and default is not None):
        if default is None:
            raise ctx.fail(p, "required field missing")
        return float(default)
    v = d[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise ctx.fail(p, f"must be a number, got {v!r}")
    v = float(v)
    if not math.isfinite(v):
        raise ctx.fail(p, f"must be finite, got {v}")
    if gt is not None and not v > gt:
        raise ctx.fail(p, f"must be > {gt:g}, got {v:g}")
    if ge is not None and not v >= ge:
        raise ctx.fail(p, f"must be >= {ge:g}, got {v:g}")
    if le is not None and not v <= le:
        raise ctx.fail(p, f"must be <= {le:g}, got {v:g}")
    if lt is not None and not v < lt:
        raise ctx.fail(p, f"must be < {lt:g}, got {v:g}")
    return v


def _int(
    ctx: _Ctx, d: dict, key: str, path: str, default: int | None = None, *, ge: int | None = None
) -> int:
    p = _join(path, key)
    if key not in d:
        if default is None:
            raise ctx.fail(p, "required field missing")
        return int(default)
    v = d[key]
    if isinstance(v, bool) or not isinstance(v, int):
        raise ctx.fail(p, f"must be an integer, got {v!r}")
    if ge is not None and v < ge:
        raise ctx.fail(p, f"must be >= {ge}, got {v}")
    return int(v)


def _bool(ctx: _Ctx, d: dict, key: str, path: str, default: bool) -> bool:
    if key not in d:
        return default
    v = d[key]
    if not isinstance(v, bool):
        raise ctx.fail(_join(path, key), f"must be true or false, got {v!r}")
    return v


def _str(ctx: _Ctx, d: dict, key: str, path: str, default: str | None = None) -> str:
    p = _join(path, key)
    if key not in d:
        if default is None:
            raise ctx.fail(p, "required field missing")
        return default
    v = d[key]
    if not isinstance(v, str) or (default is None and not v.strip()):
        raise ctx.fail(p, f"must be a non-empty string, got {v!r}")
    return v


def _choice(ctx: _Ctx, d: dict, key: str, path: str, allowed: Sequence[T], default: T | None = None) -> T:
    """A string (or, for integer ``allowed``, an integer) that must be one of ``allowed``."""
    if allowed and isinstance(allowed[0], int):
        v: Any = _int(ctx, d, key, path, default)  # type: ignore[arg-type]
    else:
        v = _str(ctx, d, key, path, default)  # type: ignore[arg-type]
    if v not in allowed:
        raise ctx.fail(_join(path, key), f"must be one of {list(allowed)}, got {v!r}")
    return v  # type: ignore[no-any-return]


def _list(ctx: _Ctx, d: dict, key: str, path: str) -> list:
    v = d.get(key)
    if v is None:
        return []
    if not isinstance(v, list):
        raise ctx.fail(_join(path, key), f"must be a list, got {type(v).__name__}")
    return v


def _record(
    ctx: _Ctx,
    raw: Any,
    cls: type[T],
    path: str,
    *,
    defaults: Mapping[str, float] | None = None,
    bounds: Mapping[str, Mapping[str, float]] | None = None,
) -> T:
    """Read the mapping ``raw`` at ``path`` into the all-numbers dataclass ``cls``.

    Keys are ``cls``'s field names; a field's YAML default is ``defaults[name]``, else the
    dataclass default; a field with neither (or a ``None`` default) is required. ``bounds[name]`` are the keyword
    bounds of :func:`_num` (``gt``, ``ge``, ``le``, ``lt``) for that field.
    """
    defaults = defaults or {}
    bounds = bounds or {}
    dflt: dict[str, float | None] = {}
    for f in dataclasses.fields(cls):  # type: ignore[arg-type]
        dflt[f.name] = defaults.get(f.name, None if f.default is dataclasses.MISSING else f.default)  # type: ignore[arg-type]
    required = {k for k, v in dflt.items() if v is None}
    d = _mapping(ctx, raw, path, set(dflt), required)
    return cls(**{k: _num(ctx, d, k, path, v, **bounds.get(k, {})) for k, v in dflt.items()})
