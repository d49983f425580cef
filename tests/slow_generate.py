"""``attneave`` with every batch job slowed down, for tests that kill a batch mid-way.

    python tests/slow_generate.py SECONDS generate CONFIG -o DIR ...

Not a test module: the tests run it as a separate process. The sleep is put
in front of each job here, in this process only (forked workers inherit it),
so that production code carries no test hook.
"""

import sys
import time

import attneave.stimuli.batch.execution as execution
from attneave.cli import main

_run_job = execution.run_job


def _slow_run_job(job, out_dir):
    time.sleep(float(sys.argv[1]))
    return _run_job(job, out_dir)


execution.run_job = _slow_run_job

if __name__ == "__main__":
    sys.exit(main(sys.argv[2:]))
