"""Report sections per capability, each present only when the mission used it.

A section module has ``build(mission, data, out) -> Section | None``: None when the bag holds
none of its traffic. ``make_sections`` runs them all; ``render_section`` gives its HTML.
FF stays the page's main body (``fire_report.report``); PM (``pm``) and CP (``cp``) are here.
"""

from __future__ import annotations

import html
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from fire_report.data import Mission
from fire_report.sections.bagdata import SectionData, load_section_data

Figure = tuple[str, str]


@dataclass
class Section:
    """One capability's part of the page: a heading, a table of numbers, figures, notes."""

    key: str  # metrics.json key ("pm", "cp")
    heading: str
    rows: list[tuple[str, str]] = field(default_factory=list)
    figures: list[Figure] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    metrics: dict[str, Any] = field(default_factory=dict)


def make_sections(mission: Mission, out: Path, *, salvage: bool = True) -> list[Section]:
    """Every section the bag has data for (figures written into ``out``)."""
    from fire_report.sections import cp, pm

    data: SectionData = load_section_data(mission.path, mission.topics, salvage=salvage)
    found = [mod.build(mission, data, out) for mod in (pm, cp)]
    return [s for s in found if s is not None]


def render_section(s: Section) -> str:
    e = html.escape
    rows = "".join(f"<tr><th>{e(k)}</th><td>{e(v)}</td></tr>" for k, v in s.rows)
    figs = "".join(
        f'<figure><img src="{e(name)}" alt="{e(cap)}"><figcaption>{e(cap)}</figcaption></figure>'
        for name, cap in s.figures
    )
    notes = "".join(f"<li>{e(n)}</li>" for n in s.notes)
    return (
        f'<section id="{e(s.key)}"><h2>{e(s.heading)}</h2>'
        + (f"<table>{rows}</table>" if rows else "")
        + (f"<ul>{notes}</ul>" if notes else "")
        + figs
        + "</section>"
    )


__all__ = ["Section", "make_sections", "render_section"]
