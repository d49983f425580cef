"""Threads in the analysis: one BLAS thread for its many small linear-algebra calls, and an
ordered map over two threads for its large numpy passes.

The mixed model factorises a (small + 1)-square matrix (a few hundred rows)
at every Newton step, and the group tests multiply thin matrices. OpenBLAS
splits such calls across its threads, and when another process holds the
other core its threads wait for each other: a 201 x 201 Cholesky took
0.16 s with two threads on a 2-core machine with one core busy, against
0.12 ms with one (numpy 2.4, scipy-openblas 0.3.31). One thread costs
nothing measurable on an idle machine for matrices of this size, so the
analysis always runs with one (threadpoolctl, the tool scikit-learn uses
for the same purpose).

The Monte Carlo chunks and the choice models' blocks are numpy work that
runs without the GIL, so two threads on two cores run them about twice as
fast; :func:`ordered_map` keeps at most two items per thread in flight (so
memory stays bounded) and, on Ctrl-C or SIGTERM, cancels the items not yet
started instead of waiting for them.

References
----------
.. [1] threadpoolctl, https://github.com/joblib/threadpoolctl
"""

from __future__ import annotations

import contextlib
import os

__all__ = ["MAX_THREADS", "one_blas_thread", "ordered_map"]


@contextlib.contextmanager
def one_blas_thread():
    """Limit the BLAS libraries loaded in this process to one thread inside the block.

    Examples
    --------
    >>> import numpy as np
    >>> with one_blas_thread():
    ...     float(np.linalg.cholesky(np.eye(3) * 4)[0, 0])
    2.0
    """
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        yield


#: Threads for :func:`ordered_map` (measured on the Monte Carlo chunks: 2.2 x faster with two
#: threads on two cores); each item in flight holds its own arrays.
MAX_THREADS = 2


def ordered_map(fn, count):
    """``fn(0), ..., fn(count - 1)`` in order, at most :data:`MAX_THREADS` running at once.

    A generator: item i is computed ahead of its turn only within a window of
    two items per thread. Items not started when the caller stops (an
    exception, Ctrl-C, SIGTERM) are cancelled.

    Examples
    --------
    >>> list(ordered_map(lambda i: i * i, 5))
    [0, 1, 4, 9, 16]
    """
    threads = min(MAX_THREADS, count, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
                  else os.cpu_count() or 1)
    if threads <= 1:
        yield from (fn(i) for i in range(count))
        return
    from concurrent.futures import ThreadPoolExecutor

    ex = ThreadPoolExecutor(threads)
    try:
        pending = [ex.submit(fn, i) for i in range(min(count, 2 * threads))]
        for i in range(count):
            result = pending[i].result()
            pending[i] = None  # its arrays can go
            if i + 2 * threads < count:
                pending.append(ex.submit(fn, i + 2 * threads))
            yield result
    finally:
        # a stop (Ctrl-C, SIGTERM) must not wait for items that have not started
        ex.shutdown(wait=True, cancel_futures=True)

