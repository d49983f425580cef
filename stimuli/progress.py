"""Progress of a long command on stderr, in a terminal or in a log.

One helper for every command (``generate``, ``extract``, ``analyze``,
``power``, ``figures``): a stage that runs longer than :data:`THRESHOLD`
seconds is announced by one line on stderr while it runs and another when it
ends, whether stderr is a terminal or a log file, so that a batch job's log
shows how far a run of many minutes got; a counted loop adds a line at most
every :data:`EVERY` seconds. Where stderr is a terminal a tqdm bar is drawn as
well. ``quiet`` silences both. It lives in :mod:`attneave.stimuli` so that
both the stimulus and the analysis commands can use it (``stimuli`` never
imports ``analysis``).

Examples
--------
>>> import io
>>> out = io.StringIO()
>>> with Stages("demo", file=out, threshold=0.0) as st:
...     st.stage("reading")
>>> out.getvalue().startswith("attneave demo: reading")
True
"""

from __future__ import annotations

import sys
import threading
import time

__all__ = ["THRESHOLD", "EVERY", "Stages"]

#: Seconds after which a running stage is announced.
THRESHOLD = 2.0
#: Fewest seconds between two lines of a counted loop.
EVERY = 10.0


class Stages:
    """Stage lines (and a tqdm bar on a terminal) on stderr for one command.

    Parameters
    ----------
    command : str
        Named in every line (``attneave COMMAND: ...``).
    quiet : bool
        Nothing at all.
    bar : bool or None
        The tqdm bar: None where `file` is a terminal.
    total : int, optional
        Items of a counted loop (:meth:`advance`); the bar counts them.
    file : file-like, optional
        Default ``sys.stderr`` (looked up when the object is made).
    threshold : float, optional
        Default :data:`THRESHOLD` (read when the object is made, so a test
        may lower it).
    """

    def __init__(self, command, quiet=False, bar=None, total=None, file=None, threshold=None, unit="it"):
        self.command, self.quiet = command, bool(quiet)
        self.file = sys.stderr if file is None else file
        self.threshold = THRESHOLD if threshold is None else float(threshold)
        self.t0 = time.perf_counter()
        self.name, self.started, self.timer = None, None, None
        self.total, self.count, self.last_line = total, 0, self.t0
        self.lock = threading.Lock()
        tty = hasattr(self.file, "isatty") and self.file.isatty()
        show = (tty if bar is None else bool(bar)) and not self.quiet
        self.bar = None
        if show:
            from tqdm import tqdm

            self.bar = tqdm(total=total, desc=command, unit=unit, file=self.file, leave=False, dynamic_ncols=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _line(self, text):
        if self.quiet:
            return
        with self.lock:
            msg = f"attneave {self.command}: {text}"
            try:
                if self.bar is not None:
                    self.bar.write(msg, file=self.file)
                else:
                    print(msg, file=self.file, flush=True)
            except (ValueError, OSError):  # stderr closed under a stage that outlived its command
                pass

    def _elapsed(self):
        return time.perf_counter() - self.t0

    def stage(self, name):
        """End the current stage and start `name`; it is announced if it outlasts the threshold."""
        self._end()
        self.name, self.started = name, time.perf_counter()
        if self.bar is not None:
            self.bar.set_description(f"{self.command}: {name}")
        if self.quiet:
            return
        if self.threshold <= 0:
            self._line(f"{name} ({self._elapsed():.1f} s)")
            return
        if self.threshold == float("inf"):  # never announced; a Timer of inf s overflows time_t in its thread
            return
        self.timer = threading.Timer(self.threshold, self._running, args=(name,))
        self.timer.daemon = True
        self.timer.start()

    def _running(self, name):
        if self.name == name:
            self._line(f"{name} ({self._elapsed():.1f} s)")

    def _end(self):
        if self.timer is not None:
            self.timer.cancel()
            self.timer = None
        if self.name is not None and not self.quiet:
            took = time.perf_counter() - self.started
            if took >= self.threshold > 0:
                self._line(f"{self.name} done in {took:.1f} s")
        self.name = None

    def advance(self, k=1):
        """`k` more items of the counted loop done; a line at most every :data:`EVERY` seconds."""
        self.count += k
        if self.bar is not None:
            self.bar.update(k)
        now = time.perf_counter()
        if not self.quiet and now - self.t0 >= self.threshold and now - self.last_line >= EVERY:
            self.last_line = now
            of = f"/{self.total}" if self.total else ""
            self._line(f"{self.name + ': ' if self.name else ''}{self.count}{of} ({now - self.t0:.1f} s)")

    def close(self):
        """End the last stage (its line if it was long) and the bar."""
        self._end()
        if self.bar is not None:
            self.bar.close()
            self.bar = None
