"""A closed contour read from a CSV file of ``x, y`` points, for the recipes that
start from a traced shape (public home: :mod:`attneave.stimuli.shapes.generators`).
"""

from __future__ import annotations

from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.contour import Contour
from attneave.stimuli.validate import as_int

__all__ = ["contour_from_csv"]


def contour_from_csv(path, resample=None):
    """A closed contour from a CSV file with columns ``x, y``.

    The points are taken as they are (image pixels, y down); the recipes
    rescale and centre them onto the canvas.

    Parameters
    ----------
    path : str or Path
        The CSV file.
    resample : int, optional
        Resample to this many equally spaced points (e.g. a pixel-traced
        contour); by default the points are kept.

    Returns
    -------
    contour : Contour
    params : dict
        ``n_points`` (as read), ``n`` (as returned), ``centre`` (the centre
        of the bounding box).

    Raises
    ------
    InputError
        Unreadable file, missing columns, non-finite values, fewer than 3
        distinct points, or a contour that crosses itself.
    """
    c = Contour.from_csv(path, closed=True, simple=True)
    n_read = c.n
    if resample is not None:
        c = c.resample(n=as_int(resample, "resample", lo=3))
        if not c.is_simple():
            raise InputError(f"{path}: resampled to {c.n} points the contour crosses itself; use more points")
    x0, y0, x1, y1 = c.bbox
    return c, dict(n_points=int(n_read), n=int(c.n), centre=[(x0 + x1) / 2.0, (y0 + y1) / 2.0])
