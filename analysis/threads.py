"""One BLAS thread for the analysis's many small linear-algebra calls.

The mixed model factorises a (small + 1)-square matrix (a few hundred rows)
at every Newton step, and the group tests multiply thin matrices. OpenBLAS
splits such calls across its threads, and when another process holds the
other core its threads wait for each other: a 201 x 201 Cholesky took
0.16 s with two threads on a 2-core machine with one core busy, against
0.12 ms with one (numpy 2.4, scipy-openblas 0.3.31). One thread costs
nothing measurable on an idle machine for matrices of this size, so the
analysis always runs with one (threadpoolctl, the tool scikit-learn uses
for the same purpose).

References
----------
.. [1] threadpoolctl, https://github.com/joblib/threadpoolctl
"""

from __future__ import annotations

import contextlib

__all__ = ["one_blas_thread"]


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
