"""Per-thread scratch buffers for the rasteriser, reused across calls.

Fresh multi-hundred-kilobyte numpy arrays cost page faults on every call:
glibc serves them from ``mmap`` or gives the freed top of its heap back to
the system, so every render faults its temporaries in again. On a 500-vertex
spiky polygon that kernel time (about 1200 faults, 2.5 ms) was twice the
arithmetic. The rasteriser therefore computes into named buffers kept per
thread (so that worker threads never share one) and grown as needed, handed
out several rows at a time because each Python-level call costs about a
microsecond, more when the caches are cold.
"""

from __future__ import annotations

import math
import threading

import numpy as np

_TLS = threading.local()
_MIN = 1 << 12  # elements: small buffers are cheap, keep one allocation
MAX_KEPT = 1 << 23  # elements (64 MB of float64) per buffer and thread


def scratch(name, shape, dtype=np.float64, zeroed=False):
    """A scratch array of `shape` and `dtype`, reused across calls.

    Parameters
    ----------
    name : str
        Key of the buffer; arrays alive at the same time need distinct names.
    shape : int or tuple of int
        Shape of the (C-contiguous) array handed out.
    dtype : numpy dtype, optional
        Element type (a buffer is kept per name and dtype).
    zeroed : bool, optional
        If True the array is all zero when handed out and the caller must
        leave it all zero again.

    Returns
    -------
    ndarray
        A view valid until the next call with the same name and dtype in
        this thread; never hand it to a caller outside the rasteriser.

    Examples
    --------
    >>> a = scratch("doc", (2, 3))
    >>> a[:] = 1.0
    >>> scratch("doc", 4).base is a.base
    True
    """
    n = shape if isinstance(shape, int) else math.prod(shape)
    if n > MAX_KEPT:  # huge images: do not keep hundreds of MB around
        return (np.zeros if zeroed else np.empty)(shape, dtype)
    store = _TLS.__dict__
    key = (name, dtype, zeroed)
    buf = store.get(key)
    if buf is None or buf.size < n:
        grow = 0 if buf is None else min(2 * buf.size, MAX_KEPT)  # amortise growth
        buf = (np.zeros if zeroed else np.empty)(max(n, _MIN, grow), dtype)
        store[key] = buf
    return buf[:n] if n is shape else buf[:n].reshape(shape)


def ramp(n, dtype=np.float64):
    """``np.arange(n, dtype=dtype)`` from a cached buffer (read only)."""
    key = ("ramp", dtype)
    store = _TLS.__dict__
    buf = store.get(key)
    if buf is None or buf.size < n:
        buf = np.arange(max(n, _MIN, 0 if buf is None else 2 * buf.size), dtype=dtype)
        buf.flags.writeable = False
        store[key] = buf
    return buf[:n]
