"""The outputs of an analysis (:func:`attneave.analysis.analyze.analyze`).

:func:`write_analysis` writes an :class:`~attneave.analysis.analyze.Analysis`:

``clicks.csv``
    Every input row, in input order, with its line in the file, the input
    columns as written, the mapping, ``peak_hit``, ``excluded`` and
    ``reason``.
``per_stimulus.csv``, ``per_participant.csv``
    One row per stimulus of the set / per participant in the file
    (including those without a usable click).
``models.csv``
    The choice model fitted with each predictor that differs from the
    others (surprisal and its rivals, :mod:`attneave.analysis.models.predictors`): beta,
    log-likelihood, AIC.
``points.csv``, ``choices.csv``, ``analysis.R``
    The choice data in long format and an R script fitting the same models
    (:mod:`attneave.analysis.report.choice_table`).
``summary.json``
    Counts (``n_clicks, n_used, n_excluded, exclusions`` by reason),
    ``beta_hat`` with its Wald and profile intervals, the group test, the
    model comparison, the correlation, peak, AUC and concavity results, and
    every resolved parameter.
``figures/*.png``, ``figures/*.svg`` and ``report.html``
    The figures of :mod:`attneave.analysis.report.plots` (each as PNG and SVG) and one
    self-contained page written as a methods-and-results section
    (:mod:`attneave.analysis.report.html`; images embedded as base64).

Writing is all-or-nothing: everything is written into a fresh hidden
temporary directory beside the output directory, which is renamed into place
when complete (a rename within one file system is atomic). An interrupted or
failed run leaves at most that hidden directory, which is removed on any
error it can catch, and never a half-written output directory.
"""

from __future__ import annotations

import datetime
import json
import os
import shutil
from pathlib import Path

from attneave.stimuli.errors import InputError
from attneave.stimuli.io import replace_directory, temporary_directory

__all__ = ["ANALYSIS_FILES", "check_output_dir", "foreign_entries", "write_analysis"]


#: What ``write_analysis`` puts in the output directory: ``--force`` replaces a directory only when
#: it holds ``summary.json`` and nothing else than these (and figures/ only PNG and SVG files), so
#: that a user's own files are never deleted with an earlier output.
ANALYSIS_FILES = frozenset({"clicks.csv", "per_stimulus.csv", "per_participant.csv", "models.csv", "points.csv",
                            "choices.csv", "analysis.R", "summary.json", "report.html", "figures"})


def foreign_entries(out):
    """The entries of directory `out` that an analysis does not write (sorted names; '' -> none).

    ``figures/`` counts as an analysis's when it holds only ``.png`` and ``.svg`` files.
    A directory without ``summary.json`` is not an earlier analysis output at all:
    then every entry is foreign.
    """
    from attneave.stimuli.io import is_temporary

    out = Path(out)
    names = sorted(p.name for p in out.iterdir())
    if "summary.json" not in names:
        return names
    bad = [n for n in names if n not in ANALYSIS_FILES and not is_temporary(n)]
    fig = out / "figures"
    if "figures" in names:
        if fig.is_symlink() or not fig.is_dir():
            bad.append("figures")
        else:
            bad += [f"figures/{p.name}" for p in sorted(fig.iterdir())
                    if p.suffix.lower() not in (".png", ".svg") or not p.is_file() or p.is_symlink()]
    return sorted(bad)


def check_output_dir(out, force=False, inputs=()):
    """Raise `InputError` if `out` may not be written (before any work is done).

    Refused: an `out` that is one of `inputs` or holds one (``--force``
    would delete it), the working directory or one of its parents, a path
    that exists and is not a directory, a non-empty directory without
    `force`, and, even with `force`, a non-empty directory that is not an
    earlier analysis output (one holding files :func:`write_analysis` does
    not write: they would be deleted with it), or a directory that cannot
    be created.
    """
    from attneave.stimuli.io import check_output_spares_inputs

    check_output_spares_inputs(out, list(inputs), what="-o")
    out = Path(out)
    if out.exists() or out.is_symlink():
        if not out.is_dir():
            raise InputError(f"-o {out}: exists and is not a directory")
        if any(out.iterdir()):
            if not force:
                raise InputError(f"-o {out}: directory exists and is not empty; choose another -o or pass --force")
            bad = foreign_entries(out)
            if bad:
                shown = ", ".join(bad[:3]) + (f" and {len(bad) - 3} more" if len(bad) > 3 else "")
                raise InputError(f"-o {out}: --force replaces only an earlier analysis output, and this directory "
                                 f"holds files analyze does not write ({shown}); move them or choose another -o")
    # found before the analysis runs, not after it
    anc = out.parent
    while not anc.exists() and anc != anc.parent:
        anc = anc.parent
    if anc.exists() and not anc.is_dir():
        raise InputError(f"{out}: cannot be created, {anc} is not a directory")
    if anc.is_dir() and not os.access(anc, os.W_OK | os.X_OK):
        raise InputError(f"{out}: cannot be created, no permission to write in {anc}")


def write_analysis(analysis, out, figures=True, force=False, inputs=None):
    """Write the outputs of an analysis into directory `out`, all or nothing.

    Parameters
    ----------
    analysis : Analysis
    out : str or Path
        Output directory; created (with its parents). If it exists and is not
        empty it is replaced only with ``force=True``.
    figures : bool
        Draw the figures (the slowest part); without them ``report.html``
        still holds the tables.
    inputs : dict, optional
        Recorded in ``summary.json`` (e.g. the input paths as given); `out`
        may not be or hold one of them.

    Returns
    -------
    Path
        `out`.
    """
    from attneave.stimuli import __version__
    from attneave.stimuli.io import atomic_write
    from attneave.stimuli.tables import write_table

    out = Path(out)
    check_output_dir(out, force, [p for v in (inputs or {}).values() for p in (v if isinstance(v, list) else [v])])
    tmp = temporary_directory(out)
    try:
        write_table(analysis.clicks, tmp / "clicks.csv")
        write_table(analysis.per_stimulus, tmp / "per_stimulus.csv")
        write_table(analysis.per_participant, tmp / "per_participant.csv")
        write_table(analysis.models, tmp / "models.csv")
        summary = dict(analysis.summary)
        summary["version"] = __version__
        summary["r_export"] = _write_r_export(analysis, tmp, __version__)
        if not summary["r_export"]["choices_csv"]:
            summary["warnings"] = summary.get("warnings", []) + [summary["r_export"]["note"]]
        if inputs:
            summary["inputs"] = {k: [str(p) for p in v] if isinstance(v, list) else str(v) for k, v in inputs.items()}
        images = []
        if figures:
            from attneave.analysis.report import plots

            (tmp / "figures").mkdir()
            for stem, caption, png, svg in plots.all_figures(analysis):
                for ext, data in (("png", png), ("svg", svg)):
                    with atomic_write(tmp / "figures" / f"{stem}.{ext}", "wb") as fh:
                        fh.write(data)
                images.append((stem, caption, png, f"{stem}.svg"))
        summary["figures"] = [f"figures/{stem}.{ext}" for stem, *_ in images for ext in ("png", "svg")]
        with atomic_write(tmp / "summary.json", "w") as fh:
            json.dump(summary, fh, indent=2, sort_keys=True, allow_nan=False)
            fh.write("\n")
        from attneave.analysis.report.html import render

        # the date goes into the page only, so that reruns give the same summary.json
        page = dict(summary, date=datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"))
        with atomic_write(tmp / "report.html", "w") as fh:
            fh.write(render(analysis, page, images))
        os.chmod(tmp, 0o755)
        replace_directory(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return out


def _write_r_export(analysis, tmp, version):
    """points.csv, choices.csv (when small enough) and analysis.R; returns what was written."""
    from attneave.analysis.report.choice_table import MAX_CHOICE_ROWS, choices_table, points_table, r_script
    from attneave.stimuli.io import atomic_write
    from attneave.stimuli.tables import write_table

    names = list(analysis.summary.get("predictors") or ["surprisal"])
    names = names if "surprisal" in names else ["surprisal"] + names
    write_table(points_table(analysis, names), tmp / "points.csv")
    choices = choices_table(analysis, names)
    if choices is not None:
        write_table(choices, tmp / "choices.csv")
    with atomic_write(tmp / "analysis.R", "w") as fh:
        fh.write(r_script(names, version, choices is not None))
    note = ("choices.csv holds one row per used click and contour point" if choices is not None else
            f"choices.csv not written: it would exceed {MAX_CHOICE_ROWS:,} rows (used clicks x points); "
            "analysis.R builds it from clicks.csv and points.csv")
    return dict(choices_csv=choices is not None, points_csv=True, r_script="analysis.R", predictors=names, note=note)
