"""Report sections per capability, each present only when the mission used it.

A section module (``pm``: perimeter monitoring, ``cp``: coverage search) has
``build(mission, data, out) -> Section | None``: None when the bag holds none of its traffic.
This package holds only the :class:`Section` record the modules fill; the report
(``fire_report.report``) runs them and ``fire_report.page`` renders them, so no section module
is imported from here (each one imports this record).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

Figure = tuple[str, str]


@dataclass
class Section:
    """One capability's part of the page: a heading, a table of numbers, figures, notes."""

    key: str  # metrics.json key ("pm", "cp"), also the page anchor
    heading: str
    rows: list[tuple[str, str]] = field(default_factory=list)
    figures: list[Figure] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    metrics: dict[str, Any] = field(default_factory=dict)


__all__ = ["Figure", "Section"]
