"""Test support for the agent package (never imported by the node): :mod:`.harness`."""
