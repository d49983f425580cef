"""The compiled kernel of the pure G2 QIC solve, if it was built.

``qic_solve.c`` (plain C99, built at install by ``setup.py`` as an
optional extension) solves one piece of the QIC spline exactly as the numpy
reference does (:func:`attneave.stimuli.curves.qic.newton.solve_nodes` behind
``attneave.stimuli.curves.qic.spline``): circle-tangent end angles, the small-angle start,
damped Newton on the node angles with the cyclic tridiagonal solve, held (G1)
nodes and given end tangents, and the segments in pixels with their tangent
ranges, in one call. ``clothoid_moments.c`` holds its generalised Fresnel
integrals, Gauss-Legendre sums (numpy's rules where the numpy path sums too,
composite sums where it uses the Fresnel closed form; both reach the rounding
floor), and evaluates clothoid points
(:func:`attneave.stimuli.curves.euler.clothoid_points`) and a spline's samples
(:meth:`attneave.stimuli.curves.qic.result.QICSpline.sample`). The two paths' splines
agree to about 1e-14 (``tests/test_qic_kernel.py`` asks for 1e-12).

It is loaded with ctypes; if it was not built, cannot be loaded, or
``ATTNEAVE_NUMPY_SPLINE=1`` is set, :data:`KERNEL` is ``'numpy'`` and the
numpy path, the reference, is used.
"""

from __future__ import annotations

import ctypes
from pathlib import Path

import numpy as np

from attneave.stimuli.compiled import address as _address
from attneave.stimuli.compiled import load_library

__all__ = ["KERNEL", "LIB", "SIGNATURES", "NO_START", "NO_CONVERGENCE", "DEGENERATE", "solve_piece", "clothoid_xy", "sample_segments",
           "turn_samples"]

_HERE = Path(__file__).resolve().parent
#: Status codes of :func:`solve_piece` (0: solved).
NO_START, NO_CONVERGENCE, DEGENERATE = 1, 2, 3
_NO_MEMORY = 4


_D, _L, _P, _I = ctypes.c_double, ctypes.c_long, ctypes.c_void_p, ctypes.c_int
#: The kernel's interface as Python calls it: name -> (restype, argtypes), one
#: entry per prototype of ``qic_api.h`` that Python calls (checked by
#: tests/test_kernel_interface.py).
SIGNATURES = {
    "attneave_qic_piece": (_L, [_P, _L, _L, _D, _D, _P, _D, _L, _L, _P]),
    "attneave_clothoid_points": (None, [_L] + [_P] * 8),
    "attneave_sample_segments": (_L, [_L, _P, _D, _L] + [_P] * 8 + [_D, _L, _P]),
    "attneave_turn_samples": (_L, [_L, _D, _L, _L, _P, _L, _P, _P, _P]),
}


LIB = load_library(_HERE, "qic_solve", "ATTNEAVE_NUMPY_SPLINE", SIGNATURES)
#: Which QIC solver runs: ``'c'`` (the compiled kernel) or ``'numpy'``.
KERNEL = "numpy" if LIB is None else "c"
_NAN = float("nan")


def solve_piece(Q, closed, t0, t1, theta_hold, tol, max_iter, max_halvings):
    """One piece of the pure G2 QIC spline by the kernel.

    Parameters
    ----------
    Q : ndarray, shape (n, 2)
        The piece's points (float64, C-contiguous; image pixels).
    closed : bool
    t0, t1 : float or None
        Open pieces: tangent angle at the first / last point (None: natural end).
    theta_hold : ndarray, shape (n,), or None
        Tangent angle of each held (G1) node, NaN elsewhere (ignored at an
        open piece's ends).
    tol, max_iter, max_halvings
        As in :func:`attneave.stimuli.curves.qic.newton.solve_nodes`.

    Returns
    -------
    status : int
        0 (solved), :data:`NO_START` (the initial guess gives a degenerate
        segment), :data:`NO_CONVERGENCE`, :data:`DEGENERATE` (a segment
        longer than a million times its chord).
    rows : ndarray, shape (7, m)
        Per segment: tangent angle at its start, start curvature, curvature
        rate (input coordinates, d theta / ds), length (px), range of the
        tangent angle, largest angle to its chord, and the Fresnel integral
        X0 (chord / length).
    info : ndarray
        Newton iterations, status, largest curvature jump over max |k|,
        largest closure residual, largest end-point miss (px).

    Raises
    ------
    MemoryError
        The kernel could not allocate its work arrays.
    """
    n = Q.shape[0]
    m = n if closed else n - 1
    out = np.empty(7 * m + 8)
    status = LIB.attneave_qic_piece(
        _address(Q), n, closed, _NAN if t0 is None else t0, _NAN if t1 is None else t1,
        None if theta_hold is None else _address(theta_hold), tol, max_iter, max_halvings, _address(out),
    )
    if status == _NO_MEMORY:
        raise MemoryError(f"QIC kernel: no memory for the work arrays of {n} points")
    return status, out[: 7 * m].reshape(7, m), out[7 * m :]


def clothoid_xy(x0, y0, theta0, k, dk, s):
    """x, y of :func:`attneave.stimuli.curves.euler.clothoid_points` by the kernel,
    for 1-D float64 C-contiguous arrays of one size."""
    x, y = np.empty(s.size), np.empty(s.size)
    LIB.attneave_clothoid_points(s.size, *(_address(a) for a in (x0, y0, theta0, k, dk, s, x, y)))
    return x, y


def sample_segments(counts, max_step, max_samples, x0, y0, theta0, k0, dk, L, xe, ye, sign):
    """Samples of clothoid segments by the kernel: ``counts[j]`` (>= 2)
    points equally spaced in arc length on segment j, the last one put on
    ``(xe[j], ye[j])`` exactly.

    `counts` is None where `max_step` > 0: then each segment gets as few
    points as keep the tangent's change between neighbours at most
    `max_step` radians, at least 3 and at most ``max(max_samples, 3)``.
    The segments' arrays are 1-D of one length m. Returns the samples'
    counts and the (5, total) array of rows s (arc length from the first
    segment's start), x, y, tangent angle and ``sign`` times curvature.
    """
    m = L.size
    if counts is None:
        counts = np.empty(m, np.int64)
        cap = m * max(int(max_samples), 3)
    else:
        counts = np.ascontiguousarray(counts, np.int64)
        cap = int(counts.sum())
    out = np.empty((5, cap))
    rows = [np.ascontiguousarray(a, np.float64) for a in (x0, y0, theta0, k0, dk, L, xe, ye)]
    total = LIB.attneave_sample_segments(m, _address(counts), max_step, int(max_samples), *(_address(a) for a in rows),
                                         sign, cap, _address(out))
    return counts, out[:, :total]


def turn_samples(max_step, max_samples, P, start, theta0, k0, dk, L):
    """The points of :func:`sample_segments` with ``counts=None`` (as
    :meth:`~attneave.stimuli.curves.qic.result.QICSpline.sample_by_turn` chooses
    them), for the robust rule's checks: only x and y, as rows of an
    (n, 2) array (GEOS's layout), and per segment the largest distance of
    its samples from the line through its chord, computed as
    :func:`attneave.stimuli.curves.qic.rule.segment_bulge` does before its division
    by the mean chord (bit for bit: ``tests/test_qic_kernel.py``).

    Segment j runs from point ``start[j]`` of `P` ((N, 2) float64) to the
    next (cyclic); the segments' arrays are 1-D float64 of one length m."""
    m = L.size
    cap = m * max(int(max_samples), 3)
    # one buffer per kind: each array's address costs about a microsecond, a copy of all less
    seg = np.concatenate((theta0, k0, dk, L))
    P = np.ascontiguousarray(P, np.float64)
    start = np.ascontiguousarray(start, np.int64)
    out = np.empty(2 * cap + m)
    total = LIB.attneave_turn_samples(m, max_step, int(max_samples), cap, _address(P), len(P), _address(start),
                                      _address(seg), _address(out))
    return out[: 2 * total].reshape(total, 2), out[2 * cap :]
