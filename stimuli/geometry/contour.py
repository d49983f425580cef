"""The `Contour`: an ordered curve of points in image pixels.

Conventions (see docs/design.md, "Coordinates")
-----------------------------------------------
* Points are ``(x, y)`` floats in image pixels: x is the column, y the row,
  y points down, pixel centres at integer coordinates (OpenCV's convention).
* A closed contour never repeats its first point at the end.
* Closed contours are stored counter-clockwise *as seen on the screen*; the
  constructor reverses a clockwise input, keeping its first point first.
* Curvature is geometric: positive where a closed contour is convex, negative
  where it is concave, whatever the order the points were given in.
* Arc-length position ``t`` in [0, 1) is measured from the first point in the
  stored direction.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.errors import InputError
from attneave.stimuli.geometry.polyline import (
    bounds,
    edges,
    unchecked_crossings,
    unchecked_gaussian_curvature,
    unchecked_nearest,
    unchecked_shoelace,
    unchecked_turning_angles,
)
from attneave.stimuli.validate import (
    MAX_COORDINATE,
    MIN_AREA_RATIO,
    MIN_EXTENT,
    as_int,
    as_number,
    check_area,
    check_flag,
    check_points,
    check_scale,
    check_values,
    count_distinct_upto3,
)

__all__ = ["Contour", "MAX_COORDINATE", "MIN_EXTENT", "MIN_AREA_RATIO"]

_MAX_RESAMPLE = 10**8  # points; 1.6 GB of coordinates, far beyond any stimulus


class Contour:
    """A closed or open curve given by ordered points in image pixels.

    Parameters
    ----------
    points : (N, 2) array_like
        ``(x, y)`` in image pixels: x = column, y = row, y down, pixel centres
        at integer coordinates. For a closed contour do not repeat the first
        point at the end (a repeated end point is dropped).
    closed : bool, optional
        Whether the last point joins the first (default True). A bool: a
        string such as ``'no'`` is refused, not taken as True.
    orient : bool, optional
        Store a closed contour counter-clockwise as seen on the screen,
        reversing it (first point kept first) if needed. Default True.
    simple : bool, optional
        Require a simple curve: raise `InputError` if it crosses itself.
        Default False (a figure eight still has curvature and surprisal).
    name : str, optional
        Used in error messages (e.g. the file it came from).

    Raises
    ------
    InputError
        Non-finite or complex coordinates, a wrong shape, fewer than 3
        distinct points, coordinates beyond +-:data:`MAX_COORDINATE` px, a
        shape smaller than :data:`MIN_EXTENT` px or than 1e-10 of its
        distance from the origin (its geometry would overflow or be rounding
        noise), a closed contour that encloses no area (all points on one
        line, or a path retracing itself: area at most
        :data:`MIN_AREA_RATIO` times the perimeter squared, plus the
        rounding of its coordinates), a `closed`, `orient` or `simple` that
        is not a bool, or (with ``simple=True``) a self-intersection.

    Examples
    --------
    >>> import numpy as np
    >>> th = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    >>> c = Contour(np.c_[100 + 50 * np.cos(th), 100 + 50 * np.sin(th)])
    >>> round(float(c.perimeter), 2), round(float(c.area))
    (314.16, 7854)
    >>> bool(np.allclose(c.curvature(), 1 / 50, rtol=1e-3))
    True
    """

    __slots__ = ("_points", "closed", "name", "_cum")

    def __init__(self, points, closed=True, *, orient=True, simple=False, name=None):
        self.name = name
        where = f"{name}: " if name else ""
        self.closed = check_flag(closed, f"{where}closed")
        orient = check_flag(orient, f"{where}orient")
        simple = check_flag(simple, f"{where}simple")
        p = check_points(points, f"{name}: points" if name else "points")
        check_scale(p, where)
        # consecutive duplicates carry no direction; drop them (and a repeated end point);
        # a copy: the caller's array is neither kept nor frozen
        p = np.array(p, dtype=float, order="C")
        z = p.view(np.complex128).ravel()  # one complex per point: cheap row comparisons
        if len(z) > 1:
            keep = np.ones(len(z), bool)
            np.not_equal(z[1:], z[:-1], out=keep[1:])
            if not keep.all():
                p, z = p[keep], z[keep]
            if self.closed and len(z) > 1 and z[-1] == z[0]:
                p, z = p[:-1], z[:-1]
        distinct = count_distinct_upto3(z)
        if distinct < 3:
            raise InputError(f"{where}a contour needs at least 3 distinct points, got {distinct}")
        area = unchecked_shoelace(p - p[0]) if self.closed else 0.0  # about the first point: no cancellation
        if self.closed and orient and area > 0:
            # y down: a positive shoelace sum is clockwise on the screen
            p = np.concatenate([p[:1], p[:0:-1]])
        p.setflags(write=False)
        self._points = p
        self._cum = None
        if self.closed:
            check_area(abs(area), self.perimeter, p, where)
        if simple:
            self.require_simple()

    @classmethod
    def _trusted(cls, points, closed, name=None):
        """A contour from points already known to be valid and oriented (no checks)."""
        self = object.__new__(cls)
        p = np.array(points, dtype=float)
        p.setflags(write=False)
        self._points, self.closed, self.name, self._cum = p, bool(closed), name, None
        return self

    # ------------------------------------------------------------------ basics
    @property
    def points(self):
        """(N, 2) read-only array of ``(x, y)`` in image pixels."""
        return self._points

    @property
    def n(self):
        """Number of points."""
        return len(self._points)

    def __len__(self):
        return len(self._points)

    def __repr__(self):
        kind = "closed" if self.closed else "open"
        return f"Contour({self.n} points, {kind}, length={self.perimeter:.4g} px)"

    def _segments(self):
        return edges(self._points, self.closed)

    def segment_lengths(self):
        """Lengths of the N (closed) or N-1 (open) segments, in pixels."""
        d = self._segments()
        return np.abs(d.view(np.complex128).ravel())  # hypot of the rows, in one pass

    def _cumulative(self):
        if self._cum is None:
            self._cum = np.concatenate(([0.0], np.cumsum(self.segment_lengths())))
        return self._cum

    @property
    def perimeter(self):
        """Length of the curve in pixels (including the closing segment)."""
        return float(self._cumulative()[-1])

    length = perimeter

    @property
    def signed_area(self):
        """Area in px^2, positive when the points run counter-clockwise on the screen."""
        return -unchecked_shoelace(self._points)

    @property
    def area(self):
        """Enclosed area in px^2 (absolute value of `signed_area`)."""
        return abs(self.signed_area)

    @property
    def centroid(self):
        """Area centroid ``(x, y)`` of a closed contour (vertex mean for an open one)."""
        p = self._points
        if not self.closed:
            return p.mean(axis=0)
        q = np.roll(p, -1, axis=0)
        cross = p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]
        a = cross.sum() / 2
        if a == 0:
            return p.mean(axis=0)
        return np.array([((p[:, 0] + q[:, 0]) * cross).sum(), ((p[:, 1] + q[:, 1]) * cross).sum()]) / (6 * a)

    @property
    def bbox(self):
        """``(xmin, ymin, xmax, ymax)`` in pixels."""
        return bounds(self._points)

    # ------------------------------------------------------------- arc length
    def arclength(self):
        """Arc length ``s`` (px) of every point from the first point."""
        return self._cumulative()[: self.n].copy()

    def t(self):
        """Arc-length position ``t = s / perimeter`` in [0, 1) of every point."""
        return self.arclength() / self.perimeter

    def point_at(self, t):
        """Points at arc-length positions `t` (fractions of the perimeter).

        Parameters
        ----------
        t : array_like
            Positions; for a closed contour taken modulo 1, for an open one
            clipped to [0, 1].

        Returns
        -------
        (M, 2) ndarray
            ``(x, y)`` in image pixels.

        Raises
        ------
        InputError
            `t` not finite numbers.
        """
        t = np.atleast_1d(check_values(t, "t"))
        if t.ndim != 1:
            raise InputError(f"t: expected a number or a 1-D array of positions, got shape {t.shape}")
        t = np.mod(t, 1.0) if self.closed else np.clip(t, 0.0, 1.0)
        return self._at_arclength(t * self.perimeter)

    def _at_arclength(self, s):
        """Points at arc lengths `s` in [0, perimeter] (px), by linear interpolation."""
        cum = self._cumulative()
        p = self._points
        ring = np.concatenate((p, p[:1])) if self.closed else p
        out = np.empty((len(s), 2))
        # np.interp on contiguous columns: a strided column would be copied first
        out[:, 0] = np.interp(s, cum, np.ascontiguousarray(ring[:, 0]))
        out[:, 1] = np.interp(s, cum, np.ascontiguousarray(ring[:, 1]))
        return out

    def resample(self, n=None, spacing=None):
        """Equally spaced points along the arc, starting at the first point.

        Parameters
        ----------
        n : int, optional
            Number of points (closed: spacing ``L/n``; open: ``n`` points
            including both ends, spacing ``L/(n-1)``).
        spacing : float, optional
            Target spacing in pixels; ``n`` is the nearest count that divides
            the length evenly. Give exactly one of `n` and `spacing`.

        Returns
        -------
        Contour
            The resampled contour (same orientation). Its actual spacing is
            ``perimeter / n`` of the original for a closed contour.

        Raises
        ------
        InputError
            When both or neither of `n`, `spacing` are given, `n` is not an
            integer >= 3 (3.7 is refused, not truncated), or `spacing` is
            not a finite number > 0.
        """
        n = self._resolve_n(n, spacing)
        L = self.perimeter
        s = np.arange(n) * (L / n) if self.closed else np.linspace(0.0, L, n)
        # equal arc steps of a valid contour are distinct: no need to re-validate
        return Contour._trusted(self._at_arclength(s), self.closed, name=self.name)

    def _resolve_n(self, n, spacing):
        if (n is None) == (spacing is None):
            raise InputError("give exactly one of n and spacing")
        if spacing is not None:
            spacing = as_number(spacing, "spacing", gt=0)
            n = int(round(self.perimeter / spacing)) + (0 if self.closed else 1)
            if n < 3:
                raise InputError(f"spacing: {spacing:g} px gives n = {n}; resampling needs n >= 3 points")
        n = as_int(n, "n")
        if n < 3:
            raise InputError(f"n: resampling needs n >= 3 points, got {n}")
        if n > _MAX_RESAMPLE:
            # an absurd n (or a tiny spacing) would otherwise die allocating terabytes
            what = f"spacing {spacing} px gives" if spacing is not None else "got"
            raise InputError(f"resampling needs n <= {_MAX_RESAMPLE:.0e} points; {what} n = {n}")
        return n

    # --------------------------------------------------------------- geometry
    def turning_angles(self):
        """Signed turning angle (rad) at every point; see :func:`turning_angles`."""
        return unchecked_turning_angles(self._points, self.closed)

    def curvature(self, method="exact", sigma=None):
        """Signed curvature (1/px) at every point, positive where convex.

        Parameters
        ----------
        method : {'exact', 'gaussian'}
            ``'exact'``: turning angle divided by the mean length of the two
            adjacent segments. Exact for clean input (a regular n-gon
            inscribed in a circle of radius R gives 1/R up to (pi/n)^2/6) and
            finite at corners. ``'gaussian'``: for noisy input (pixel-traced
            contours); the contour is resampled at equal arc-length steps,
            differentiated with a periodic Gaussian derivative in the Fourier
            domain (see :func:`gaussian_curvature`) and read back at the
            points' own arc positions. Closed contours only.
        sigma : float, optional
            Gaussian scale in pixels of arc length; default 1% of the perimeter.

        Returns
        -------
        (N,) ndarray
            NaN at the two ends of an open contour (method 'exact').

        Raises
        ------
        InputError
            An unknown `method`, 'gaussian' on an open contour, or a `sigma`
            that is not a finite number > 0.
        """
        if method == "exact":
            a = self.turning_angles()
            seg = self.segment_lengths()
            if self.closed:
                ds = 0.5 * (seg + np.roll(seg, 1))
            else:
                ds = np.concatenate(([np.nan], 0.5 * (seg[1:] + seg[:-1]), [np.nan]))
            return a / ds
        if method == "gaussian":
            if not self.closed:
                raise InputError("gaussian curvature is for closed contours")
            sigma = 0.01 * self.perimeter if sigma is None else as_number(sigma, "sigma", gt=0)
            # sample finely enough that sigma spans several samples
            m = int(max(self.n, np.ceil(8 * self.perimeter / sigma), 64))
            uni = self.resample(n=m)
            k = unchecked_gaussian_curvature(uni.points, sigma)
            s = np.arange(m + 1) * (self.perimeter / m)
            return np.interp(self.arclength(), s, np.append(k, k[0]))
        raise InputError(f"unknown curvature method {method!r}; expected 'exact' or 'gaussian'")

    def project(self, points, chunk=2_000_000):
        """Nearest point on the contour to each of `points`.

        Parameters
        ----------
        points : (M, 2) array_like
            ``(x, y)`` in image pixels.
        chunk : int
            Upper bound on query-by-segment pairs held in memory at once.

        Returns
        -------
        nearest : (M, 2) ndarray
            The closest points on the curve (on segments, not only vertices).
        t : (M,) ndarray
            Their arc-length positions in [0, 1).
        distance : (M,) ndarray
            Euclidean distance in pixels.

        Raises
        ------
        InputError
            `points` not (M, 2) (or one ``(x, y)``) finite numbers.
        """
        try:
            one = np.ndim(points) == 1  # a single (x, y)
        except ValueError:  # ragged rows: check_points names them
            one = False
        q = check_points(np.atleast_2d(points) if one else points, "points", min_points=0)
        return unchecked_nearest(q, self._points, self._segments(), self._cumulative(), self.closed, chunk)

    # ------------------------------------------------------------- simplicity
    def self_intersections(self):
        """Points where the curve crosses or touches itself (empty if simple).

        Uses GEOS (through shapely) so that the test is exact and fast.

        Returns
        -------
        (K, 2) ndarray
            ``(x, y)`` of the crossings found.
        """
        return unchecked_crossings(self._points, self.closed)

    def is_simple(self):
        """True when the curve does not cross or touch itself."""
        import shapely

        ring = np.vstack([self._points, self._points[:1]]) if self.closed else self._points
        return bool(shapely.is_simple(shapely.LineString(ring)))

    def require_simple(self):
        """Raise `InputError` naming a crossing if the curve is not simple."""
        if not self.is_simple():
            x, y = self.self_intersections()[0]
            where = f"{self.name}: " if self.name else ""
            raise InputError(f"{where}the contour crosses itself near (x={x:.3f}, y={y:.3f}); a simple curve is needed")
        return self

    # ---------------------------------------------------------- transforms
    def reversed(self):
        """The same curve traversed the other way (a closed one keeps its first
        point and is not re-oriented, so its curvature signs flip)."""
        p = self._points
        q = np.concatenate([p[:1], p[:0:-1]]) if self.closed else p[::-1]
        return Contour(q, self.closed, orient=False, name=self.name)

    def transformed(self, scale=1.0, offset=(0.0, 0.0)):
        """``points * scale + offset``, orientation kept.

        Parameters
        ----------
        scale : float
            A finite number > 0.
        offset : (2,) array_like
            ``(dx, dy)`` in image pixels, finite.

        Returns
        -------
        Contour

        Raises
        ------
        InputError
            A `scale` or `offset` out of range, or a result whose size the
            :class:`Contour` rules refuse.
        """
        scale = as_number(scale, "scale", gt=0)
        off = check_values(offset, "offset")
        if off.shape != (2,):
            raise InputError(f"offset: expected (dx, dy), got shape {off.shape}")
        return Contour(self._points * scale + off, self.closed, orient=False, name=self.name)

    # --------------------------------------------------------------------- io
    @classmethod
    def from_csv(cls, path, closed=True, **kwargs):
        """Read a contour from a CSV file with columns ``x, y`` (image pixels).

        Parameters
        ----------
        path : str or path-like
            The CSV file.
        closed : bool
            Whether the last point joins the first.
        **kwargs
            Passed to :class:`Contour` (``name`` defaults to `path`).

        Returns
        -------
        Contour

        Raises
        ------
        InputError
            Missing columns, non-numeric or NaN values (naming the line), or
            fewer than 3 distinct points.
        """
        from attneave.stimuli.tables import read_points

        kwargs.setdefault("name", str(path))
        return cls(read_points(path), closed, **kwargs)

    def to_csv(self, path):
        """Write columns ``x, y`` (image pixels) to `path` atomically, in stored order.

        Parameters
        ----------
        path : str or path-like
            The CSV file to write.
        """
        from attneave.stimuli.tables import write_table

        write_table({"x": self._points[:, 0], "y": self._points[:, 1]}, path)
