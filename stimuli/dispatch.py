"""Run chunks of independent work in this process, in local worker processes or on Dask.

The machinery shared by ``attneave generate`` (:mod:`attneave.stimuli.batch.execution`)
and ``attneave extract`` (:mod:`attneave.stimuli.extraction.corpus`): the
callers make their outputs independent of where and in which order the
chunks run, so that any of the three gives byte-identical files.

Local workers are forked processes made by
:func:`attneave.stimuli.workers.orphan_safe_pool` (they exit when the parent
dies, even by ``kill -9``). At most a window of chunks is in flight at a
time, so that a run over 100,000 items does not hold 100,000 futures.

References
----------
Dask Development Team, *Dask: Library for dynamic task scheduling* (2016),
https://distributed.dask.org
"""

from __future__ import annotations

import contextlib
import math
import sys

from attneave.stimuli.errors import InputError

__all__ = ["init_worker", "serial_opencv", "chunk_size", "terminate_workers", "dask_client", "run_chunks"]


def init_worker(forked=False):
    """Keep OpenCV in a worker process from starting a thread pool of its own (one process per core).

    Not in a `forked` worker that inherited OpenCV from its parent: it runs
    serially already (:func:`serial_opencv` in the parent), and
    reconfiguring the pool it inherited would wait forever: the parent's
    OpenCV worker threads, asleep on condition variables at the fork, do not
    exist in the child, and ``cv2.setNumThreads`` waits in
    ``pthread_cond_destroy`` for them to leave.
    """
    if forked and "cv2" in sys.modules:
        return
    with contextlib.suppress(Exception):
        import cv2

        cv2.setNumThreads(1)


@contextlib.contextmanager
def serial_opencv():
    """OpenCV in this process single-threaded while local workers are forked from it; restored after.

    Its pool's threads are stopped here, where they exist, so that a forked
    worker neither inherits a pool it cannot reconfigure nor runs as many
    OpenCV threads as there are cores in every process. Nothing is done if
    OpenCV is not imported (a worker then imports and sets it itself).
    """
    cv2 = sys.modules.get("cv2")
    before = None
    with contextlib.suppress(Exception):
        before = cv2.getNumThreads() if cv2 is not None else None
        if before is not None:
            cv2.setNumThreads(1)
    try:
        yield
    finally:
        if before is not None:
            with contextlib.suppress(Exception):
                cv2.setNumThreads(before)


def chunk_size(n, slots, largest=16):
    """Items per chunk: about four chunks per slot, between 1 and `largest`.

    >>> chunk_size(1000, 2), chunk_size(10, 2), chunk_size(0, 4)
    (16, 2, 1)
    """
    return max(1, min(largest, math.ceil(n / (4 * max(1, slots)))))


def terminate_workers(ex):
    """Stop the processes of a ``ProcessPoolExecutor`` at once (an error or Ctrl-C)."""
    if hasattr(ex, "terminate_workers"):  # Python >= 3.14
        with contextlib.suppress(Exception):
            ex.terminate_workers()
            return
    for proc in list((getattr(ex, "_processes", None) or {}).values()):
        with contextlib.suppress(Exception):
            proc.terminate()


@contextlib.contextmanager
def dask_client(scheduler):
    """A ``dask.distributed.Client`` for `scheduler` (an address, or a Client, used as it is).

    Raises
    ------
    InputError
        dask.distributed is not installed, or the scheduler does not answer
        (one line naming ``--scheduler``).
    """
    try:
        from dask.distributed import Client
    except ImportError:
        raise InputError("--scheduler needs dask.distributed; install it with: pip install 'attneave[dask]'") from None
    if isinstance(scheduler, Client):
        yield scheduler
        return
    try:
        client = Client(scheduler, timeout="20s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(f"--scheduler {scheduler}: cannot connect ({exc})") from None
    try:
        yield client
    finally:
        client.close()


def run_chunks(fn, chunks, workers=1, scheduler=None, window=None, **kwargs):
    """Yield ``fn(chunk, **kwargs)`` for every chunk of the iterable `chunks`, in the order they finish.

    Parameters
    ----------
    fn : callable
        A module-level function (it is pickled by reference).
    chunks : iterable
        Consumed lazily: at most `window` chunks are submitted and not yet
        finished at any time.
    workers : int
        Local worker processes; 1 runs the chunks in this process.
    scheduler : str or dask.distributed.Client, optional
        Run on Dask instead (the workers must see the same files at the same paths).
    window : int, optional
        Chunks in flight (default four per worker slot).
    """
    chunks = iter(chunks)
    if scheduler is not None:
        yield from _run_dask(fn, chunks, scheduler, window, kwargs)
    elif workers <= 1:
        for chunk in chunks:
            yield fn(chunk, **kwargs)
    else:
        yield from _run_pool(fn, chunks, workers, window or 4 * workers, kwargs)


def _run_pool(fn, chunks, workers, window, kwargs):
    import multiprocessing

    from attneave.stimuli.workers import orphan_safe_pool

    # fork: workers start at once with everything imported, and the caller's __main__ is not re-run
    ctx = multiprocessing.get_context("fork") if sys.platform.startswith("linux") else None
    with serial_opencv():
        ex = orphan_safe_pool(workers, mp_context=ctx, initializer=init_worker, initargs=(ctx is not None,))
        yield from _run_in(ex, fn, chunks, window, kwargs)


def _run_in(ex, fn, chunks, window, kwargs):
    from concurrent.futures import FIRST_COMPLETED, wait

    try:
        pending = set()
        for chunk in chunks:
            pending.add(ex.submit(fn, chunk, **kwargs))
            while len(pending) >= window:
                finished, pending = wait(pending, return_when=FIRST_COMPLETED)
                for fut in finished:
                    yield fut.result()
        while pending:
            finished, pending = wait(pending, return_when=FIRST_COMPLETED)
            for fut in finished:
                yield fut.result()
    except BaseException:
        # an error or Ctrl-C: stop at once rather than finish the queued chunks
        terminate_workers(ex)  # before shutdown(), which forgets the processes
        ex.shutdown(wait=False, cancel_futures=True)
        raise
    ex.shutdown(wait=True)


def _run_dask(fn, chunks, scheduler, window, kwargs):
    from dask.distributed import as_completed

    with dask_client(scheduler) as client:
        window = window or 4 * max(1, sum(client.nthreads().values()))
        live = []
        queue = as_completed()
        try:
            for chunk in chunks:
                fut = client.submit(fn, chunk, pure=False, **kwargs)
                live.append(fut)
                queue.add(fut)
                while queue.count() >= window:
                    done = next(queue)
                    live.remove(done)
                    yield done.result()
            for done in queue:
                live.remove(done)
                yield done.result()
        except BaseException:
            client.cancel(live)
            raise
