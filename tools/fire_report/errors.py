"""Errors of the report (one line each, naming the input and the problem)."""


class ReportError(Exception):
    """The report cannot be made; the message is one line and names what is wrong."""


class ReportInputError(ReportError, ValueError):
    """An argument of a report function is out of range (a matching gate, ...)."""
