"""Benchmarks that need processes: the messaging-only skeleton and the scale runs."""
