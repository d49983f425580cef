"""Surprisal of a contour read from a CSV file: what ``attneave surprisal`` computes.

:func:`surprisal_of_file` reads the file once (points and their CSV lines),
refuses what the command refuses (a closed contour that crosses itself, more
output points than the caller allows, a spacing that gives fewer than 3
points) with messages that name the file, the CSV line or the argument (its
flag when ``attneave`` runs it, see :func:`attneave.stimuli.argnames.arg`), and
says which points the contour dropped. The geometry is
:func:`attneave.stimuli.geometry.information.surprisal`'s.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.contour import Contour
from attneave.stimuli.geometry.information import surprisal
from attneave.stimuli.validate import arg, as_int, as_number, check_scale

__all__ = ["surprisal_of_file", "dropped_points_note"]


def surprisal_of_file(path, n=None, spacing=None, closed=True, max_points=None, **kwargs):
    """Curvature and surprisal along the contour of a CSV file of ``x, y`` points.

    Parameters
    ----------
    path : str or Path
        CSV file with columns ``x, y`` (image pixels, y down).
    n, spacing : optional
        Number of equally spaced points, or their spacing in px (as
        :func:`~attneave.stimuli.geometry.information.surprisal`; default
        ``n = 100``).
    closed : bool
        A closed contour must be simple: the sign of its curvature (convex +,
        concave -) needs an inside.
    max_points : int, optional
        Most points the result may have (the command's bound on its output),
        checked before anything is allocated.
    **kwargs
        ``model, A, b, bits, prominence, length_unit`` of
        :func:`~attneave.stimuli.geometry.information.surprisal`.

    Returns
    -------
    result : SurprisalResult
    note : str or None
        Which points the contour dropped (consecutive repeats, a closed
        contour's last point repeating its first), with their CSV lines.

    Raises
    ------
    InputError
        One line naming the file (unreadable, too few points, coordinates
        out of range, a closed contour crossing itself) or the argument.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "square.csv"
    >>> _ = path.write_text("x,y\\n0,0\\n100,0\\n100,100\\n0,100\\n0,0\\n")
    >>> r, note = surprisal_of_file(path, n=8)
    >>> len(r.s), note.endswith("which repeats the first (a closed contour joins its last point to its first)")
    (8, True)
    """
    from attneave.stimuli.tables import read_points

    pts, lines = read_points(path, with_lines=True)
    # the bounds every contour has (Contour's own check), with the CSV line of the point at fault
    check_scale(pts, f"{path}: ", labels=[f"line {k}" for k in lines])
    c = Contour(pts, closed, name=str(path))
    if closed and not c.is_simple():
        x, y = c.self_intersections()[0]
        raise InputError(f"{path}: the closed contour crosses itself near (x={x:.6g}, y={y:.6g}); the sign of "
                         "its curvature (convex +, concave -) needs a simple curve (use --open to treat it as "
                         "an open curve)")
    _check_size(c, n, spacing, max_points)
    note = dropped_points_note(pts, lines, closed)
    return surprisal(c, n=n, spacing=spacing, **kwargs), note


def _check_size(contour, n, spacing, max_points):
    """Bound the number of output points before anything is allocated."""
    if n is not None and max_points is not None:
        try:
            as_int(n, arg("n"), lo=3, hi=max_points)
        except InputError:
            raise InputError(f"{arg('n')}: must be 3 <= n <= {max_points:,} points, got {n}") from None
    if spacing is None:
        return
    spacing = as_number(spacing, arg("spacing"), gt=0)
    count = contour.perimeter / spacing
    if max_points is not None and count > max_points:
        raise InputError(f"{arg('spacing')}: {spacing:g} px on a contour of {contour.perimeter:.6g} px gives "
                         f"n = {count:.3g} points; n <= {max_points:,} (use a larger spacing)")
    least = 2.5 if contour.closed else 1.5  # round(n) (+ 1, the end point of an open contour) >= 3
    if count < least:
        raise InputError(f"{arg('spacing')}: {spacing:g} px on a contour of {contour.perimeter:.6g} px gives "
                         f"fewer than 3 points (use a spacing below {contour.perimeter / least:.6g} px)")


def dropped_points_note(pts, lines, closed):
    """Which points a :class:`~attneave.stimuli.geometry.contour.Contour` of `pts` drops, or None.

    Consecutive repeats, and a closed contour's last point when it repeats
    the first (common in real data; accepted), named by their CSV `lines`.
    """
    if len(pts) < 2:
        return None
    same = np.flatnonzero((pts[1:] == pts[:-1]).all(axis=1))
    keep = np.ones(len(pts), bool)
    keep[same + 1] = False
    q = pts[keep]
    closing = closed and len(q) > 1 and (q[-1] == q[0]).all()
    if not (len(same) or closing):
        return None
    parts = []
    if len(same):
        named = ", ".join(str(int(lines[i + 1])) for i in same[:5]) + (", ..." if len(same) > 5 else "")
        parts.append(f"{len(same)} point(s) repeating the one before (line(s) {named})")
    if closing:
        last = int(lines[np.flatnonzero(keep)[-1]])
        parts.append(f"the last point (line {last}), which repeats the first (a closed contour joins "
                     "its last point to its first)")
    return "dropped " + " and ".join(parts)
