"""Stimulus sets from YAML configs.

``params`` (the recipes' parameter schemas), ``recipes`` (make the items of
one stimulus), ``placement`` and ``drawing`` (canvas and image of an item),
``config`` and ``config_file`` (read, bound and resolve the YAML file),
``errors`` (the one pydantic-error formatter), ``job`` (plan and make one
recipe call), ``outdir`` (the output directory's lock and state),
``execution`` (local workers or Dask) and ``runner`` (the whole batch,
resumable and reproducible)."""

from attneave.stimuli._lazy import attach as _attach

__getattr__, __dir__, __all__ = _attach(__name__, {
    "load_config": ".config",
    "run_batch": ".runner",
    "plan_jobs": ".job",
    "BatchResult": ".runner",
})
