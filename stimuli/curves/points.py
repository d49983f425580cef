"""Points through which a spline passes: validation, the geometric sign of
curvature and first tangent estimates, shared by every spline family.

Points are ``(x, y)`` in image pixels (x = column, y = row, y down) unless a
function says otherwise; a closed curve does not repeat its first point.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.curves.euler import wrap_angle
from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import as_points

__all__ = ["spline_points", "geometric_sign", "chord_end_angles", "circle_tangents", "bisector_tangents", "end_angles"]


def spline_points(points, closed, what="points"):
    """Validate the points of a spline.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Points ``(x, y)``; finite.
    closed : bool
        A closed spline needs 3 points, an open one 2.
    what : str
        Name used in error messages.

    Returns
    -------
    ndarray, shape (N, 2)

    Raises
    ------
    InputError
        Non-finite values, too few points or two consecutive equal points.

    Examples
    --------
    >>> spline_points([[0, 0], [1, 0], [0, 1]], closed=True).shape
    (3, 2)
    """
    P = as_points(points, what)
    need = 3 if closed else 2
    if len(P) < need:
        raise InputError(f"{what}: a {'closed' if closed else 'open'} spline needs at least {need} points, got {len(P)}")
    nxt = np.concatenate((P[1:], P[:1])) if closed else P[1:]
    eq = nxt == P[: len(nxt)]
    same = eq[:, 0] & eq[:, 1]
    if same.any():
        i = int(np.flatnonzero(same)[0])
        j = (i + 1) % len(P)
        hint = " (a closed curve must not repeat its first point at the end)" if closed and j == 0 else ""
        raise InputError(f"{what}: rows {i} and {j} are the same point; consecutive points must differ{hint}")
    return P


def geometric_sign(P, closed, y_down=True):
    """Factor turning d(theta)/ds in the input coordinates into the project's
    geometric curvature sign (positive where a closed curve is convex; for an
    open curve positive for a left turn on the screen).

    Examples
    --------
    >>> geometric_sign([[0, 0], [1, 0], [0, 1]], closed=True)   # positive area
    1.0
    >>> geometric_sign([[0, 0], [1, 0]], closed=False)           # y down
    -1.0
    """
    P = np.asarray(P, dtype=float)
    if closed:
        x, y = P[:, 0], P[:, 1]
        area2 = float(x[:-1] @ y[1:] - x[1:] @ y[:-1] + x[-1] * y[0] - x[0] * y[-1])
        if area2 != 0.0:
            # a traversal whose signed area is positive in these coordinates
            # turns positively at its convex points, in any handedness
            return 1.0 if area2 > 0 else -1.0
    return -1.0 if y_down else 1.0


def chord_end_angles(phi, r, closed, t_start=None, t_end=None):
    """End angles of every segment relative to its chord, from the circle
    through each point and its two neighbours.

    Parameters
    ----------
    phi, r : ndarray, shape (M,)
        Direction (radians) and length of each chord.
    closed : bool
    t_start, t_end : float, optional
        Open curves: tangent angle imposed at the first / last point. A free
        (natural) end gets the small-angle clothoid with zero end curvature,
        ``phi0 = -phi1 / 2``.

    Returns
    -------
    p0, p1 : ndarray, shape (M,)
        Tangent angle minus chord angle at the start and end of each segment.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.pi / 2 * np.arange(4)                   # a square's chords
    >>> p0, p1 = chord_end_angles(t, np.ones(4), closed=True)
    >>> bool(np.allclose(p0, -np.pi / 4) and np.allclose(p1, np.pi / 4))
    True
    """
    m = phi.size
    if closed:
        prev = np.arange(-1, m - 1)
        rp = r[prev]
        t = wrap_angle(phi - phi[prev])
        # inscribed angle: lies between 0 and the turn t, so no wrapping
        beta = np.arctan2(rp * np.sin(t), r + rp * np.cos(t))
        p0 = beta - t
        p1 = np.concatenate((beta[1:], beta[:1]))
        return p0, p1
    p0 = np.zeros(m)
    p1 = np.zeros(m)
    if m > 1:
        t = wrap_angle(phi[1:] - phi[:-1])
        beta = np.arctan2(r[:-1] * np.sin(t), r[1:] + r[:-1] * np.cos(t))
        p1[:-1] = beta
        p0[1:] = beta - t
    if t_start is not None:
        p0[0] = wrap_angle(t_start - phi[0])
    if t_end is not None:
        p1[-1] = wrap_angle(t_end - phi[-1])
    if t_start is None:
        p0[0] = -0.5 * p1[0] if (m > 1 or t_end is not None) else 0.0
    if t_end is None:
        p1[-1] = -0.5 * p0[-1] if (m > 1 or t_start is not None) else 0.0
    return p0, p1


def circle_tangents(P, closed):
    """Tangent angle at each point (input coordinates, radians): the circle
    through it and its two neighbours (open ends: ``phi0 = -phi1 / 2``).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    >>> th = circle_tangents(np.c_[np.cos(t), np.sin(t)], closed=True)
    >>> bool(np.allclose(np.cos(th - t - np.pi / 2), 1))
    True
    """
    P = np.asarray(P, dtype=float)
    D = (np.roll(P, -1, axis=0) - P) if closed else np.diff(P, axis=0)
    r = np.hypot(D[:, 0], D[:, 1])
    phi = np.arctan2(D[:, 1], D[:, 0])
    p0, p1 = chord_end_angles(phi, r / r.mean(), closed)
    theta = phi + p0
    if not closed:
        theta = np.r_[theta, phi[-1] + p1[-1]]
    return theta


def bisector_tangents(P, closed):
    """Tangent angle at each point (input coordinates, radians): the
    direction of the sum of the unit vectors along the two sides that meet
    there, i.e. the bisector of the polygon's turn (open ends: the side).

    Unlike :func:`circle_tangents` it gives both sides the same weight,
    however long they are; at a sharp turn it halves the turn.

    Examples
    --------
    >>> import numpy as np
    >>> th = bisector_tangents(np.array([[0, 0], [4, 0], [4, 1]]), closed=False)
    >>> bool(np.isclose(th[1], np.pi / 4))
    True
    """
    P = np.asarray(P, dtype=float)
    # by 1-D slices of the coordinates: np.roll and (N, 2) reductions cost more than the arithmetic
    x, y = P[:, 0], P[:, 1]
    if closed:
        dx, dy = np.concatenate((x[1:], x[:1])) - x, np.concatenate((y[1:], y[:1])) - y
    else:
        dx, dy = x[1:] - x[:-1], y[1:] - y[:-1]
    r = np.hypot(dx, dy)
    ux, uy = dx / r, dy / r
    if closed:
        bx, by = ux + np.concatenate((ux[-1:], ux[:-1])), uy + np.concatenate((uy[-1:], uy[:-1]))
        nx, ny = -uy, ux
    else:
        bx, by = np.concatenate((ux[:1], ux[1:] + ux[:-1], ux[-1:])), np.concatenate((uy[:1], uy[1:] + uy[:-1], uy[-1:]))
        nx, ny = -np.append(uy, uy[-1]), np.append(ux, ux[-1])
    # a full reversal (turn of pi) has no bisector: use the normal of the side
    flat = np.hypot(bx, by) < 1e-12
    if flat.any():
        bx[flat], by[flat] = nx[flat], ny[flat]
    return np.arctan2(by, bx)


def end_angles(p0, theta0, p1, theta1):
    """Two-point Hermite data in the frame of their chord.

    Returns
    -------
    r, chord, f0, f1 : float
        Chord length and direction (radians), and the tangent angles at the
        two ends minus the chord's, wrapped to (-pi, pi].

    Examples
    --------
    >>> r, chord, f0, f1 = end_angles((0, 0), 0.5, (0, 2), 2.0)
    >>> r, round(chord, 4), round(f0, 4), round(f1, 4)
    (2.0, 1.5708, -1.0708, 0.4292)
    """
    p0 = np.asarray(p0, dtype=float).reshape(2)
    p1 = np.asarray(p1, dtype=float).reshape(2)
    d = p1 - p0
    chord = float(np.arctan2(d[1], d[0]))
    return float(np.hypot(*d)), chord, float(wrap_angle(theta0 - chord)), float(wrap_angle(theta1 - chord))
