"""Splines through points by name: the QIC spline (:mod:`attneave.stimuli.curves.qic.spline`),
polynomial baselines (:mod:`attneave.stimuli.curves.polynomial`) and log-aesthetic
splines (G1: :mod:`attneave.stimuli.curves.lac.g1`; G2: :mod:`attneave.stimuli.curves.lac.spline`), behind one entry point,
:func:`fit_spline`, used by ``attneave spline``.
"""

from __future__ import annotations

from dataclasses import replace

from attneave.stimuli.curves.polynomial import PolynomialSpline, polynomial_spline
from attneave.stimuli.curves.qic.spline import ConvergenceError, QICSpline, qic_spline
from attneave.stimuli.errors import InputError
from attneave.stimuli.validate import check_flag

__all__ = [
    "ConvergenceError",
    "QICSpline",
    "PolynomialSpline",
    "qic_spline",
    "polynomial_spline",
    "fit_spline",
    "METHODS",
]

METHODS = ("qic", "qic-g2", "cubic", "cubic-natural", "poly2", "poly3", "poly4", "poly5", "lac-g1", "lac")


def fit_spline(points, method="qic", closed=True, **kwargs):
    """Fit any of the spline methods by name.

    Parameters
    ----------
    points : array_like, shape (N, 2)
        Points ``(x, y)`` in image pixels (y down).
    method : str
        ``'qic'`` (:func:`~attneave.stimuli.curves.qic.spline.qic_spline`, robust), ``'qic-g2'``
        (the same, pure G2), ``'cubic'`` (periodic when closed,
        not-a-knot when open), ``'cubic-natural'`` (open only),
        ``'poly2'`` .. ``'poly5'`` (:func:`~attneave.stimuli.curves.polynomial.polynomial_spline`; ``'poly3'``
        is the same curve as ``'cubic'``), ``'lac-g1'``
        (:func:`attneave.stimuli.curves.lac.g1.lac_g1_spline`), ``'lac'`` (the G2
        log-aesthetic spline, :func:`attneave.stimuli.curves.lac.spline.lac_spline`).
    closed : bool
        Closed curve (default) or open; must be a bool (a string such as
        ``'no'`` is refused).
    **kwargs
        Passed to the fitting function.

    Returns
    -------
    QICSpline, PolynomialSpline, LACSpline or LACG2Spline
        Each has ``sample(k)``, ``metrics(k)``, ``iterations``, ``seconds``
        and ``method``.
    """
    closed = check_flag(closed, "closed")
    if method in ("qic", "qic-g2"):
        return qic_spline(points, closed, robust=method == "qic", **kwargs)
    if method == "cubic":
        return polynomial_spline(points, 3, closed, **kwargs)
    if method == "cubic-natural":
        if closed:
            raise InputError("method: 'cubic-natural' is for open curves (closed=False)")
        return polynomial_spline(points, 3, False, bc_type="natural", **kwargs)
    if method in ("poly2", "poly3", "poly4", "poly5"):
        sp = polynomial_spline(points, int(method[-1]), closed, **kwargs)
        return replace(sp, method=method)
    if method == "lac-g1":
        from attneave.stimuli.curves.lac.g1 import lac_g1_spline

        return lac_g1_spline(points, closed, **kwargs)
    if method == "lac":
        from attneave.stimuli.curves.lac.spline import lac_spline

        return lac_spline(points, closed=closed, **kwargs)
    raise InputError(f"method: expected one of {', '.join(METHODS)}, got {method!r}")
