"""The cumulant function of a contour's choice model, tabulated for fast lookups.

For a stimulus with standardised predictions ``z_i`` at its n points, a
participant who clicks point i with probability ``exp(b z_i) / sum exp(b z)``
has log-likelihood ``b z_j - K(b)`` at a click on j, with the cumulant
function ``K(b) = log sum_i exp(b z_i)``; its derivatives in b are the mean
(E), variance (V) and third central moment (T) of z under the choice
probabilities. The mixed model evaluates them at every cell (participant,
stimulus) at each of its steps; this table makes that cost O(cells) whatever
n, by cubic Hermite interpolation of K, E and V (each with the next as its
derivative) on a fine grid of slopes.

"""

from __future__ import annotations

import numpy as np

__all__ = ["CumulantTable"]


class CumulantTable:
    """``K_s(b) = log sum_i exp(b z_si)`` and its derivatives, tabulated per stimulus.

    The grid is split into blocks of `block` steps, computed for all stimuli
    the first time a slope falls in them and kept side by side as one array
    of cubic Hermite coefficients, so that a lookup is one gather and a
    Horner step whatever the blocks its slopes fall in. A fit touches a few
    units of slope, so memory is ``S x (a few hundred) x 12`` values, not the
    whole grid.

    Parameters
    ----------
    Z : (S, n) array_like
        Standardised predictions.
    bound : float
        Slopes are tabulated on ``[-bound, bound]``; beyond it K is extended
        linearly (slope E at the bound, V = 0), which keeps the likelihood
        concave and bounded.
    step : float
        Grid step.
    block : int
        Grid steps per block.
    """

    def __init__(self, Z, bound=12.0, step=0.01, block=50):
        self.Z = np.asarray(Z, dtype=float)
        self.bound, self.step, self.block = float(bound), float(step), int(block)
        self.grid = np.arange(-bound, bound + step / 2, step)
        self._coef = np.empty((self.Z.shape[0], 0, 12))  # (S, steps covered, 12)
        self._k0 = self._k1 = 0  # the blocks covered: k0 <= k < k1

    @property
    def nbytes(self):
        """Memory held by the blocks computed so far."""
        return self._coef.nbytes

    def _coefficients(self, k):
        """Block k as ``(S, block, 12)`` Horner coefficients: for each stimulus and interval, the
        coefficient of ``t**q`` (q = 0..3, major) for K, E and V (minor), t in [0, 1] across the
        interval, so that one gather reads all a cell needs."""
        b = self.grid[k * self.block:(k + 1) * self.block + 1]
        S, n = self.Z.shape
        F = np.empty((S, len(b), 4))  # K, E, V, T at the nodes
        rows = max(1, (1 << 20) // max(n * len(b), 1))  # (rows, nodes, n) values at a time
        chunk = max(1, (1 << 20) // max(n, 1))  # nodes at a time when one stimulus is already large
        for s0 in range(0, S, rows):
            z = self.Z[s0:s0 + rows]
            for g0 in range(0, len(b), chunk):
                bb = b[g0:g0 + chunk]
                x = bb[None, :, None] * z[:, None, :]
                mx = x.max(axis=2, keepdims=True)
                p = np.exp(x - mx)
                sw = p.sum(axis=2)
                p /= sw[:, :, None]
                E = np.einsum("sgn,sn->sg", p, z)
                d = z[:, None, :] - E[:, :, None]
                p *= d * d
                sl = (slice(s0, s0 + rows), slice(g0, g0 + chunk))
                F[sl + (0,)] = np.log(sw) + mx[:, :, 0]
                F[sl + (1,)] = E
                F[sl + (2,)] = p.sum(axis=2)
                F[sl + (3,)] = np.einsum("sgn,sgn->sg", p, d)
        # cubic Hermite on each interval: values f and slopes h f' (the next function) at both ends;
        # the last block may be short, its unused intervals (never looked up) zero
        f0, f1 = F[:, :-1, :3], F[:, 1:, :3]
        d0, d1 = self.step * F[:, :-1, 1:], self.step * F[:, 1:, 1:]
        C = np.zeros((S, self.block, 4, 3))
        m = len(b) - 1
        C[:, :m, 0], C[:, :m, 1] = f0, d0
        C[:, :m, 2] = 3 * (f1 - f0) - 2 * d0 - d1
        C[:, :m, 3] = 2 * (f0 - f1) + d0 + d1
        return C.reshape(S, self.block, 12)

    def _cover(self, lo_k, hi_k):
        """Extend the coefficients to blocks lo_k..hi_k (a copy, rare: a fit's slopes move little)."""
        if self._k0 <= lo_k and hi_k < self._k1:
            return
        if self._k1 == self._k0:
            self._k0 = self._k1 = lo_k
        k0, k1 = min(lo_k, self._k0), max(hi_k + 1, self._k1)
        parts = ([self._coefficients(k) for k in range(k0, self._k0)] + [self._coef]
                 + [self._coefficients(k) for k in range(self._k1, k1)])
        self._coef = np.concatenate(parts, axis=1)
        self._k0, self._k1 = k0, k1

    def _locate(self, b):
        """Clipped slopes, their interval on the grid, and the position t in it."""
        bc = np.clip(b, -self.bound, self.bound)
        x = (bc + self.bound) / self.step
        i = np.minimum(np.floor(x).astype(np.int64), len(self.grid) - 2)
        return bc, i, x - i

    def __call__(self, s, b, dV=False):
        """K, E = K', V = K'' at slopes `b` of stimuli `s` (arrays of one shape); with `dV` also V'
        (the derivative of the interpolated V, so that it is exactly consistent with it)."""
        b = np.asarray(b, dtype=float)
        s = np.broadcast_to(np.asarray(s), b.shape)
        return self._evaluate(s, b, dV)

    def _evaluate(self, s, b, dV):
        s = np.asarray(s, dtype=np.int64).ravel()
        fb = b.ravel()
        if fb.size:
            lo, hi = self._locate(np.array([fb.min(), fb.max()]))[1] // self.block
            self._cover(int(lo), int(hi))
        W, first = self._coef.shape[1], self._k0 * self.block
        C = self._coef.reshape(-1, 12)
        out = np.empty((4 if dV else 3, fb.size))
        # in runs of _RUN cells, so that the gathered coefficients (96 bytes a cell) stay in the
        # cache for the Horner passes: over all cells at once those passes were bound by memory
        for c0 in range(0, fb.size, _RUN):
            sl = slice(c0, c0 + _RUN)
            bb = fb[sl]
            bc, i, t = self._locate(bb)
            i -= first
            i += s[sl] * W
            c = np.take(C, i, axis=0)
            for f in range(3):  # K, E, V by Horner's rule, t in [0, 1] across the interval
                v = out[f, sl]
                np.multiply(c[:, 9 + f], t, out=v)
                for q in (6, 3, 0):
                    v += c[:, q + f]
                    if q:
                        v *= t
            if dV:
                v = out[3, sl]
                np.multiply(c[:, 11], 3 * t, out=v)
                v += 2 * c[:, 8]
                v *= t
                v += c[:, 5]
                v /= self.step
            beyond = np.flatnonzero(bb != bc)
            if beyond.size:  # linear beyond the bound: K + E (b - bound), V = V' = 0
                o = out[:, sl]
                o[0, beyond] += o[1, beyond] * (bb - bc)[beyond]
                o[2:, beyond] = 0.0
        out = out.reshape((-1,) + b.shape)
        return tuple(out)


#: Cells looked up at a time (the gathered coefficients of a run, 0.4 MB, stay in the cache).
_RUN = 4096
