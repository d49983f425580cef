"""Progress of an analysis on stderr."""

from __future__ import annotations

__all__ = ["Progress"]


class Progress:
    """Stages of the analysis on a tqdm bar on stderr; `sub` reports a stage's own progress (0..1).

    The bar is drawn where stderr is a terminal (or when `enabled` is True).
    Where it is not (a log file, a batch job) and `announce` is True -- a
    long run -- each stage is written as one line with the time so far, so
    that a log shows how far a run of many minutes got.
    """

    def __init__(self, enabled, announce=False):
        import sys
        import time

        from tqdm import tqdm

        self.lines = announce and (enabled is False or (enabled is None and not sys.stderr.isatty()))
        self.t0 = time.perf_counter()

        self.bar = tqdm(total=1000, desc="analyze", file=sys.stderr, disable=None if enabled is None else not enabled,
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| {elapsed}", leave=False)
        self.done = 0
        # share of the run each stage takes (measured on 1,000,000 clicks), so the bar moves evenly
        self.weights = {"predictions": 40, "mapping clicks": 250, "choice models": 100, "correlations": 60,
                        "Monte Carlo group and items tests": 450, "mixed model": 100}
        self.current = None

    def stage(self, name):
        self._finish()
        if self.lines:
            import sys
            import time

            print(f"attneave analyze: {name} ({time.perf_counter() - self.t0:.1f} s)", file=sys.stderr, flush=True)
        self.current = name
        self.start = self.done
        self.bar.set_description(f"analyze: {name}")

    def sub(self, fraction):
        self.bar.update(int(self.start + fraction * self.weights.get(self.current, 0)) - self.done)
        self.done = int(self.start + fraction * self.weights.get(self.current, 0))

    def _finish(self):
        if self.current is not None:
            self.sub(1.0)

    def close(self):
        self._finish()
        self.bar.close()
