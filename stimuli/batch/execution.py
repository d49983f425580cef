"""Running the jobs of a batch: in this process, in local worker processes or on Dask.

Local workers are forked processes (one per core at most is useful), made
by :func:`attneave.stimuli.workers.orphan_safe_pool`: when the parent dies (even by
``kill -9``), they exit within a second instead of waiting forever for work
that will never come.
"""

from __future__ import annotations

import contextlib
import math
import sys

from attneave.stimuli.batch.job import run_job
from attneave.stimuli.errors import InputError
from attneave.stimuli.workers import orphan_safe_pool

__all__ = ["execute"]

def _init_worker():
    # one process per core: keep libraries from starting thread pools of their own
    with contextlib.suppress(Exception):
        import cv2

        cv2.setNumThreads(1)


def _run_chunk(chunk, out_dir):
    return [(job["key"], run_job(job, out_dir)) for job in chunk]


def _chunks(jobs, slots):
    size = max(1, min(16, math.ceil(len(jobs) / (4 * max(1, slots)))))
    return [jobs[i:i + size] for i in range(0, len(jobs), size)]


def execute(jobs, out, workers=1, scheduler=None, progress=None, total=None, initial=0):
    """Run `jobs`, writing into `out`; yield ``(key, rows)`` for every job as it finishes.

    Parameters
    ----------
    jobs : list of dict
        From :func:`attneave.stimuli.batch.job.plan_jobs`.
    out : Path
        The set directory.
    workers : int
        Local worker processes; 1 runs the jobs in this process. Never more
        processes than jobs are started.
    scheduler : str or dask.distributed.Client, optional
        Run on Dask instead.
    progress : bool or None
        tqdm bar on stderr; None shows it when stderr is a terminal.
    total, initial : int
        The bar's total and start (jobs complete before this run).
    """
    from tqdm import tqdm

    bar = tqdm(total=len(jobs) if total is None else total, initial=initial, desc="generate", unit="call",
               file=sys.stderr, disable=(None if progress is None else not progress), dynamic_ncols=True)
    try:
        if scheduler is not None:
            yield from _execute_dask(jobs, out, scheduler, bar)
        elif min(workers, len(jobs)) <= 1:
            for job in jobs:
                yield job["key"], run_job(job, out)
                bar.update(1)
        else:
            yield from _execute_pool(jobs, out, min(workers, len(jobs)), bar)
    finally:
        bar.close()


def _execute_pool(jobs, out, workers, bar):
    import multiprocessing
    from concurrent.futures import FIRST_EXCEPTION, wait

    ctx = None
    if sys.platform.startswith("linux"):
        # fork: workers start at once with everything imported, and the caller's
        # __main__ is not re-run (spawn and forkserver would need an
        # ``if __name__ == "__main__"`` guard in every script that calls this)
        ctx = multiprocessing.get_context("fork")
    out_s = str(out.resolve())
    ex = orphan_safe_pool(workers, mp_context=ctx, initializer=_init_worker)
    try:
        futures = {ex.submit(_run_chunk, chunk, out_s): len(chunk) for chunk in _chunks(jobs, workers)}
        pending = set(futures)
        while pending:
            finished, pending = wait(pending, return_when=FIRST_EXCEPTION)
            for fut in finished:
                yield from fut.result()
                bar.update(futures[fut])
    except BaseException:
        # an error or Ctrl-C: stop at once rather than finish the queued chunks; a
        # worker killed mid-write leaves at most a temporary file, which the rerun removes
        _terminate_workers(ex)  # before shutdown(), which forgets the processes
        ex.shutdown(wait=False, cancel_futures=True)
        raise
    ex.shutdown(wait=True)


def _terminate_workers(ex):
    if hasattr(ex, "terminate_workers"):  # Python >= 3.14
        with contextlib.suppress(Exception):
            ex.terminate_workers()
            return
    for proc in list((getattr(ex, "_processes", None) or {}).values()):
        with contextlib.suppress(Exception):
            proc.terminate()


def _execute_dask(jobs, out, scheduler, bar):
    try:
        from dask.distributed import Client, as_completed
    except ImportError:
        raise InputError(
            "--scheduler needs dask.distributed; install it with: pip install 'attneave[dask]'"
        ) from None
    own = not isinstance(scheduler, Client)
    if own:
        try:
            client = Client(scheduler, timeout="20s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise InputError(f"--scheduler {scheduler}: cannot connect ({exc})") from None
    else:
        client = scheduler
    try:
        slots = max(1, sum(client.nthreads().values()))
        chunks = _chunks(jobs, slots)
        futures = client.map(_run_chunk, chunks, out_dir=str(out.resolve()), pure=False)
        sizes = {f.key: len(c) for f, c in zip(futures, chunks)}
        try:
            for fut in as_completed(futures):
                yield from fut.result()
                bar.update(sizes[fut.key])
        except BaseException:
            client.cancel(futures)
            raise
    finally:
        if own:
            client.close()
