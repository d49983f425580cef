"""Threads of the analysis: one BLAS thread for its many small linear-algebra calls, and
:func:`threaded_map` for its large elementwise numpy passes.

The mixed model factorises a (small + 1)-square matrix (a few hundred rows)
at every Newton step, and the group tests multiply thin matrices. OpenBLAS
splits such calls across its threads, and when another process holds the
other core its threads wait for each other: a 201 x 201 Cholesky took
0.16 s with two threads on a 2-core machine with one core busy, against
0.12 ms with one (numpy 2.4, scipy-openblas 0.3.31). One thread costs
nothing measurable on an idle machine for matrices of this size, so the
analysis always runs with one (threadpoolctl, the tool scikit-learn uses
for the same purpose).

The large passes (the Monte Carlo chunks, the choice models' blocks, the
mixed model's table lookups, the mapping of clicks per stimulus) run numpy
without the GIL, so two Python threads use two cores: the Monte Carlo stage
of 1,000,000 clicks took 12.4 s instead of 24.5 s. Each item writes its own
slice or returns its own result, so the values are those of one thread.

References
----------
.. [1] threadpoolctl, https://github.com/joblib/threadpoolctl
"""

from __future__ import annotations

import contextlib
import os

__all__ = ["one_blas_thread", "threaded_map", "MAX_THREADS"]

#: Threads of :func:`threaded_map` (at most the cores this process may use); each item in flight
#: holds its own arrays, which the memory plan (:mod:`attneave.analysis.budget`) counts.
MAX_THREADS = 2


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


def threaded_map(fn, items, minimum=2):
    """Yield ``fn(item)`` for each of `items`, in order, on up to :data:`MAX_THREADS` threads.

    Fewer than `minimum` items, or one usable core, run in this thread. At
    most two items per thread are submitted ahead of the one yielded, so the
    memory in flight stays bounded; a stop (Ctrl-C, SIGTERM) raised while
    waiting cancels the items not yet started instead of waiting for them.

    Examples
    --------
    >>> list(threaded_map(lambda v: v * v, range(5)))
    [0, 1, 4, 9, 16]
    """
    items = list(items)
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
    threads = min(MAX_THREADS, len(items), cores)
    if threads <= 1 or len(items) < minimum:
        yield from map(fn, items)
        return
    from concurrent.futures import ThreadPoolExecutor

    ahead = 2 * threads
    ex = ThreadPoolExecutor(threads)
    try:
        pending = [ex.submit(fn, item) for item in items[:ahead]]
        for i in range(len(items)):
            result = pending[i].result()
            pending[i] = None  # its arrays can go
            if i + ahead < len(items):
                pending.append(ex.submit(fn, items[i + ahead]))
            yield result
    finally:
        ex.shutdown(wait=True, cancel_futures=True)
