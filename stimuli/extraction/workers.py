"""Worker processes that do not outlive their parent.

A ``ProcessPoolExecutor``'s workers wait for work on a pipe; if the parent
is killed outright (``kill -9``, the OOM killer) nobody tells them, and they
stay alive holding their memory. Each worker here asks the kernel to end it
when its parent dies (``prctl(PR_SET_PDEATHSIG, SIGKILL)`` on Linux) and, on
every system, watches its parent's pid from a daemon thread and exits
within about a second of the parent's death.
"""

from __future__ import annotations

import os
import sys
import threading
import time

__all__ = ["orphan_safe_pool", "POLL_SECONDS"]

#: How often (s) a worker checks that its parent is alive.
POLL_SECONDS = 0.5
_PR_SET_PDEATHSIG = 1


def orphan_safe_pool(max_workers):
    """A ``ProcessPoolExecutor`` whose workers exit within seconds when the parent dies.

    Parameters
    ----------
    max_workers : int

    Returns
    -------
    concurrent.futures.ProcessPoolExecutor
    """
    from concurrent.futures import ProcessPoolExecutor

    return ProcessPoolExecutor(max_workers=max_workers, initializer=_watch_parent, initargs=(os.getpid(),))


def _watch_parent(parent):
    """Worker initialiser: die with the parent (`parent` is its pid, taken before the fork)."""
    if sys.platform.startswith("linux"):
        try:
            import ctypes
            import signal

            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
        except (OSError, AttributeError):  # no prctl: the watcher thread below still works
            pass
    # the parent may have died before prctl took effect: then we are already orphaned
    if os.getppid() != parent:
        os._exit(1)

    def watch():
        while True:
            time.sleep(POLL_SECONDS)
            if os.getppid() != parent:
                os._exit(1)  # no cleanup: the parent, which owns every output, is gone

    threading.Thread(target=watch, name="attneave-parent-watch", daemon=True).start()
