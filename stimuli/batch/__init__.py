"""Stimulus sets from YAML configs: the config schema (``config``), the
recipes that make and draw items (``recipes``) and the runner that writes a
set reproducibly and resumably (``runner``)."""

from stimuli._lazy import attach as _attach

__getattr__, __dir__, __all__ = _attach(__name__, {
    "load_config": ".config",
    "run_batch": ".runner",
    "plan_jobs": ".runner",
    "BatchResult": ".runner",
})
