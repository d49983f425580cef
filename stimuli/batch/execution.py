"""Running the jobs of a batch: in this process, in local worker processes or on Dask.

The pool and the Dask client are :mod:`attneave.stimuli.dispatch`'s (shared
with ``extract``): local workers are forked processes made by
:func:`attneave.stimuli.workers.orphan_safe_pool` (when the parent dies, even by
``kill -9``, they exit within a second instead of waiting forever for work
that will never come), with OpenCV serial in each.
"""

from __future__ import annotations

import sys

from attneave.stimuli.batch.job import run_job
from attneave.stimuli.dispatch import chunk_size, dask_client, run_chunks

__all__ = ["execute"]


def _run_chunk(chunk, out_dir):
    # run_job looked up here at call time (tests/slow_generate.py slows it down in this module)
    return [(job["key"], run_job(job, out_dir)) for job in chunk]


def _chunks(jobs, slots):
    size = chunk_size(len(jobs), slots)
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
            with dask_client(scheduler) as client:
                slots = max(1, sum(client.nthreads().values()))
                yield from _report(run_chunks(_run_chunk, _chunks(jobs, slots), scheduler=client,
                                              out_dir=str(out.resolve())), bar)
        elif min(workers, len(jobs)) <= 1:
            for job in jobs:
                yield job["key"], run_job(job, out)
                bar.update(1)
        else:
            workers = min(workers, len(jobs))
            yield from _report(run_chunks(_run_chunk, _chunks(jobs, workers), workers=workers,
                                          out_dir=str(out.resolve())), bar)
    finally:
        bar.close()


def _report(results, bar):
    """Yield the ``(key, rows)`` of every finished chunk; advance the bar by its jobs."""
    for chunk in results:
        yield from chunk
        bar.update(len(chunk))
