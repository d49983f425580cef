"""Solving the QIC spline piece by piece: the curve is cut at its G0 corners and
each piece between them is solved on its own (damped Newton on the node
tangents, :mod:`attneave.stimuli.curves.qic.newton`, or the compiled kernel),
so that a relaxation of the robust rule re-solves only the pieces it touches.
Used by :func:`attneave.stimuli.curves.qic.spline.qic_spline`.
"""

from __future__ import annotations

import numpy as np

from attneave.stimuli.curves.euler import wrap_angle
from attneave.stimuli.curves.points import chord_end_angles
from attneave.stimuli.curves.qic import kernel as qic_kernel
from attneave.stimuli.curves.qic.newton import NewtonResult, solve_nodes, tangent_range

__all__ = ["PieceFit"]

#: Chord / segment length below which a segment counts as degenerate (length -> inf).
MIN_X0 = 1e-6


def _pieces(N, closed, g0, ts, te):
    """(node indices, closed?, start tangent, end tangent) of the pieces
    between the G0 corners `g0` (sorted)."""
    if closed and not g0:
        return [(np.arange(N), True, None, None)]
    if closed:
        # from the first corner round to it again: with g0 sorted, corner c is at position c - g0[0]
        cuts = [c - g0[0] for c in g0] + [N]
        return [((np.arange(a, b + 1) + g0[0]) % N, False, None, None) for a, b in zip(cuts[:-1], cuts[1:])]
    cuts = [0] + list(g0) + [N - 1]
    return [
        (np.arange(a, b + 1), False, ts if a == 0 else None, te if b == N - 1 else None)
        for a, b in zip(cuts[:-1], cuts[1:])
    ]


def _solve_piece(P, idx, pclosed, t0, t1, held, held_keys, tol, max_iter, max_halvings, ranges):
    """One piece between G0 corners: (segments dict, iterations, G2 error, largest miss / chord), or
    (None, solver result) where Newton fails or a segment degenerates."""
    N = len(P)
    Q = P if idx.size == N and pclosed else P[idx]
    if qic_kernel.LIB is not None:
        theta_hold = None
        if held:
            # by a mask over the points: np.isin costs ~10 us on a few dozen
            mask = np.zeros(N, bool)
            mask[held_keys] = True
            inside = mask[idx]
            if inside.any():
                theta_hold = np.full(idx.size, np.nan)
                theta_hold[inside] = [held[int(i)] for i in idx[inside]]
        status, rows, info = qic_kernel.solve_piece(Q, pclosed, t0, t1, theta_hold, tol, max_iter, max_halvings)
        if status:
            res = None if status == qic_kernel.NO_START else NewtonResult(
                None, None, {"X0": rows[6]}, int(info[0]), status != qic_kernel.NO_CONVERGENCE, info[2], info[3])
            return None, res
        m = rows.shape[1]
        seg = dict(start=idx[:m], x=Q[:m], theta0=rows[0], k0=rows[1], dk=rows[2], L=rows[3])
        if ranges:
            seg.update(turn=rows[4], chord_dev=rows[5])
        return seg, int(info[0]), float(info[2]), float(info[4])
    Qn = np.concatenate((Q[1:], Q[:1])) if pclosed else Q[1:]
    D = Qn - Q[: len(Qn)]
    r = np.hypot(D[:, 0], D[:, 1])
    h = float(np.add.reduce(r)) / r.size  # the mean chord: the piece's scale
    rn = r / h
    phi = np.arctan2(D[:, 1], D[:, 0])
    p0i, p1i = chord_end_angles(phi, rn, pclosed, t0, t1)
    nodes = idx  # node k of the piece is input row idx[k]
    hold = None
    if held:
        hold = np.isin(nodes[: p0i.size + (0 if pclosed else 1)], held_keys)
        if not pclosed:
            # a piece's end nodes are free ends (or the open curve's given tangents)
            hold[0] = hold[-1] = False
        for k in np.flatnonzero(hold):
            th = held[int(nodes[k])]
            if k < p0i.size:
                p0i[k] = wrap_angle(th - phi[k])
            km = k - 1 if k > 0 else (p0i.size - 1 if pclosed else None)
            if km is not None:
                p1i[km] = wrap_angle(th - phi[km])
        if not hold.any():
            hold = None
    res = solve_nodes(p0i, p1i, rn, pclosed, t0 is None, t1 is None, hold, tol, max_iter, max_halvings)
    if res is None or not res.ok or np.minimum.reduce(res.st["X0"]) < MIN_X0:
        return None, res
    st, A = res.st, res.A
    nseg = r.size
    # each segment ends at r (1, G / X0) in its chord frame: the miss is
    # r |G| / X0 (the tests check it independently by sampling)
    miss = float(np.maximum.reduce(np.abs(r * st["G"] / st["X0"])))
    p0 = st["phi0"]  # end angles to the chord, as solved
    seg = dict(start=idx[:nseg], x=Q[:nseg], theta0=phi + p0, k0=st["k0"] / h,
               dk=(st["k1"] - st["k0"]) / st["L"] / h**2, L=st["L"] * h)
    if ranges:
        lo, hi = tangent_range(st["delta"], A)
        seg.update(turn=hi - lo, chord_dev=np.maximum(np.abs(p0 + hi), np.abs(p0 + lo)))
    return seg, res.iterations, res.g2, miss


class PieceFit:
    """Segments of one fit, in order from the first point, before packing; with `ranges` (the robust
    rule) also each segment's tangent range (``turn``) and largest angle to its chord (``chord_dev``).
    With `pieces` (a dict kept across the fits of the robust rule) a piece between G0 corners that an
    earlier fit solved with the same held tangents is taken from it: pieces are solved independently,
    so a relaxation re-solves only the piece(s) it touches; ``iterations`` counts the solved ones."""

    def __init__(self, P, closed, g0, held, ts, te, tol, max_iter, max_halvings=30, ranges=True, pieces=None):
        N = len(P)
        segs, self.iterations, self.g2, miss = [], 0, 0.0, 0.0
        self.failed_piece = None
        held_keys = np.fromiter(held, dtype=int, count=len(held))
        for idx, pclosed, t0, t1 in _pieces(N, closed, g0, ts, te):
            key = None
            if pieces is not None:
                # the held tangents inside the piece, found by the (few) held nodes, not by a
                # Python loop over the piece's nodes (0.16 ms at N = 1000) nor np.isin (~10 us)
                inside = ()
                if held:
                    in_piece = np.zeros(N, bool)
                    in_piece[idx] = True
                    inside = held_keys[in_piece[held_keys]]
                key = (idx.tobytes(), pclosed, t0, t1, tuple((int(k), held[int(k)]) for k in inside))
            solved = key is None or key not in pieces
            out = (_solve_piece(P, idx, pclosed, t0, t1, held, held_keys, tol, max_iter, max_halvings, ranges)
                   if solved else pieces[key])
            if key is not None:
                pieces[key] = out
            if out[0] is None:
                self.failed_piece = (idx, out[1])
                return
            seg, its, g2, m = out
            its = its if solved else 0
            self.iterations += its
            miss = max(miss, m)
            self.g2 = max(self.g2, g2)
            segs.append(seg)
        # the miss relative to the curve's size (by 1-D reductions: along axis 0 of (N, 2) they are slow)
        span = [float(np.maximum.reduce(v) - np.minimum.reduce(v)) for v in (P[:, 0], P[:, 1])]
        size = max(span)
        self.closure = miss / (size or 1.0)
        if len(segs) == 1 and pclosed:
            self.seg = segs[0]
            return
        start = np.concatenate([s["start"] for s in segs])
        # pieces of a closed curve with corners start at the first corner: put
        # the segments back in order from the first point
        order = np.argsort(start, kind="stable")
        self.seg = {key: np.concatenate([s[key] for s in segs])[order] for key in segs[0]}
