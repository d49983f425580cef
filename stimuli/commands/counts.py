"""Count arguments of the command line (``--points``, ``--samples``): whole
numbers, written plainly or in scientific notation (``1e5``), bounded above
by what an output table can sensibly hold, so that a typo such as ``1e12``
gets one line naming the bound instead of a memory error."""

from __future__ import annotations

#: Most rows a curve or spline table may have (about 50 MB of CSV).
MAX_ROWS = 1_000_000


def count(lo, hi=MAX_ROWS, what="a whole number"):
    """An argparse ``type`` accepting whole numbers in ``[lo, hi]``.

    Examples
    --------
    >>> count(2)("1e3")
    1000
    >>> count(2)("1e8")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: at most 1000000 (the bound on output rows), got 1e8
    """
    import argparse
    import math

    def parse(text):
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}") from None
        if not math.isfinite(v) or v != int(v):
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}")
        if v < lo:
            raise argparse.ArgumentTypeError(f"at least {lo}, got {text}")
        if v > hi:
            raise argparse.ArgumentTypeError(f"at most {hi} (the bound on output rows), got {text}")
        return int(v)

    return parse
