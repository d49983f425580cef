"""Simulated observers and power analysis (``observers``)."""
