"""The outputs of an analysis (:func:`analysis.analyze.analyze`).

:func:`write_analysis` writes an :class:`~analysis.analyze.Analysis`:

``clicks.csv``
    Every input row, in input order, with its line in the file, the input
    columns as written, the mapping, ``peak_hit``, ``excluded`` and
    ``reason``.
``per_stimulus.csv``, ``per_participant.csv``
    One row per stimulus of the set / per participant in the file
    (including those without a usable click).
``models.csv``
    The choice model fitted with each predictor that differs from the
    others (surprisal and its rivals, :mod:`analysis.predictors`): beta,
    log-likelihood, AIC.
``points.csv``, ``choices.csv``, ``analysis.R``
    The choice data in long format and an R script fitting the same models
    (:mod:`analysis.choice_table`).
``summary.json``
    Counts (``n_clicks, n_used, n_excluded, exclusions`` by reason),
    ``beta_hat`` with its Wald and profile intervals, the group test, the
    model comparison, the correlation, peak, AUC and concavity results, and
    every resolved parameter.
``figures/*.png`` and ``report.html``
    The figures of :mod:`analysis.plots` and one self-contained page (images
    embedded as base64) showing them with the main tables.

Writing is all-or-nothing: everything is written into a fresh hidden
temporary directory beside the output directory, which is renamed into place
when complete (a rename within one file system is atomic). An interrupted or
failed run leaves at most that hidden directory, which is removed on any
error it can catch, and never a half-written output directory.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path

from stimuli.errors import InputError

__all__ = ["check_output_dir", "write_analysis"]


def check_output_dir(out, force=False):
    """Raise `InputError` if `out` exists (unless `force`), is not a directory, or cannot be created."""
    out = Path(out)
    if out.exists():
        if not out.is_dir():
            raise InputError(f"{out}: exists and is not a directory")
        if any(out.iterdir()) and not force:
            raise InputError(f"{out}: directory exists and is not empty; choose another -o or pass --force")
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
        Recorded in ``summary.json`` (e.g. the input paths as given).

    Returns
    -------
    Path
        `out`.
    """
    from stimuli import __version__
    from stimuli.io import atomic_write, write_table

    out = Path(out)
    check_output_dir(out, force)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".tmp", dir=out.parent))
    except OSError as exc:
        raise InputError(f"{out}: cannot be created ({exc.strerror or exc})") from None
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
            summary["inputs"] = {k: str(v) for k, v in inputs.items()}
        images = []
        if figures:
            from . import plots

            (tmp / "figures").mkdir()
            for name, png in plots.all_figures(analysis):
                with atomic_write(tmp / "figures" / name, "wb") as fh:
                    fh.write(png)
                images.append((name, png))
        summary["figures"] = [f"figures/{name}" for name, _ in images]
        with atomic_write(tmp / "summary.json", "w") as fh:
            json.dump(summary, fh, indent=2, sort_keys=True, allow_nan=False)
            fh.write("\n")
        with atomic_write(tmp / "report.html", "w") as fh:
            fh.write(_html(analysis, summary, images))
        os.chmod(tmp, 0o755)
        _swap_into_place(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return out


def _write_r_export(analysis, tmp, version):
    """points.csv, choices.csv (when small enough) and analysis.R; returns what was written."""
    from stimuli.io import atomic_write, write_table

    from .choice_table import MAX_CHOICE_ROWS, choices_table, points_table, r_script

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


def _swap_into_place(tmp, out):
    if out.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".old", dir=out.parent))
        os.rmdir(old)
        os.replace(out, old)
        try:
            os.replace(tmp, out)
        except BaseException:
            os.replace(old, out)
            raise
        shutil.rmtree(old, ignore_errors=True)
    else:
        os.replace(tmp, out)


def _fmt(v, digits=4):
    if v is None:
        return "n/a"
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return str(v)


def _html(analysis, summary, images):
    import base64
    import html

    s = summary
    g = s["group"]
    esc = html.escape
    rows = [
        ("clicks", s["n_clicks"]), ("used", s["n_used"]), ("excluded", s["n_excluded"]),
        ("participants (with a used click)", f"{s['n_participants']} ({s['n_participants_used']})"),
        ("stimuli (clicked)", f"{s['n_stimuli']} ({s['n_stimuli_clicked']})"),
        ("beta_hat (pooled ML)", f"{_fmt(s['beta_hat'])}, {s['beta_ci_method']} CI "
                                 f"[{_fmt(s['beta_ci'][0])}, {_fmt(s['beta_ci'][1])}], profile CI "
                                 f"[{_fmt(s['beta_profile_ci'][0])}, {_fmt(s['beta_profile_ci'][1])}]"),
        ("group test", f"{g['test']}: t = {_fmt(g['statistic'])} ({g['n']} participants), "
                       f"p = {_fmt(g['p_value'])} (one-sided, greater; t distribution with {g['df']} df "
                       f"would give {_fmt(g['p_value_parametric'])}), d_z = {_fmt(g['effect_size'])}, "
                       f"mean = {_fmt(g['mean'])}"),
        ("items test", f"per-stimulus mean z: t = {_fmt(s['by_stimulus']['statistic'])} "
                       f"({s['by_stimulus']['n']} stimuli), Monte Carlo p = {_fmt(s['by_stimulus']['p_value'])} "
                       f"(one-sided)"),
        ("Spearman (density vs surprisal)", f"mean rho = {_fmt(s['spearman']['mean_rho'])}, circular-shift p = "
                                            f"{_fmt(s['spearman']['p_value'])}; {s['spearman']['n_significant']} of "
                                            f"{s['spearman']['n_stimuli']} stimuli p < 0.05"),
        ("peak hit rate vs chance", f"{_fmt(s['peaks']['hit_rate'])} vs {_fmt(s['peaks']['chance'])}"),
        ("AUC (surprisal at clicks vs all points)", _fmt(s["auc"]["value"])),
        ("concave share: clicks vs length", f"{_fmt(s['concave']['click_share'])} vs "
                                            f"{_fmt(s['concave']['length_share'])}"),
    ]
    table = "\n".join(f"<tr><th>{esc(k)}</th><td>{esc(str(v))}</td></tr>" for k, v in rows)
    excl = "\n".join(f"<tr><th>{esc(k)}</th><td>{v}</td></tr>" for k, v in s["exclusions"].items())
    models = analysis.models.to_html(index=False, float_format=lambda x: f"{x:.6g}", border=0)
    per_s = analysis.per_stimulus.head(500).to_html(index=False, float_format=lambda x: f"{x:.4g}", border=0)
    per_p = analysis.per_participant.head(500).to_html(index=False, float_format=lambda x: f"{x:.4g}", border=0)
    figs = "\n".join(
        f'<figure><img alt="{esc(name)}" src="data:image/png;base64,{base64.b64encode(png).decode("ascii")}">'
        f"<figcaption>{esc(name)}</figcaption></figure>"
        for name, png in images
    )
    warn = "".join(f"<p class=warn>{esc(w)}</p>" for w in s.get("warnings", []))
    params = esc(json.dumps(s["params"], indent=1, sort_keys=True))
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>attneave analysis</title>
<style>
body {{ font-family: sans-serif; margin: 2em; max-width: 1400px; }}
table {{ border-collapse: collapse; margin-bottom: 1.5em; font-size: 90%; }}
th, td {{ border-bottom: 1px solid #ddd; padding: 3px 8px; text-align: left; }}
img {{ max-width: 100%; }} .warn {{ color: #a00; }} pre {{ background: #f6f6f6; padding: 1em; }}
</style></head><body>
<h1>Clicks against predicted information</h1>
{warn}
<h2>Summary</h2><table>{table}</table>
<h2>Exclusions (rows kept in clicks.csv with their reason)</h2><table>{excl}</table>
<h2>Models</h2>{models}
<h2>Figures</h2>{figs or '<p>(figures not drawn)</p>'}
<h2>Per stimulus</h2>{per_s}
<h2>Per participant</h2>{per_p}
<h2>Parameters</h2><pre>{params}</pre>
</body></html>
"""
