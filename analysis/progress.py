"""Progress of an analysis on stderr (:class:`attneave.stimuli.progress.Stages` with the analysis's stages)."""

from __future__ import annotations

from attneave.stimuli.progress import Stages

__all__ = ["Progress"]


class Progress(Stages):
    """Stages of the analysis: a line on stderr for every stage over the threshold (terminal or log),
    and a bar weighted by the share of the run each stage takes where stderr is a terminal (or when
    `enabled` is True); `sub` reports a stage's own progress (0..1); `quiet` silences both.
    """

    #: share of the run each stage takes (measured on 1,000,000 clicks), so the bar moves evenly
    WEIGHTS = {"predictions": 40, "mapping clicks": 250, "choice models": 100, "correlations": 60,
               "Monte Carlo group and items tests": 450, "mixed model": 100}

    def __init__(self, enabled=None, quiet=False):
        super().__init__("analyze", quiet=quiet, bar=enabled, total=1000, unit="")
        self.done = self.start = 0

    def stage(self, name):
        self.sub(1.0)
        super().stage(name)
        self.start = self.done

    def sub(self, fraction):
        target = int(self.start + fraction * self.WEIGHTS.get(self.name, 0))
        if self.bar is not None and target > self.done:
            self.bar.update(target - self.done)
        self.done = max(self.done, target)
