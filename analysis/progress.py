"""Progress of an analysis on stderr."""

from __future__ import annotations

__all__ = ["Progress"]


class Progress:
    """Stages of the analysis on a tqdm bar on stderr; `sub` reports a stage's own progress (0..1)."""

    def __init__(self, enabled):
        import sys

        from tqdm import tqdm

        self.bar = tqdm(total=1000, desc="analyze", file=sys.stderr, disable=None if enabled is None else not enabled,
                        bar_format="{desc}: {percentage:3.0f}%|{bar}| {elapsed}", leave=False)
        self.done = 0
        # share of the run each stage takes (measured on 1,000,000 clicks), so the bar moves evenly
        self.weights = {"predictions": 40, "mapping clicks": 250, "choice models": 100, "correlations": 60,
                        "Monte Carlo group and items tests": 450, "mixed model": 100}
        self.current = None

    def stage(self, name):
        self._finish()
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
