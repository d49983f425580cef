"""The check that a concave/convex pair of deformations is what it claims to be
(Barenholtz et al., 2003): the moved vertex concave in one version and convex in
the other, every other vertex (outside a bump) turning as in the base shape, and
neither version crossing itself. Public home:
:mod:`attneave.stimuli.shapes.deformations`, which re-exports :func:`check_deformation`.
"""

from __future__ import annotations

import numpy as np

__all__ = ["check_deformation", "STRAIGHT_TURN"]

#: Turning angles (rad) within this of 0 count as straight.
STRAIGHT_TURN = 1e-9


def check_deformation(base, concave, convex, index, window=None, min_turn=0.0):
    """Whether a concave/convex pair meets the conditions of a valid place.

    Parameters
    ----------
    base, concave, convex : Contour
        Same number of points.
    index : int
        The moved vertex.
    window : array of bool, optional
        Vertices moved by a bump (where the dent may turn several vertices
        concave). Default: only `index`.
    min_turn : float
        The moved vertex's turning angle must be below ``-min_turn`` in the
        concave version and above ``min_turn`` in the convex one (radians).

    Returns
    -------
    ok : bool
    reason : str
        Empty when valid, else why not.
    """
    tb, tc, tv = base.turning_angles(), concave.turning_angles(), convex.turning_angles()
    thr = max(STRAIGHT_TURN, float(min_turn))
    if not tc[index] < -thr:
        return False, "the concave version's vertex is not concave"
    if not tv[index] > thr:
        return False, "the convex version's vertex is not convex"
    nb, nc, nv = tb < -STRAIGHT_TURN, tc < -STRAIGHT_TURN, tv < -STRAIGHT_TURN
    others = np.ones(len(tb), bool)
    others[index] = False
    if np.any(nv[others] != nb[others]):
        return False, "the convex version changes the sign of another vertex"
    if window is None:
        if np.any(nc[others] != nb[others]):
            return False, "the concave version changes the sign of another vertex"
    else:
        window = np.asarray(window, bool)
        outside = ~window
        if np.any(nc[outside] != nb[outside]):
            return False, "the concave version changes the sign of a vertex outside the bump"
        if np.any(nb[window]):
            return False, "the bump would overlap a concavity of the base"
        # the dent's concave vertices must be one run through the centre
        run = _run_through(nc, index)
        if np.any(nc & window & ~run):
            return False, "the dent is concave in more than one place"
    if not concave.is_simple():
        return False, "the concave version crosses itself"
    if not convex.is_simple():
        return False, "the convex version crosses itself"
    return True, ""


def _run_through(flags, index):
    """Boolean mask of the circular run of True in `flags` containing `index`."""
    n = len(flags)
    out = np.zeros(n, bool)
    if not flags[index]:
        return out
    out[index] = True
    for step in (1, -1):
        j = (index + step) % n
        while flags[j] and not out[j]:
            out[j] = True
            j = (j + step) % n
    return out
