"""Worker processes that do not outlive their parent.

A ``ProcessPoolExecutor``'s workers wait for work on a pipe; if the parent
is killed outright (``kill -9``, the OOM killer) nobody tells them, and they
stay alive holding their memory. Each worker made here asks the kernel to
end it when its parent dies (``prctl(PR_SET_PDEATHSIG, SIGKILL)`` on Linux)
and, on every system, watches its parent's pid from a daemon thread and
exits within about a second of the parent's death. Used by ``generate`` and
``extract`` alike.
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
import time

__all__ = ["orphan_safe_pool", "watch_parent", "POLL_SECONDS"]

#: How often (s) a worker checks that its parent is alive.
POLL_SECONDS = 0.5
_PR_SET_PDEATHSIG = 1  # from <linux/prctl.h>


def watch_parent(parent_pid, interval=POLL_SECONDS):
    """Make this process exit when `parent_pid` is no longer its parent.

    Parameters
    ----------
    parent_pid : int
        The parent's pid, taken in the parent before the worker started.
    interval : float
        Seconds between checks of :func:`os.getppid` (a dead parent's
        children are re-parented, so the pid changes).
    """
    if sys.platform.startswith("linux"):
        with contextlib.suppress(OSError, AttributeError):  # no prctl: the watcher thread still works
            import ctypes
            import signal

            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
    if os.getppid() != parent_pid:  # the parent died before prctl took effect
        os._exit(1)

    def poll():
        while os.getppid() == parent_pid:
            time.sleep(interval)
        os._exit(1)  # no cleanup: the parent owns every output, and a rerun removes what is half-written

    threading.Thread(target=poll, name="attneave-watch-parent", daemon=True).start()


def _init(parent_pid, initializer, initargs):
    watch_parent(parent_pid)
    if initializer is not None:
        initializer(*initargs)


def orphan_safe_pool(max_workers, mp_context=None, initializer=None, initargs=()):
    """A ``ProcessPoolExecutor`` whose workers exit within seconds when the parent dies.

    Parameters
    ----------
    max_workers : int
    mp_context : multiprocessing context, optional
    initializer : callable, optional
        Run in each worker after the watch has started, with `initargs`.
    initargs : tuple

    Returns
    -------
    concurrent.futures.ProcessPoolExecutor
    """
    from concurrent.futures import ProcessPoolExecutor

    return ProcessPoolExecutor(max_workers=max_workers, mp_context=mp_context, initializer=_init,
                               initargs=(os.getpid(), initializer, tuple(initargs)))
