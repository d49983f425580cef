"""Matplotlib without a display and PNG files written atomically: what every
figure module of :mod:`analysis` needs (so that they need not import each
other)."""

from __future__ import annotations

from pathlib import Path

__all__ = ["pyplot", "save_png", "DPI"]

DPI = 120


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend (imported on first use)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_png(fig, path):
    """Save a matplotlib figure as PNG atomically and close it; return the path."""
    from attneave.stimuli.io import atomic_write

    path = Path(path)
    with atomic_write(path, "wb") as fh:
        fig.savefig(fh, format="png", dpi=DPI, metadata={"Software": None})
    pyplot().close(fig)
    return path
