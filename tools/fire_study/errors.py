"""The one error a study raises for bad input or a refused resume: its message is one line."""

from __future__ import annotations

__all__ = ["StudyError"]


class StudyError(ValueError):
    """Bad study file, refused results directory, ...: ``str(e)`` names the file and the field."""
