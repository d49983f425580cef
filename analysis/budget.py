"""Which models an analysis runs, and whether it fits in memory before anything heavy is allocated.

:func:`choose_models` reads the ``models`` argument of
:func:`attneave.analysis.analyze.analyze` (``--models`` of ``attneave
analyze``); :func:`estimate` gives the peak memory of each stage from the
sizes of the design alone (stimuli, points per contour, clicks,
participants, grid), and :func:`plan` refuses a run that would not fit, in
one line naming the option to change, or leaves out an optional model that
would not fit when it was not asked for by name.

The estimates are upper bounds of the arrays each stage holds at once
(measured on the benchmarks of ``benchmarks/bench_analysis.py --scale``),
not of Python's own overhead.
"""

from __future__ import annotations

import os

from attneave.analysis.argnames import arg
from attneave.stimuli.errors import InputError

__all__ = ["MODELS", "OPTIONAL", "choose_models", "available_bytes", "estimate", "plan"]

#: The models of an analysis. ``choice`` (the pooled fit of the tested prediction, and the
#: per-participant and per-stimulus betas) always runs: every other result is read beside it.
MODELS = {
    "choice": "pooled, per-participant and per-stimulus conditional logit of the tested prediction",
    "rivals": "each rival predictor fitted alone, compared by AIC (models.csv)",
    "joint": "the predictors of --predictors fitted jointly, with likelihood-ratio tests",
    "blurred": "the pooled fit observed through the click localisation error (--click-sd)",
    "mixed": "the mixed conditional logit with crossed random slopes (participants, stimuli)",
    "group": "the Monte Carlo nulls of the group and items tests (--group-simulations)",
}
OPTIONAL = tuple(k for k in MODELS if k != "choice")


def choose_models(models):
    """The set of models asked for, and whether they were named (True) or the default (False).

    Parameters
    ----------
    models : str, sequence of str or None
        Names among :data:`MODELS`, as a sequence or one comma-separated
        string; None or ``"all"``: every model (those that do not fit in
        memory are then left out, with the reason, rather than refused).

    Examples
    --------
    >>> sorted(choose_models("mixed,group")[0])
    ['choice', 'group', 'mixed']
    >>> choose_models(None)[1]
    False
    """
    if models is None or (isinstance(models, str) and models.strip() == "all"):
        return set(MODELS), False
    names = [v.strip() for v in models.split(",")] if isinstance(models, str) else list(models)
    names = [v for v in names if v]
    bad = [v for v in names if v not in MODELS]
    if bad or not names:
        raise InputError(f"{arg('models')} must be names among {','.join(MODELS)} (or all), got "
                         f"{','.join(map(str, names))!r}")
    return {"choice", *names}, True


def available_bytes():
    """Memory this process may still allocate: physical memory and RLIMIT_AS, less what it holds.

    Returns
    -------
    float
        ``min(0.8 x physical memory - resident set, RLIMIT_AS - address space)``
        in bytes (the resident set and address space read from
        /proc/self/status; inf where nothing is known).
    """
    import resource

    held, vm = _status_bytes()
    out = float("inf")
    try:
        out = 0.8 * os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE") - held
    except (ValueError, OSError):
        pass
    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    if soft != resource.RLIM_INFINITY:
        out = min(out, soft - vm)
    return out


def _status_bytes():
    """(VmRSS, VmSize) of this process in bytes (0 where /proc is not there)."""
    rss = vm = 0
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    rss = int(line.split()[1]) * 1024
                elif line.startswith("VmSize:"):
                    vm = int(line.split()[1]) * 1024
    except OSError:
        pass
    return rss, vm


def estimate(n_stimuli, n, n_clicks, n_participants, grid, permutations, n_predictors=1):
    """Peak bytes of each stage of an analysis, from the sizes of its design.

    Parameters
    ----------
    n_stimuli, n, n_clicks, n_participants, grid, permutations, n_predictors : int

    Returns
    -------
    dict of str -> float
        ``predictions`` (every predictor's values, z and geometry at the n
        points of each stimulus, held for the whole run), ``clicks`` (the
        click table and its mapping), ``correlations`` (density, prediction
        and ranks on the grid, the shifts' null), ``choice``, ``mixed``
        (cells, the dense system of the smaller set of units and its chunks,
        the tabulated cumulants) and ``group`` (the Monte Carlo chunks).

    Examples
    --------
    >>> e = estimate(100, 100, 100_000, 100, 1024, 1000)
    >>> 1e6 < sum(e.values()) < 2e9
    True
    """
    S, G, U = int(n_stimuli), max(int(n_participants), 1), int(n_clicks)
    f8 = 8.0
    small = min(G, S) + 1
    cells = min(U, G * S)
    return dict(
        predictions=S * n * f8 * 40,
        clicks=U * 600.0,
        correlations=S * (grid * 8 + (permutations + 1)) * f8,
        choice=S * n * f8 * (4 + 3 * n_predictors) + 4 * (1 << 20) * f8 + cells * 10 * f8,
        # cells; the dense system and its chunks; C's rows kept by two states (up to 64 MB each); the
        # cumulant table over 8 units of slope (4 units, and their copy when the table grows)
        mixed=cells * 16 * f8 + small * small * f8 * 4 + 4096 * small * f8 * 4
        + 2 * min(max(G, S) * small, 1 << 23) * f8 + S * 8 * 101 * 4 * f8,
        group=(1 << 22) * f8 * 4 * 2 + U * 4 * f8,  # two chunks in flight (threads.MAX_THREADS)
    )


def plan(models, named, sizes, flags=None, available=None):
    """The models that run, and those left out with the reason; refuses a run that does not fit.

    Parameters
    ----------
    models : set of str
        From :func:`choose_models`.
    named : bool
        Whether they were named (a named model that does not fit is
        refused; a default one is left out).
    sizes : dict
        Keyword arguments of :func:`estimate`.
    flags : dict, optional
        The option that sets each size, for the message (default the
        command's: ``-n``, ``--grid``, ``--models``).
    available : float, optional
        Bytes available (default :func:`available_bytes`).

    Returns
    -------
    run : set of str
    skipped : dict of str -> str
        Each model left out and why.

    Raises
    ------
    InputError
        When the stages that always run (or a model named in `models`) need
        more memory than is available: one line with both figures and the
        option to change.
    """
    flags = flags or {}
    avail = available_bytes() if available is None else available
    e = estimate(**sizes)
    skipped = {k: f"not asked for ({flags.get('models', arg('models'))})" for k in OPTIONAL if k not in models}
    run = set(models)
    core = e["predictions"] + e["clicks"] + e["correlations"] + e["choice"] + e["group"]
    gb = 2.0**30
    if core > avail:
        big = max(("predictions", "correlations", "clicks"), key=lambda k: e[k])
        fix = {"predictions": f"lower {flags.get('n', arg('n'))} (points per contour, now {sizes['n']:,})",
               "correlations": f"lower {flags.get('grid', arg('grid'))} (now {sizes['grid']:,}) or "
                               f"{flags.get('permutations', arg('permutations'))}",
               "clicks": "analyse fewer clicks at a time"}[big]
        raise InputError(f"this analysis would need about {core / gb:.1f} GB ({big} {e[big] / gb:.1f} GB) but "
                         f"only {max(avail, 0) / gb:.1f} GB of memory is available: {fix}")
    if "mixed" in run and core + e["mixed"] > avail:
        why = (f"needs about {e['mixed'] / gb:.1f} GB beyond the {core / gb:.1f} GB of the rest, more than the "
               f"{max(avail, 0) / gb:.1f} GB available")
        if named:
            raise InputError(f"the mixed model {why}: leave mixed out of {flags.get('models', arg('models'))}")
        run.discard("mixed")
        skipped["mixed"] = f"left out: it {why}"
    return run, skipped
